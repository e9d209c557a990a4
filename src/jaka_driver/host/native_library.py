"""Where the project's compiled libraries are: the IK fast path (``libjaka_ik.so``,
kinematics/native.py) and the twin's cycle (``libjaka_drives.so``, sim/native_drives.py).

``make setup`` compiles them to ``devel/lib`` of the source tree, a catkin build to the
workspace's ``devel/lib`` and ``install/lib``. Each is optional: without it the Python path
does the same work, only slower.
"""
from __future__ import annotations

import logging
import os
from pathlib import Path
from typing import Callable, Optional, TypeVar

log = logging.getLogger(__name__)
T = TypeVar("T")


def path(name: str, variable: str) -> Path:
    """``$variable`` when set, else ``devel/lib/<name>`` of the source tree (``make setup``),
    else the ``lib`` folder of the first catkin devel or install space on
    ``CMAKE_PREFIX_PATH`` that has it; a path that does not exist when none has."""
    explicit = os.environ.get(variable)
    if explicit:
        return Path(explicit)
    from ..common.models import repo_root
    made = repo_root() / "devel" / "lib" / name
    if made.is_file():
        return made
    for prefix in filter(None, os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep)):
        built = Path(prefix) / "lib" / name
        if built.is_file():
            return built
    return made


def opened(path: Path, load: Callable[[Path], Optional[T]], what: str, fallback: str
           ) -> Optional[T]:
    """``load(path)`` (the library opened and checked, or None), and a log line saying where
    ``what`` came from (source tree, devel or install space), or that ``fallback`` does its
    work: whoever loads a library says so."""
    lib = load(path)
    if lib is None:
        log.info("%s %s not found, or built from other sources: %s", what, path, fallback)
    else:
        log.info("%s %s", what, path)
    return lib

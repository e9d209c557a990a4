"""Every Python file of the project compiles without a warning (an invalid escape sequence, a
``is`` with a literal...): pytest.ini ignores "invalid escape sequence" for the ROS packages
Debian ships, so this test holds our own files to it. Static: each file is compiled, nothing
imported."""
import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = [p for p in (ROOT / "scripts").iterdir() if p.is_file()
           and p.read_text(errors="replace").startswith("#!/usr/bin/env python3")]
TEST_NODES = [p for p in (ROOT / "test" / "rostest_nodes").iterdir() if p.is_file()]
SOURCES = sorted([*ROOT.glob("src/**/*.py"), *ROOT.glob("test/**/*.py"),
                  *ROOT.glob("bench/**/*.py"), *SCRIPTS, *TEST_NODES])


def test_there_are_sources_to_compile():
    assert len(SOURCES) > 300


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_compiles_without_a_warning(path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        compile(path.read_text(encoding="utf-8"), str(path), "exec")

"""The protocol library depends on nothing else in jaka_driver: a copy of src/jaka_driver/protocol
alone, as a top-level package with the rest of the driver unavailable, imports every module."""
import shutil
import subprocess
import sys
from pathlib import Path

import jaka_driver.protocol

PROTOCOL_DIR = Path(jaka_driver.protocol.__file__).parent


def test_every_protocol_module_imports_without_the_rest_of_the_package(tmp_path):
    copy = tmp_path / "jaka_protocol"
    shutil.copytree(PROTOCOL_DIR, copy, ignore=shutil.ignore_patterns("__pycache__"))
    modules = sorted(p.stem for p in copy.glob("*.py") if p.stem != "__init__")
    assert len(modules) >= 7   # units, fields, wire, errors, replies, commands, status, client
    script = (
        "import sys\n"
        # the driver must not be importable at all: a hidden dependency then fails loudly
        "sys.modules['jaka_driver'] = None\n"
        f"sys.path.insert(0, {str(tmp_path)!r})\n"
        "import importlib\n"
        f"for name in {modules!r}:\n"
        "    importlib.import_module('jaka_protocol.' + name)\n"
        "import jaka_protocol\n"
        "print(sorted(m for m in sys.modules if m.startswith('jaka')))\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=60, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "jaka_driver" not in done.stdout.replace("'jaka_driver'", "")

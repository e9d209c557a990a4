"""Make a script of this package run the same way from rosrun, roslaunch or a shell.

Re-executes under the project's venv (MuJoCo and Pinocchio live there) when started by another
interpreter, and puts ``src/`` and the generated messages on ``sys.path``, so a script works
even when ``devel/setup.bash`` was not sourced.
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
_venv_python = os.path.join(ROOT, ".venv", "bin", "python")
if (os.path.exists(_venv_python)
        and os.path.realpath(sys.prefix) != os.path.realpath(os.path.join(ROOT, ".venv"))
        and not os.environ.get("JAKA_DRIVER_NO_REEXEC")):
    os.environ["JAKA_DRIVER_NO_REEXEC"] = "1"
    os.execv(_venv_python, [_venv_python] + sys.argv)
for _path in (os.path.join(ROOT, "devel", "lib", "python3", "dist-packages"),
              os.path.join(ROOT, "src")):
    if _path not in sys.path:
        sys.path.insert(0, _path)

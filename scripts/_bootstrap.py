"""Make a script of this package run the same way from rosrun, roslaunch or a shell.

Re-executes under the project's venv (MuJoCo and Pinocchio live there) when started by another
interpreter, and puts ``src/`` and the generated messages on ``sys.path``, so a script works
even when ``devel/setup.bash`` was not sourced.

The venv is ``.venv`` beside the sources (``make setup``, or ``scripts/setup.sh --deps`` run by
a catkin build); an installed copy (``catkin_make install``) finds its path in the file
``jaka_driver_venv`` that the install put beside this one.
"""
import os
import sys

HERE = os.path.dirname(os.path.realpath(__file__))
ROOT = os.path.dirname(HERE)


def _venv() -> str:
    recorded = os.path.join(HERE, "jaka_driver_venv")
    if os.path.isfile(recorded):
        with open(recorded) as f:
            return f.read().strip()
    return os.path.join(ROOT, ".venv")


_venv_dir = _venv()
_venv_python = os.path.join(_venv_dir, "bin", "python")
if (os.path.exists(_venv_python)
        and os.path.realpath(sys.prefix) != os.path.realpath(_venv_dir)
        and not os.environ.get("JAKA_DRIVER_NO_REEXEC")):
    os.environ["JAKA_DRIVER_NO_REEXEC"] = "1"
    os.execv(_venv_python, [_venv_python] + sys.argv)
for _path in (os.path.join(ROOT, "devel", "lib", "python3", "dist-packages"),
              os.path.join(ROOT, "src")):
    if os.path.isdir(_path) and _path not in sys.path:
        sys.path.insert(0, _path)

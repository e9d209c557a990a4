# Used by catkin_python_setup() for catkin workspaces only; `make setup` needs none of it.
from setuptools import setup

setup(name="jaka_driver", version="0.1.0", packages=["jaka_driver", "jaka_driver.motion",
      "jaka_driver.sim", "jaka_driver.kinematics", "jaka_driver.ros", "jaka_driver.protocol",
      "jaka_driver.controller", "jaka_driver.emulator"],
      package_dir={"": "src"})

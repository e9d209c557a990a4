# Used by catkin_python_setup() for catkin workspaces only; `make setup` needs none of it.
from setuptools import find_packages, setup

setup(name="jaka_driver", version="0.1.0", packages=find_packages("src"),
      package_dir={"": "src"})

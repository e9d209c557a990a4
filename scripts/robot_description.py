#!/usr/bin/env python3
"""The arm's URDF with a tool on the flange, for the launch file's ``robot_description``:
`scripts/robot_description.py zu5 dh_pgi` (tools: none, dh_pgi, suction)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import _bootstrap  # noqa: E402,F401  (venv + sys.path)

from jaka_driver.common.tool_urdf import main  # noqa: E402

sys.exit(main())

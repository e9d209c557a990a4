#!/usr/bin/env python3
"""Write ``flange_poses.json``: flange poses of every JAKA arm at fixed joint vectors, computed
straight from JAKA's own joint chains, independently of the driver.

The chains below are JAKA's URDFs as written (JAKARobotics/jaka_ros2 @ c83b594,
``src/jaka_description/urdf/jaka_<model>.urdf``): for each joint its origin xyz (m) and rpy
(rad) in the parent link, its axis and, for the revolute ones, its position limits (rad) —
transcribed from a table of those files, not from the driver's generator. Nothing of the
driver is imported: the transforms are composed here with plain numpy, URDF's way (origin =
translation · Rz(yaw)·Ry(pitch)·Rx(roll), then a turn about the joint's axis).

Where the driver does not take JAKA's file as written (docs/models.md), this script applies
the same decision from its own description, so the comparison still tests the rest:
  * c12, pro12: the pose is taken from JAKA's base link (the mounting face), not from its
    `world` 40 mm below it (the file's `fixed` joint is skipped);
  * a20: JAKA's file is broken; the a20 is evaluated on the zu20 rows.
The flange is the last link of each file (MiniCobo: dummy_tcp, identical to Link_6).

Joint vectors: q = 0, JAKA's pose_1, and ``N_RANDOM`` vectors uniform inside the limits
(seeded, so the file is reproducible). Output per model: a list of {"q": rad, "position_m",
"rotation": 3x3 row-major}.

Usage: ``python3 make_flange_poses.py`` (writes flange_poses.json beside this file).
"""
import json
from pathlib import Path

import numpy as np

N_RANDOM = 10
SEED = 2025
POSE_1 = (0.0, np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2, 0.0)
POSE_1_MINICOBO = (0.0, 0.0, np.pi / 2, 0.0, np.pi / 2, 0.0)
FROM_BASE_LINK = {"c12", "pro12"}
SAME_CHAIN = {"a20": "zu20"}

# model, then per joint: name | xyz | rpy | axis | lower | upper ("(none)": element absent)
CHAINS = """
zu3
  fixed           | -0.002 0 -0.00001                 | 0 0 0                   |                                   |       | 
  joint_1         | 0 0 0.15055                       | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.248 0 0                         | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.228 1.1925E-05 -0.115           | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.1175 0                       | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 0.1065 0                        | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
zu5
  fixed           | 0 0 0                             | 0 0 0                   |                                   |       | 
  joint_1         | 0 0 0.12015                       | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.43 0 0                          | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.3685 -1.185E-05 -0.114          | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.1135 0                       | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 0.107 0                         | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
zu7
  fixed           | 0 0 0                             | 0 0 0                   |                                   |       | 
  joint_1         | 0 0 0.12015                       | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.36 0 0                          | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.30353 0 -0.11501                | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.1135 0                       | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 0.107 0                         | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
zu12
  fixed           | 0 0 0.04                          | 0 0 0                   |                                   |       | 
  joint_1         | 0 0 0.10265                       | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.595 0 0                         | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.5715 0 -0.1315                  | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.115 0                        | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 0.1035 0                        | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
zu18
  fixed           | 0 0 0                             | 0 0 0                   |                                   |       | 
  joint_1         | 0 0 0.14265                       | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.51 0 0                          | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.4 0 -0.154                      | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.115 0                        | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 0.1035 0                        | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
zu20
  fixed           | 0.005 0 0                         | 0 0 0                   |                                   |       | 
  joint_1         | 0.0044104 -0.00027834 0.1965      | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.897 0 0                         | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.7445 0 -0.18835                 | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.1385 0                       | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | -0.00025841 0.1205 0.00025841     | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
zu30
  fixed           | 0.005 0 0                         | 0 0 0                   |                                   |       | 
  joint_1         | 0.0044104 -0.00027834 0.1965      | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.6625 0 0                        | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.549 0 -0.18835                  | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.1385 0                       | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0.00039033 0.1205 0               | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
c5
  fixed           | 0 0 0                             | 0 0 0                   |                                   |       | 
  joint_1         | 0 -0.00022535 0.12015             | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.43 0 0                          | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.3685 -1.185E-05 -0.114          | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.1135 0                       | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 0.107 0                         | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
c7
  fixed           | 0 0 0                             | 0 0 0                   |                                   |       | 
  joint_1         | 0 -0.00022535 0.12015             | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.36 0 0                          | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.3035 0 -0.11501                 | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.1135 0                       | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 0.107 0                         | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
c12
  fixed           | 0 0 0.04                          | 0 0 0                   |                                   |       | 
  joint_1         | 0 -0.0002479 0.14265              | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.595 0 0                         | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.5715 0 -0.1315                  | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.115 0                        | 1.5708 0 -3.1416        | 0 0 -1                            | -6.28 | 6.28
  joint_6         | -0.00025841 0.1035 -0.00025841    | 1.5708 0 3.1416         | 0 0 1                             | -6.28 | 6.28
pro5
  fixed           | 0 0 0                             | 0 0 0                   |                                   |       | 
  joint_1         | 0 0 0.12015                       | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.43 0 0                          | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.3685 -1.185E-05 -0.114          | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.1135 0                       | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 0.107 0                         | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
pro7
  fixed           | (none)                            | (none)                  |                                   |       | 
  joint_1         | 0 0 0.12015                       | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.36 0 0                          | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.3035 0 -0.11502                 | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.1135 0                       | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 0.107 0                         | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
pro12
  fixed           | 0 0 0.04                          | 0 0 0                   |                                   |       | 
  joint_1         | 0 -0.00018758 0.14265             | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.595 0 0                         | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.5715 0 -0.1315                  | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.115 0                        | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0.00025836 0.1035 0.00025795      | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
pro16
  fixed           | (none)                            | (none)                  |                                   |       | 
  joint_1         | 0 0 0.1965                        | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.819 0 0                         | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.687 0 -0.15801                  | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.14415 0                      | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 0.12665 0                       | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
pro18
  fixed           | 0 0 0                             | 0 0 0                   |                                   |       | 
  joint_1         | 0 0 0.14265                       | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.51 0 0                          | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.4 0 -0.154                      | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.115 0                        | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0.00025836 0.1035 0.00025795      | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
s5
  fixed           | (none)                            | (none)                  |                                   |       | 
  joint_1         | 0 -0.00022535 0.12015             | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.43 0 0                          | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.3685 0 -0.114                   | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.1135 0                       | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0.00026137 0.1175 0.00025782      | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
s7
  fixed           | 0 0.0002282 0                     | 0 0 0                   |                                   |       | 
  joint_1         | 0 -0.00022535 0.12015             | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 1.5708 0         | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0 0.36 0                          | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0 0.3035 -0.11501                 | 0 0 -1.5708             | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 0.1135 0                        | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 -0.1175 0                       | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
s12
  fixed           | (none)                            | (none)                  |                                   |       | 
  joint_1         | 0 -0.00018758 0.14265             | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.62
  joint_3         | 0.595 0 0                         | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.5715 0 -0.1315                  | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.115 0                        | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0.00025822 0.112 0.00025865       | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
a5
  fixed           | (none)                            | (none)                  |                                   |       | 
  joint_1         | 0 -0.00022535 0.12015             | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -1.48 | 4.628
  joint_3         | 0.43 0 0                          | 0 0 0                   | 0 0 1                             | -3.05 | 3.05
  joint_4         | 0.3685 0 -0.115                   | 0 0 0                   | 0 0 1                             | -1.48 | 4.62
  joint_5         | 0 -0.1135 0                       | 1.5708 -0.00010901 0    | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 0.107 0                         | -1.5708 0 -0.00010901   | -0.00010901 0 1                   | -6.28 | 6.28
a12
  fixed           | (none)                            | (none)                  |                                   |       | 
  joint_1         | 9.3823E-05 0 0.14265              | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
  joint_3         | 0.77 0 0.0375                     | 0 0 1.5708              | 0 0 1                             | -6.28 | 6.28
  joint_4         | 0 -0.5515 0                       | -1.5708 0 -3.1416       | 0 0 1                             | -6.28 | 6.28
  joint_5         | 0 -0.115 0                        | -1.5708 -1.5708 3.1416  | 0 0 1                             | -6.28 | 6.28
  joint_6         | 0 -0.1035 0                       | 1.5708 0 0              | 0 0 1                             | -6.28 | 6.28
a20
  fixed           | 0.005 0 0                         | 0 0 0                   |                                   |       | 
  joint_1         | 0.0044104 -0.00027834 0.1965      | 0 0 0                   | 0 0 -1                            | -6.28 | 6.28
  joint_2         | 0 0 0                             | 1.5708 0 0              | -0.045307 0 0.99897               | -1.48 | 4.62
  joint_3         | 0.89688 0.043276 0                | 0 0 0                   | -0.045307 0 0.99897               | -3.05 | 3.05
  joint_4         | 0.74837 -0.055302 -0.11393        | 0 0 0                   | -0.045307 0 0.99897               | -1.48 | 4.62
  joint_5         | 0.0015718 -0.13849 7.1288E-05     | 1.5708 0 0              | 0.011349 0.00051471 0.99994       | -6.28 | 6.28
  joint_6         | 0.0081481 0.12022 0.00014266      | -1.5708 0 0             | 0.065828 0.0012607 0.99783        | -6.28 | 6.28
minicobo
  fixed           | (none)                            | (none)                  |                                   |       | 
  joint_1         | 0 0 0.187                         | 0 0 0                   | 0 0 1                             | -6.28 | 6.28
  joint_2         | 0 -0.006 0                        | 1.5708 -1.5708 0        | 0 0 1                             | -2.09 | 2.09
  joint_3         | 0.21 0 0                          | 0 0 -1.5708             | 0 0 1                             | -2.27 | 2.27
  joint_4         | 0 0.2105 0                        | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
  joint_5         | 0 0 0                             | 1.5708 0 0              | 0 0 1                             | -2.09 | 2.09
  joint_6         | 0 0.1593 0                        | -1.5708 0 0             | 0 0 1                             | -6.28 | 6.28
  dummy_tcp_joint | 0 0 0                             | 0 0 0                   |                                   |       | 
"""


def parse(text: str) -> dict:
    chains, name = {}, None
    for line in text.strip().splitlines():
        if not line.startswith(" "):
            name = line.strip()
            chains[name] = []
            continue
        joint, xyz, rpy, axis, lower, upper = (c.strip() for c in line.split("|"))
        chains[name].append({
            "joint": joint,
            "xyz": [0.0, 0.0, 0.0] if xyz in ("", "(none)") else [float(v) for v in xyz.split()],
            "rpy": [0.0, 0.0, 0.0] if rpy in ("", "(none)") else [float(v) for v in rpy.split()],
            "axis": [float(v) for v in axis.split()] if axis else None,
            "limits": (float(lower), float(upper)) if lower else None})
    return chains


def rot_x(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rot_z(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def about(axis, angle):
    """Rotation about a unit axis (Rodrigues)."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def flange(rows, q, skip_fixed_root):
    T = np.eye(4)
    qi = iter(q)
    for k, row in enumerate(rows):
        if k == 0 and skip_fixed_root:
            continue
        step = np.eye(4)
        roll, pitch, yaw = row["rpy"]
        step[:3, :3] = rot_z(yaw) @ rot_y(pitch) @ rot_x(roll)
        step[:3, 3] = row["xyz"]
        if row["axis"] is not None:
            turn = np.eye(4)
            turn[:3, :3] = about(row["axis"], next(qi))
            step = step @ turn
        T = T @ step
    return T


def main():
    chains = parse(CHAINS)
    rng = np.random.default_rng(SEED)
    out = {}
    for name, own in chains.items():
        rows = chains[SAME_CHAIN.get(name, name)]
        limits = np.array([r["limits"] for r in own if r["limits"] is not None])
        vectors = [np.zeros(6), np.array(POSE_1_MINICOBO if name == "minicobo" else POSE_1)]
        vectors += list(rng.uniform(limits[:, 0], limits[:, 1], (N_RANDOM, 6)))
        out[name] = []
        for q in vectors:
            T = flange(rows, q, name in FROM_BASE_LINK)
            out[name].append({"q": q.tolist(), "position_m": T[:3, 3].tolist(),
                              "rotation": T[:3, :3].tolist()})
    path = Path(__file__).with_name("flange_poses.json")
    lines = ",\n".join(f" {json.dumps(name)}: [\n" + ",\n".join(f"  {json.dumps(r)}" for r in recs)
                       + "\n ]" for name, recs in out.items())
    path.write_text("{\n" + lines + "\n}\n")
    print(f"wrote {path}: {len(out)} models")


if __name__ == "__main__":
    main()

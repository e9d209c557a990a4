"""The pinhole model of the twin's cameras: the projection MuJoCo renders, as CameraInfo's K
and P state it, and its inverse (a depth image back to points).

MuJoCo renders a camera of vertical field of view ``fovy`` through a symmetric frustum of
``tan(fovy/2)`` at unit distance, as tall as the image: so ``fy = (h/2) / tan(fovy/2)``, ``fx =
fy`` (square pixels) and the principal point is the image's centre. Pixel coordinates are
OpenCV's and CameraInfo's — (0, 0) the centre of the top-left pixel — so the centre is at
``((w-1)/2, (h-1)/2)``. A point ``p`` (m, optical frame: z forward, x right, y down) is seen at
pixel ``(u, v) = (fx x/z + cx, fy y/z + cy)``; a depth image holds ``z``
(test/integration/test_twin_cameras_see_where_camera_info_says.py checks both on rendered
pictures).
"""
from __future__ import annotations

import math

import numpy as np


def intrinsics(width: int, height: int, fovy_deg: float) -> np.ndarray:
    """K (3×3, px) of a ``width`` × ``height`` px camera of vertical field of view
    ``fovy_deg``."""
    f = (height / 2.0) / math.tan(math.radians(fovy_deg) / 2.0)
    return np.array([[f, 0.0, (width - 1) / 2.0],
                     [0.0, f, (height - 1) / 2.0],
                     [0.0, 0.0, 1.0]])


def projection(K: np.ndarray) -> np.ndarray:
    """P (3×4) of a monocular camera: ``[K | 0]``."""
    return np.hstack([K, np.zeros((3, 1))])


def project(K: np.ndarray, points) -> np.ndarray:
    """Pixels (…, 2) of ``points`` (…, 3; m, optical frame, z > 0)."""
    p = np.asarray(points, float)
    uvw = p @ K.T
    return uvw[..., :2] / uvw[..., 2:3]


def unproject(K: np.ndarray, depth: np.ndarray) -> np.ndarray:
    """Points (h, w, 3; m, optical frame) of a depth image (h, w; m, NaN where nothing is
    seen: those points are NaN)."""
    h, w = depth.shape
    v, u = np.mgrid[0:h, 0:w]
    z = depth.astype(np.float64)
    x = (u - K[0, 2]) / K[0, 0] * z
    y = (v - K[1, 2]) / K[1, 1] * z
    return np.stack([x, y, z], axis=-1)

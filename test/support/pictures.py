"""Reading the twin's pictures back: an independent PNG decoder and the arm's pixel mask, shared
by the renderer's tests and the node's snapshot service test."""
from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np

from jaka_driver.sim.snapshot import BACKGROUND


def arm_pixels(rgb: np.ndarray) -> np.ndarray:
    """Mask of pixels in the arm's white, lit or in shade: neutral, brighter than the floor,
    and not the sky."""
    i = rgb.astype(int)
    neutral = i.max(axis=2) - i.min(axis=2) <= 12
    return neutral & (i.min(axis=2) >= 170) & np.any(i != BACKGROUND, axis=2)


def read_png(path: Path) -> np.ndarray:
    """Decode with ImageMagick, an independent PNG reader."""
    size = subprocess.run(["identify", "-format", "%w %h", str(path)], capture_output=True,
                          text=True, check=True).stdout.split()
    w, h = int(size[0]), int(size[1])
    raw = subprocess.run(["convert", str(path), "-depth", "8", "rgb:-"], capture_output=True,
                         check=True).stdout
    return np.frombuffer(raw, np.uint8).reshape(h, w, 3)

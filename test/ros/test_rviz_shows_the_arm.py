"""`roslaunch jaka_driver jaka_driver.launch rviz:=true` shows the arm in rviz, and rviz follows
it: screenshots of a virtual X display (xvfb-run, `import -window root`) before and after a
`joint_move` show the arm in its colour, and the picture changed where the arm moved.

The screenshots stay in test/artifacts/ (git-ignored) for a human to look at.
"""
from __future__ import annotations

import os
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

from support.ros_harness import stop_launch, wait_until

pytestmark = pytest.mark.ros

ROOT = Path(__file__).resolve().parents[2]
ARTIFACTS = ROOT / "test" / "artifacts"
SCREEN = "1280x1024x24"
BACKGROUND = (48, 48, 48)       # config/jaka_driver.rviz, Global Options → Background Color
TARGET = [1.2, 1.2, -1.0, 1.57, 1.57, 0.0]      # joint_1 swings the arm across the view
MIN_ARM_PIXELS = 1500           # measured: ~7000 at home, ~4000 at TARGET in a 1280x1024 shot


class RvizOnVirtualDisplay:
    """xvfb-run around roslaunch (driver, robot_state_publisher, rviz) on the test's master."""

    def __init__(self, log_dir: Path):
        self.info = log_dir / "display"
        self.log_path = log_dir / "rviz_launch.log"
        self._log = open(self.log_path, "wb")
        # The shell line reports the display xvfb-run picked (-a: the first free one) and its
        # auth file, which `import` needs, then becomes roslaunch.
        inner = (f'echo "$DISPLAY $XAUTHORITY" > {self.info}; '
                 "exec roslaunch jaka_driver jaka_driver.launch rviz:=true model:=zu5")
        self.proc = subprocess.Popen(["xvfb-run", "-a", "-s", f"-screen 0 {SCREEN}", "sh", "-c",
                                      inner], stdout=self._log, stderr=subprocess.STDOUT,
                                     start_new_session=True, env=os.environ.copy())
        self.display = self.xauthority = None

    def wait_for_display(self, timeout: float = 20.0) -> None:
        text = wait_until(lambda: self.info.exists() and self.info.read_text().strip(), timeout)
        assert text, f"xvfb-run did not start in {timeout} s:\n{self.log()}"
        self.display, self.xauthority = text.split()

    def screenshot(self, path: Path) -> np.ndarray:
        env = dict(os.environ, DISPLAY=self.display, XAUTHORITY=self.xauthority)
        subprocess.run(["import", "-window", "root", str(path)], env=env, check=True,
                       capture_output=True, timeout=20)
        return read_png(path)

    def log(self) -> str:
        self._log.flush()
        return self.log_path.read_text(errors="replace")[-3000:]

    def stop(self) -> None:
        """SIGINT lets roslaunch stop its nodes and xvfb-run its X server; whatever is still
        alive 20 s later is killed by pid."""
        stop_launch(self.proc)
        self._log.close()


def read_png(path: Path) -> np.ndarray:
    raw = subprocess.run(["convert", str(path), "-depth", "8", "ppm:-"], capture_output=True,
                         check=True).stdout
    magic, w, h, maxval, pixels = raw.split(maxsplit=4)
    assert magic == b"P6" and maxval == b"255"
    w, h = int(w), int(h)
    return np.frombuffer(pixels[: w * h * 3], np.uint8).reshape(h, w, 3)


def view_box(shot: np.ndarray) -> tuple[slice, slice]:
    """The 3D view: the rows and columns mostly painted in rviz's background colour (the
    panels around it are not, and their text and the fps counter change by themselves)."""
    bg = np.all(shot == BACKGROUND, axis=2)
    rows, cols = np.flatnonzero(bg.mean(axis=1) > 0.25), np.flatnonzero(bg.mean(axis=0) > 0.25)
    assert rows.size and cols.size, "no rviz 3D view on the screen"
    return slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1)


def arm_pixels(view: np.ndarray) -> np.ndarray:
    """The arm's white (urdf material arm_white, 0.92 0.92 0.90) as rviz lights it: neutral and
    bright. The grid is darker, the TF axes and the tool0 trail are coloured."""
    i = view.astype(int)
    return (i.max(axis=2) - i.min(axis=2) <= 20) & (i.min(axis=2) >= 150)


def settled_shot(rviz: RvizOnVirtualDisplay, path: Path, timeout: float) -> np.ndarray:
    """A screenshot once rviz shows the arm and two shots in a row agree on where it is."""
    previous = None
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        shot = rviz.screenshot(path)
        try:
            rows, cols = view_box(shot)
        except AssertionError:
            rows = None
        if rows is not None:
            arm = arm_pixels(shot[rows, cols])
            if arm.sum() >= MIN_ARM_PIXELS and previous is not None and \
                    previous.shape == arm.shape and np.sum(previous ^ arm) < 50:
                return shot
            previous = arm
        time.sleep(0.5)
    pytest.fail(f"rviz did not show a settled arm in {timeout} s (last shot {path}):\n"
                f"{rviz.log()}")


@pytest.fixture(scope="module")
def rviz(ros_master, rospy_node):
    for tool in ("rviz", "xvfb-run", "import", "convert"):
        assert subprocess.run(["which", tool], capture_output=True).returncode == 0, \
            f"{tool} is not installed: run `make setup` (scripts/apt-packages.txt lists it)"
    log_dir = Path(tempfile.mkdtemp(prefix="jaka_rviz_"))
    shown = RvizOnVirtualDisplay(log_dir)
    try:
        shown.wait_for_display()
        yield shown
    finally:
        shown.stop()


def test_rviz_shows_the_arm_and_follows_a_joint_move(rviz, rospy_node):
    import rospy
    from jaka_msgs.srv import Move

    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    try:
        rospy.wait_for_service("/jaka_driver/joint_move", timeout=60)
    except rospy.ROSException:
        pytest.fail(f"the driver did not come up:\n{rviz.log()}")
    before = settled_shot(rviz, ARTIFACTS / "rviz_before_joint_move.png", timeout=60)

    move = rospy.ServiceProxy("/jaka_driver/joint_move", Move)
    answer = move(pose=TARGET, mvvelo=2.0, mvacc=5.0)
    assert answer.ret == 1, answer.message
    after = settled_shot(rviz, ARTIFACTS / "rviz_after_joint_move.png", timeout=20)

    rows, cols = view_box(before)
    a, b = before[rows, cols], after[rows, cols]
    arm_a, arm_b = arm_pixels(a), arm_pixels(b)
    assert arm_a.sum() >= MIN_ARM_PIXELS and arm_b.sum() >= MIN_ARM_PIXELS, \
        (arm_a.sum(), arm_b.sum())
    # The arm is somewhere else: its pixels moved.
    shift = np.linalg.norm(np.argwhere(arm_a).mean(axis=0) - np.argwhere(arm_b).mean(axis=0))
    assert shift > 20, f"the arm's centre moved {shift:.0f} px only"
    assert np.sum(arm_a ^ arm_b) > MIN_ARM_PIXELS
    # And only there: nearly every changed pixel lies around the arm's old and new place
    # (the trail of tool0 runs between them), the rest of the scene stayed as it was.
    changed = np.any(np.abs(a.astype(int) - b.astype(int)) > 40, axis=2)
    assert changed.sum() > MIN_ARM_PIXELS
    r, c = np.nonzero(arm_a | arm_b)
    margin = 30
    around = np.zeros_like(changed)
    around[max(0, r.min() - margin):r.max() + margin,
           max(0, c.min() - margin):c.max() + margin] = True
    inside = (changed & around).sum() / changed.sum()
    assert inside > 0.9, f"{1 - inside:.1%} of the change is away from the arm"

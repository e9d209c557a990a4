"""A picture of the twin: the arm's visual shapes rendered offscreen (EGL, no display) at the
joints asked for — by the library, by `rosrun jaka_driver snapshot`, and by the node's
`~sim/snapshot` service at the arm's current pose."""
from __future__ import annotations

import subprocess
from pathlib import Path

import mujoco
import numpy as np
import pytest

from jaka_driver.common.models import MODEL_NAMES, load_model
from jaka_driver.sim.snapshot import BACKGROUND, TwinCamera, write_png
from jaka_driver.sim.twin_model import build_twin_model
from support.pictures import arm_pixels, read_png

ROOT = Path(__file__).resolve().parents[2]
HOME = [0.0, 1.5708, -1.5708, 1.5708, 1.5708, 0.0]
SIZE = (320, 240)       # px; small pictures keep the module fast
ARM_WHITE = np.array([0.92, 0.92, 0.90]) * 255      # urdf material "arm_white"


@pytest.fixture(scope="module")
def camera():
    with TwinCamera(load_model("zu5"), width=SIZE[0], height=SIZE[1]) as cam:
        yield cam


def test_picture_shows_the_arm_on_its_floor_under_the_sky(camera):
    rgb = camera.render(HOME)
    assert rgb.shape == (SIZE[1], SIZE[0], 3) and rgb.dtype == np.uint8
    arm = arm_pixels(rgb)
    assert arm.mean() > 0.02, f"only {arm.mean():.1%} of the picture is arm-white"
    sky = np.all(rgb == BACKGROUND, axis=2)
    assert sky[: SIZE[1] // 10].mean() > 0.9, "the top of the picture should be sky"
    assert sky[-SIZE[1] // 10:].mean() == 0, "the bottom of the picture should be floor"
    # the brightest arm pixels are the URDF's arm colour under the headlight
    brightest = rgb[arm].astype(float).max(axis=0)
    assert np.all(np.abs(brightest - ARM_WHITE) < 40), brightest


def test_same_joints_same_picture_other_joints_other_picture(camera):
    a, b = camera.render(HOME), camera.render(HOME)
    assert np.array_equal(a, b), "rendering is deterministic"
    turned = camera.render([1.0] + HOME[1:])
    moved = np.any(np.abs(a.astype(int) - turned.astype(int)) > 30, axis=2)
    assert moved.mean() > 0.01, f"turning joint_1 by 1 rad changed {moved.mean():.2%} only"
    # what changed is where the arm was or now is, not the floor far away
    near_arm = arm_pixels(a) | arm_pixels(turned)
    rows, cols = np.nonzero(near_arm)
    box = np.zeros_like(moved)
    m = SIZE[0] // 20       # the dark joint covers are not arm-white: allow a margin
    box[max(0, rows.min() - m):rows.max() + m, max(0, cols.min() - m):cols.max() + m] = True
    assert (moved & box).sum() / moved.sum() > 0.95


def test_visual_model_has_the_twin_s_kinematics():
    """The picture model keeps the URDF's <visual> shapes but moves exactly like the twin."""
    model = load_model("zu5")
    physics, visual = build_twin_model(model), build_twin_model(model, visual=True)
    assert not np.any(physics.geom_group == 1), "the physics twin has no visual-only shapes"
    assert np.sum(visual.geom_group == 1) >= 6
    q = np.array([0.3, 1.2, -1.0, 0.7, 1.1, -0.4])
    frames = []
    for m in (physics, visual):
        d = mujoco.MjData(m)
        d.qpos[:6] = q
        mujoco.mj_kinematics(m, d)
        frames.append(d.xpos[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "link_6")].copy())
    assert np.allclose(frames[0], frames[1], atol=1e-12)
    assert physics.opt.timestep == visual.opt.timestep
    assert np.allclose(physics.body_mass, visual.body_mass)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_every_model_renders(name):
    with TwinCamera(load_model(name), width=SIZE[0], height=SIZE[1]) as cam:
        share = arm_pixels(cam.render(HOME)).mean()
    assert share > 0.01, f"{name}: the arm covers {share:.1%} of the picture"


def test_png_file_decodes_to_the_same_pixels(camera, tmp_path):
    rgb = camera.render(HOME)
    path = write_png(tmp_path / "sub" / "arm.png", rgb)
    assert np.array_equal(read_png(path), rgb)


def test_bad_joints_are_refused(camera):
    with pytest.raises(ValueError, match="6 finite angles"):
        camera.render([0.0] * 5)
    with pytest.raises(ValueError, match="6 finite angles"):
        camera.render([0.0] * 5 + [float("nan")])


def test_rosrun_snapshot_writes_a_png(tmp_path):
    out = tmp_path / "arm.png"
    run = subprocess.run(["rosrun", "jaka_driver", "snapshot", "--model", "zu3", "--joints",
                          "0", "1.57", "-1.57", "1.57", "1.57", "0", "--width", "320",
                          "--height", "240", "-o", str(out)],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    assert str(out) in run.stdout
    rgb = read_png(out)
    assert rgb.shape == (240, 320, 3) and arm_pixels(rgb).mean() > 0.02


def test_rosrun_snapshot_names_the_models_on_a_wrong_one(tmp_path):
    run = subprocess.run(["rosrun", "jaka_driver", "snapshot", "--model", "zu4", "-o",
                          str(tmp_path / "x.png")], capture_output=True, text=True, timeout=60)
    assert run.returncode == 2
    assert "unknown model 'zu4'" in run.stderr and "zu18" in run.stderr
    assert not (tmp_path / "x.png").exists()


def test_docs_show_one_picture_per_model():
    for name in MODEL_NAMES:
        path = ROOT / "docs" / "images" / f"jaka_{name}.png"
        assert path.is_file(), f"{path} missing (docs/models.md shows it)"
        assert arm_pixels(read_png(path)).mean() > 0.01, f"{path} shows no arm"

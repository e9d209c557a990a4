"""The twin's cameras through ROS (one node in sim time, real_time_factor 0, the cell of
test/data/camera_cell.yaml with small cameras): image, depth, CameraInfo and the point cloud
of one frame carry one stamp, a cycle's sim time at the camera's rate; K is the rendered
projection (the ball where K and TF say); TF has the optical frames; a paused twin publishes
no frame, a stepped one the frames its steps produce."""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest
import yaml
from sensor_msgs.msg import CameraInfo, Image, PointCloud2
from tf2_msgs.msg import TFMessage

from support.ros_harness import Recorder, pause_twin, start_sim_time_driver, step_twin, wait_until

from jaka_driver.common.camera_spec import cameras_from
from jaka_driver.common.pinhole import intrinsics, project
from jaka_driver.common.transforms import quat_to_matrix

pytestmark = pytest.mark.ros

CELL = Path(__file__).resolve().parents[1] / "data" / "camera_cell.yaml"
TOPICS = {"image": ("top/image_raw", Image), "info": ("top/camera_info", CameraInfo),
          "depth": ("top/depth/image_raw", Image), "points": ("top/points", PointCloud2)}
BALL = np.array([-0.12, -0.47, 0.14])


@pytest.fixture(scope="module")
def cell(tmp_path_factory):
    """The cell with its fixed camera at 160 × 120 px: small frames keep the module fast."""
    data = yaml.safe_load(CELL.read_text())
    data["cameras"][0].update(width=160, height=120)
    path = tmp_path_factory.mktemp("cell") / "cell.yaml"
    path.write_text(yaml.safe_dump(data))
    return path, {c.name: c for c in cameras_from(data["cameras"])}


@pytest.fixture(scope="module")
def sim_driver(request, rospy_node, cell):
    """The node of this module (conftest's ``call`` talks to it)."""
    return start_sim_time_driver(request, scene=str(cell[0]))


@pytest.fixture(scope="module")
def node(sim_driver):
    driver = sim_driver
    tf = Recorder("/tf_static", TFMessage)
    recorders = {k: Recorder(f"/{topic}", kind) for k, (topic, kind) in TOPICS.items()}
    yield driver, recorders, tf
    for r in list(recorders.values()) + [tf]:
        r.close()


def _stamps(recorder) -> list:
    return [round(m.header.stamp.to_sec(), 6) for _, m in recorder.samples]


def test_one_frame_one_stamp_on_the_camera_s_cycles(node, cell):
    _, rec, _ = node
    assert wait_until(lambda: all(len(r.samples) >= 3 for r in rec.values()), 30.0)
    image, depth, info = rec["image"].latest(), rec["depth"].latest(), rec["info"].latest()
    assert (image.encoding, image.width, image.height, image.step) == ("rgb8", 160, 120, 480)
    assert (depth.encoding, depth.step) == ("32FC1", 640)
    assert image.header.frame_id == depth.header.frame_id == "top_optical_frame"
    spec = cell[1]["top"]
    assert np.allclose(info.K, intrinsics(160, 120, spec.fovy).ravel())
    assert np.allclose(np.reshape(info.P, (3, 4))[:, :3], np.reshape(info.K, (3, 3)))
    # every stamp is a 10 Hz boundary counted in 8 ms cycles, the same on every topic
    common = set(_stamps(rec["image"])) & set(_stamps(rec["depth"])) & set(_stamps(rec["info"]))
    assert len(common) >= 2
    for t in common:
        n = round(t / 0.008)
        assert abs(t - n * 0.008) < 1e-6 and int(n * 0.08 + 1e-9) > int((n - 1) * 0.08 + 1e-9)


def test_the_ball_is_where_camera_info_and_tf_put_it(node, cell):
    _, rec, tf = node
    assert wait_until(lambda: rec["depth"].latest() is not None and tf.latest(), 30.0)
    frames = {t.child_frame_id: t for _, m in tf.samples for t in m.transforms}
    assert frames["top_link"].header.frame_id == "base_link"
    assert frames["top_optical_frame"].header.frame_id == "top_link"
    assert frames["wrist_link"].header.frame_id == "flange"
    T = np.eye(4)
    for child in ("top_link", "top_optical_frame"):
        tr = frames[child].transform
        step = np.eye(4)
        step[:3, :3] = quat_to_matrix([tr.rotation.x, tr.rotation.y, tr.rotation.z,
                                       tr.rotation.w])
        step[:3, 3] = tr.translation.x, tr.translation.y, tr.translation.z
        T = T @ step
    info, depth_msg = rec["info"].latest(), rec["depth"].latest()
    depth = np.frombuffer(depth_msg.data, "<f4").reshape(120, 160)
    u, v = project(np.reshape(info.K, (3, 3)), (np.linalg.inv(T) @ np.append(BALL, 1))[:3])
    vv, uu = np.mgrid[0:120, 0:160]
    ball = (np.hypot(uu - u, vv - v) < 12) & (depth < np.nanmedian(depth) - 0.005)
    assert ball.sum() > 10
    assert abs(uu[ball].mean() - u) < 1.0 and abs(vv[ball].mean() - v) < 1.0
    # the cloud is the depth of its frame taken back through K (the depth of that frame may
    # come after the cloud)
    assert wait_until(lambda: rec["points"].latest() is not None, 30.0)
    cloud = rec["points"].latest()
    assert [f.name for f in cloud.fields] == ["x", "y", "z", "rgb"]
    xyz = np.frombuffer(cloud.data, "<f4").reshape(cloud.height, cloud.width, 4)[..., :3]
    same = wait_until(lambda: next((m for _, m in reversed(rec["depth"].samples)
                                    if m.header.stamp == cloud.header.stamp), None), 30.0)
    assert same, "no depth image of the cloud's frame"
    assert np.allclose(xyz[..., 2], np.frombuffer(same.data, "<f4").reshape(120, 160),
                       equal_nan=True)


def test_a_paused_twin_publishes_no_frame_and_a_stepped_one_its_frames(node, call):
    _, rec, _ = node
    pause_twin(call)
    try:
        time.sleep(0.5)                       # what was in flight arrives
        before = len(rec["image"].samples)
        time.sleep(0.5)
        assert len(rec["image"].samples) == before, "a frame came while paused"
        t = step_twin(call, 25)
        assert wait_until(lambda: len(rec["image"].samples) >= before + 2, 20.0)
        new = _stamps(rec["image"])[before:]
        assert len(new) == 2 and all(t - 0.2 < s <= t + 1e-6 for s in new), (new, t)
    finally:
        pause_twin(call, False)

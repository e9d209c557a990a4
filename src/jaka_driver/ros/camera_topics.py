"""The cameras' topics (docs/interface.md, "Cameras"), through ``driver.cameras`` only. Per
camera ``<name>``, in the node's namespace, as Gazebo's camera plugins name them:

- ``<name>/image_raw`` (sensor_msgs/Image, ``rgb8``) and ``<name>/camera_info``;
- ``<name>/depth/image_raw`` (``32FC1``, m along the optical axis, NaN where nothing is seen:
  REP 118) and ``<name>/depth/camera_info``;
- ``<name>/points`` (sensor_msgs/PointCloud2, organised, x y z float32 m + rgb, in the optical
  frame) when the camera has ``point_cloud: true``;
- TF (static): ``base_link`` (a fixed camera) or ``flange`` (a wrist camera) →
  ``<name>_link`` → ``<name>_optical_frame`` (REP 103's optical convention: z forward, x
  right, y down).

Every message of a frame has the frame's stamp: the time of the cycle whose state it shows (sim
time when the twin owns time). A camera renders only while somebody subscribes to one of its
topics (looked at every :data:`WATCH_PERIOD` s); frames are published from the rendering
thread, through queued publishers, so a slow subscriber never holds the renderer.
"""
from __future__ import annotations

import io
import struct
import threading
import time

import numpy as np
import rospy
import tf2_ros
from sensor_msgs.msg import CameraInfo, Image, PointCloud2, PointField

from ..backend.cameras import CameraFrame
from ..common.camera_spec import LINK_TO_OPTICAL, CameraSpec
from ..common.pinhole import intrinsics, projection, unproject
from ..driver import RobotDriver
from .frames_tf import transform_stamped

WATCH_PERIOD = 0.2          # s (wall) between looks at who subscribes
QUEUE = 2                   # frames a publisher keeps for a slow subscriber

_CLOUD_FIELDS = [PointField(name=n, offset=4 * i, datatype=PointField.FLOAT32, count=1)
                 for i, n in enumerate(("x", "y", "z", "rgb"))]


def camera_info(spec: CameraSpec) -> CameraInfo:
    """CameraInfo of ``spec``: K and P of the projection MuJoCo renders (jaka_driver.common.
    pinhole), no distortion, R the identity (a monocular camera)."""
    K = intrinsics(spec.width, spec.height, spec.fovy)
    msg = CameraInfo(height=spec.height, width=spec.width, distortion_model="plumb_bob")
    msg.header.frame_id = spec.optical_frame
    msg.D = [0.0] * 5
    msg.K = [float(v) for v in K.ravel()]
    msg.R = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    msg.P = [float(v) for v in projection(K).ravel()]
    return msg


class _PixelImage(Image):
    """An Image whose ``data`` is a C-contiguous array's memory, written into the outgoing
    buffer in one copy. genpy's own ``serialize`` copies the bytes twice more on the way (and
    ``tobytes`` once before): each copy holds the interpreter lock the arm's threads wait for
    (1280 × 720 colour + depth is 6.4 MB a frame). Subscribers receive a plain Image."""

    def serialize(self, buff) -> None:
        pixels = self.data
        self.data = b""
        try:
            super().serialize(buff)             # ends with data's length: 0
        finally:
            self.data = pixels
        buff.seek(-4, io.SEEK_CUR)
        buff.write(_LENGTH.pack(pixels.nbytes))
        buff.write(pixels)


_LENGTH = struct.Struct("<I")


def image(frame_id: str, stamp, pixels: np.ndarray, encoding: str) -> Image:
    """``pixels`` (h × w [× channels], C order, little-endian) as an Image of ``encoding``."""
    pixels = np.ascontiguousarray(pixels)
    h, w = pixels.shape[:2]
    msg = _PixelImage(height=h, width=w, encoding=encoding, is_bigendian=0,
                      step=pixels.strides[0], data=memoryview(pixels).cast("B"))
    msg.header.frame_id, msg.header.stamp = frame_id, stamp
    return msg


def point_cloud(frame_id: str, stamp, K: np.ndarray, frame: CameraFrame) -> PointCloud2:
    """The organised cloud of ``frame`` (h × w points, NaN where nothing is seen), x y z m in
    the optical frame, with each pixel's colour packed as PCL's ``rgb`` float."""
    h, w = frame.depth.shape
    xyz = unproject(K, frame.depth).astype("<f4")
    rgb = frame.rgb.astype(np.uint32)
    packed = ((rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2]).view("<f4")
    data = np.concatenate([xyz, packed[..., None]], axis=-1)
    msg = PointCloud2(height=h, width=w, fields=_CLOUD_FIELDS, is_bigendian=False,
                      point_step=16, row_step=16 * w, is_dense=False, data=data.tobytes())
    msg.header.frame_id, msg.header.stamp = frame_id, stamp
    return msg


class _CameraPublishers:
    def __init__(self, spec: CameraSpec):
        n = spec.name
        self.spec = spec
        self.K = intrinsics(spec.width, spec.height, spec.fovy)
        self.info = camera_info(spec)
        self.rgb = rospy.Publisher(f"{n}/image_raw", Image, queue_size=QUEUE)
        self.rgb_info = rospy.Publisher(f"{n}/camera_info", CameraInfo, queue_size=QUEUE)
        self.depth = rospy.Publisher(f"{n}/depth/image_raw", Image, queue_size=QUEUE)
        self.depth_info = rospy.Publisher(f"{n}/depth/camera_info", CameraInfo,
                                          queue_size=QUEUE)
        self.points = (rospy.Publisher(f"{n}/points", PointCloud2, queue_size=QUEUE)
                       if spec.point_cloud else None)
        self.all = [p for p in (self.rgb, self.rgb_info, self.depth, self.depth_info,
                                self.points) if p is not None]
        self.streaming = False
        self.failed = False         # the renderer cannot run here: said once, not retried

    def wanted(self) -> bool:
        return any(p.get_num_connections() > 0 for p in self.all)

    def publish(self, frame: CameraFrame) -> None:
        stamp = rospy.Time.from_sec(frame.stamp)
        optical = self.spec.optical_frame
        self.info.header.stamp = stamp
        self.rgb.publish(image(optical, stamp, frame.rgb, "rgb8"))
        self.rgb_info.publish(self.info)
        self.depth.publish(image(optical, stamp, np.asarray(frame.depth, "<f4"), "32FC1"))
        self.depth_info.publish(self.info)
        if self.points is not None and self.points.get_num_connections() > 0:
            self.points.publish(point_cloud(optical, stamp, self.K, frame))


def camera_transforms(specs, stamp) -> list:
    """TF of every camera: parent → ``<name>_link`` → ``<name>_optical_frame``."""
    out = []
    for s in specs:
        out.append(transform_stamped(s.parent_frame, s.link_frame, s.link_pose(), stamp))
        out.append(transform_stamped(s.link_frame, s.optical_frame, LINK_TO_OPTICAL, stamp))
    return out


class CameraTopics:
    """The topics and TF of every camera of ``driver`` (see the module)."""

    def __init__(self, driver: RobotDriver):
        self._driver = driver
        specs = driver.cameras.specs()
        self._cameras = {s.name: _CameraPublishers(s) for s in specs}
        self._tf = tf2_ros.StaticTransformBroadcaster()
        self._tf.sendTransform(camera_transforms(specs, rospy.Time.now()))
        result = driver.cameras.listen(self._publish)
        if not result.ok:
            rospy.logwarn(f"cameras: {result.message}")
            return
        threading.Thread(target=self._watch, name="camera-subscribers", daemon=True).start()

    def _publish(self, frame: CameraFrame) -> None:
        camera = self._cameras.get(frame.name)
        if camera is not None and camera.streaming:
            camera.publish(frame)

    def _watch(self) -> None:
        while not rospy.is_shutdown():
            for name, camera in self._cameras.items():
                if camera.failed:
                    continue
                try:
                    wanted = camera.wanted()
                    if wanted != camera.streaming:
                        result = self._driver.cameras.stream(name, wanted)
                        camera.streaming = wanted and result.ok
                        camera.failed = not result.ok
                        log = rospy.loginfo if result.ok else rospy.logerr
                        log(f"camera {name}: {result.message}")
                except Exception as exc:  # noqa: BLE001 — the watcher outlives a bad moment
                    rospy.logwarn_throttle(10.0, f"camera {name}: {exc!r}")
            time.sleep(WATCH_PERIOD)     # wall time: a look, not a timeout

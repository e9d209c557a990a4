"""The cameras' Images are written from the arrays' memory in one copy
(``jaka_driver.ros.camera_topics.image``): the bytes on the wire are those genpy's own Image
makes of the same pixels, for colour, depth and a pixel array that is not contiguous."""
from __future__ import annotations

import io

import numpy as np
import pytest
import rospy
from sensor_msgs.msg import Image

from jaka_driver.ros.camera_topics import image


def _genpy_bytes(frame_id, stamp, pixels, encoding) -> bytes:
    pixels = np.ascontiguousarray(pixels)
    msg = Image(height=pixels.shape[0], width=pixels.shape[1], encoding=encoding,
                is_bigendian=0, step=pixels.strides[0], data=pixels.tobytes())
    msg.header.frame_id, msg.header.stamp = frame_id, stamp
    out = io.BytesIO()
    msg.serialize(out)
    return out.getvalue()


@pytest.mark.parametrize("pixels, encoding", [
    ((np.arange(48 * 64 * 3) % 251).astype(np.uint8).reshape(48, 64, 3), "rgb8"),
    (np.linspace(0.2, 3.0, 48 * 64, dtype=np.float32).reshape(48, 64), "32FC1"),
    ((np.arange(48 * 64 * 3) % 251).astype(np.uint8).reshape(48, 64, 3)[::-1], "rgb8"),
])
def test_an_image_from_an_array_is_the_bytes_genpy_makes(pixels, encoding):
    stamp = rospy.Time(12, 345678)
    out = io.BytesIO(b"\x00" * 4)          # rospy reserves the length first
    out.seek(4)
    image("top_optical_frame", stamp, pixels, encoding).serialize(out)
    assert out.getvalue()[4:] == _genpy_bytes("top_optical_frame", stamp, pixels, encoding)
    back = Image()
    back.deserialize(out.getvalue()[4:])
    assert np.array_equal(np.frombuffer(back.data, pixels.dtype).reshape(pixels.shape), pixels)

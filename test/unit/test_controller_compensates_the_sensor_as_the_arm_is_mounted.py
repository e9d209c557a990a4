"""On a controller whose packets carry two wrenches (the recorded Zu 5s), the driver computes the
sensor's compensated reading itself: ``actual`` less the weight of the sensor's tool payload,
under gravity as the arm is mounted (docs/interface.md, "set_installation_angle"). On a wall a
payload's weight pulls along the base's −y: the reading is zero under the wall's gravity, and
would be off by the whole weight under the upright one. Expected values by hand: a 2 kg payload
at (0, 0, 50) mm, the flange turned as the base (identity)."""
import math

import numpy as np
import pytest

from jaka_driver.backend.force import GRAVITY
from jaka_driver.common.installation import installation
from jaka_driver.controller.status_view import sensor_reading
from jaka_driver.protocol.status_packet import StatusPacket
from jaka_driver.protocol.torque_sensor import TorqueSensorStatus

NAN6 = np.full(6, np.nan)


def packet(actual) -> StatusPacket:
    sensor = TorqueSensorStatus(comm_type=1, ip="", port=0, payload_mass=2.0,
                                payload_centroid=np.array([0.0, 0.0, 50.0]), status=1,
                                errcode=0, actual=np.asarray(actual, float), general=NAN6,
                                real=NAN6)
    return StatusPacket(torque_sensor=sensor)


def test_on_a_wall_the_payloads_weight_is_taken_out_along_the_bases_minus_y():
    weight = 2.0 * 9.81
    # the sensor (= base orientation) feels −y · weight, and its moment c × F = (0.05 · weight) x
    on_the_wall = packet([0.0, -weight, 0.0, 0.05 * weight, 0.0, 0.0])
    wall = installation(math.pi / 2, 0.0).gravity
    real = sensor_reading(on_the_wall, lambda: np.eye(3), wall).real
    assert real == pytest.approx(np.zeros(6), abs=1e-9)
    upright = sensor_reading(on_the_wall, lambda: np.eye(3), GRAVITY).real
    assert np.linalg.norm(upright[:3]) == pytest.approx(math.sqrt(2) * weight)

"""Trajectory recording on ROS (docs/interface.md, "Trajectory recording"): request message →
``driver.recording`` (RobotDriver's door, :mod:`jaka_driver.driver.recording_requests`) →
response, on every backend — the twin records the tool's path itself, a controller is sent
JAKA's commands.

The services carry the names of JAKA's SDK functions, as the force services do, so a JAKA user
finds them: ``~set_traj_config`` / ``~get_traj_config`` (mm, deg, mm/s, mm/s²),
``~set_traj_sample_mode`` (start with a name / stop), ``~get_traj_sample_status``,
``~get_exist_traj_file_name``, ``~rename_traj_file_name``, ``~remove_traj_file`` and
``~generate_traj_exe_file``, whose program ``~program/load`` loads as ``track/<name>`` and
``~program/play`` plays. Every response carries ``ret`` (1 success) and ``message``.
"""
from __future__ import annotations

import rospy

from jaka_driver_msgs.srv import (GetTrajConfig, GetTrajConfigResponse, GetTrajFiles,
                                  GetTrajFilesResponse, GetTrajSampleStatus,
                                  GetTrajSampleStatusResponse, RenameTrajFile,
                                  RenameTrajFileResponse, SetTrajConfig, SetTrajConfigResponse,
                                  SetTrajSampleMode, SetTrajSampleModeResponse, TrajFile,
                                  TrajFileResponse)

from ..driver import RobotDriver
from .services import _logged, _ret


def advertise_recording(driver: RobotDriver) -> list:
    """The eight recording services; returns them."""
    rec = driver.recording

    def config(_req):
        result = rec.config()
        x, r, v, a = result.value.request_units() if result.ok else (0.0,) * 4
        return GetTrajConfigResponse(xyz_interval=x, rpy_interval=r, vel=v, acc=a,
                                     ret=int(result.code), message=result.message)

    def status(_req):
        result = rec.sample_status()
        return GetTrajSampleStatusResponse(sampling=bool(result.ok and result.value),
                                           ret=int(result.code), message=result.message)

    def names(_req):
        result = rec.names()
        return GetTrajFilesResponse(names=list(result.value) if result.ok else [],
                                    ret=int(result.code), message=result.message)

    table = [
        ("set_traj_config", SetTrajConfig, lambda r: _ret(SetTrajConfigResponse)(
            rec.set_config(r.xyz_interval, r.rpy_interval, r.vel, r.acc))),
        ("get_traj_config", GetTrajConfig, config),
        ("set_traj_sample_mode", SetTrajSampleMode, lambda r: _ret(SetTrajSampleModeResponse)(
            rec.set_sample_mode(r.start, r.filename))),
        ("get_traj_sample_status", GetTrajSampleStatus, status),
        ("get_exist_traj_file_name", GetTrajFiles, names),
        ("rename_traj_file_name", RenameTrajFile, lambda r: _ret(RenameTrajFileResponse)(
            rec.rename(r.src, r.dest))),
        ("remove_traj_file", TrajFile, lambda r: _ret(TrajFileResponse)(rec.remove(r.name))),
        ("generate_traj_exe_file", TrajFile, lambda r: _ret(TrajFileResponse)(
            rec.generate(r.name))),
    ]
    return [rospy.Service(f"~{name}", srv, _logged(name, handler))
            for name, srv, handler in table]

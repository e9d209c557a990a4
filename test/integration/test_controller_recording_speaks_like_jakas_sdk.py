"""The controller backend's trajectory recording against the fake controller answering with the
literal replies of sdk_wire_formats §11 (restated in docs/protocol.md; every errorCode a
string): each of JAKA's eight commands goes out byte for byte as JAKA's SDK 2.1.14 writes it,
each reply is read as the SDK reads it, and what the SDK would abort on (a string sampleStatus,
a number in the names) is a -3, not a value. Through RobotDriver's door, a name that is no
program name and a configuration out of range are refused before anything is sent."""
from __future__ import annotations

import pytest

from support.fake_controller import FakeController, start_backend

from jaka_driver.backend import TrajConfig
from jaka_driver.driver import RobotDriver

OK = '"errorCode":"0","errorMsg":"",'


@pytest.fixture(scope="module")
def fake():
    with FakeController() as controller:
        yield controller


@pytest.fixture(scope="module")
def backend(fake):
    b = start_backend(fake)
    yield b
    b.shutdown()


@pytest.fixture(scope="module")
def driver(backend):
    d = RobotDriver(backend)
    yield d
    d.shutdown()


def answer(fake, name: str, fields: str = "", error: str = OK) -> None:
    """The fake's next reply to ``name``: §11's layout, ``fields`` after the first three."""
    fake.raw_replies[name] = ("{" + error + f'"cmdName":"{name}"'
                              + (f",{fields}" if fields else "") + "}").encode()


def sent(fake, name: str) -> str:
    """The last request ``name`` as it went out."""
    with fake.lock:
        return [t for t, r in zip(fake.texts, fake.requests) if r.get("cmdName") == name][-1]


def test_the_configuration_goes_out_with_2_decimal_intervals_and_is_read_back(fake, backend):
    answer(fake, "set_traj_config")
    answer(fake, "get_traj_config", '"xyz_interval":0.1,"rpy_interval":0.2,"vel":25.0,'
                                    '"acc":100.0')
    result = backend.recording.set_config(TrajConfig.from_request(0.1, 0.2, 25.0, 100.0))
    assert result.ok, result.message
    assert sent(fake, "set_traj_config") == ('{"acc":100.0,"cmdName":"set_traj_config",'
                                             '"rpy_interval":0.20,"vel":25.0,'
                                             '"xyz_interval":0.10}')
    assert sent(fake, "get_traj_config") == '{"cmdName":"get_traj_config"}'
    answer(fake, "get_traj_config", '"xyz_interval":0.1,"rpy_interval":0.2,"vel":25.0,'
                                    '"acc":100.0')
    read = backend.recording.config().value
    assert read.request_units() == pytest.approx((0.1, 0.2, 25.0, 100.0))


def test_a_configuration_the_controller_does_not_keep_is_refused_with_2(fake, backend):
    answer(fake, "set_traj_config")
    answer(fake, "get_traj_config", '"xyz_interval":0.1,"rpy_interval":0.2,"vel":30.0,'
                                    '"acc":100.0')
    result = backend.recording.set_config(TrajConfig.from_request(0.1, 0.2, 25.0, 100.0))
    assert result.code == 2 and "get_traj_config reads vel 30, not 25" in result.message


def test_start_status_and_stop_go_out_as_the_sdk_writes_them(fake, backend):
    answer(fake, "set_traj_sample_mode")
    assert backend.recording.start("rec1").ok
    assert sent(fake, "set_traj_sample_mode") == ('{"cmdName":"set_traj_sample_mode",'
                                                  '"filename":"rec1","mode":1}')
    answer(fake, "get_traj_sample_status", '"sampleStatus":1')
    assert backend.recording.sampling().value is True
    assert sent(fake, "get_traj_sample_status") == '{"cmdName":"get_traj_sample_status"}'
    answer(fake, "set_traj_sample_mode")
    assert backend.recording.stop().ok
    assert sent(fake, "set_traj_sample_mode") == ('{"cmdName":"set_traj_sample_mode",'
                                                  '"filename":"rec1","mode":0}')


def test_list_rename_generate_and_remove_go_out_as_the_sdk_writes_them(fake, backend):
    rec = backend.recording
    answer(fake, "get_exist_traj_file_name", '"trajTrackFileName":["rec1","rec2"]')
    assert rec.names().value == ["rec1", "rec2"]
    for name, call, text in (
            ("rename_traj_file_name", lambda: rec.rename("rec1", "rec2"),
             '{"cmdName":"rename_traj_file_name","dest":"rec2","src":"rec1"}'),
            ("generate_traj_exe_file", lambda: rec.generate("rec2"),
             '{"cmdName":"generate_traj_exe_file","fileName":"rec2"}'),
            ("remove_traj_file", lambda: rec.remove("rec2"),
             '{"cmdName":"remove_traj_file","fileName":"rec2"}')):
        answer(fake, name)
        result = call()
        assert result.ok, result.message
        assert sent(fake, name) == text
    answer(fake, "generate_traj_exe_file")
    assert rec.generate("rec2").value == "track/rec2"


def test_a_controllers_refusal_is_2_with_its_message(fake, backend):
    answer(fake, "generate_traj_exe_file", error='"errorCode":"1","errorMsg":"no such file",')
    result = backend.recording.generate("gone")
    assert result.code == 2 and "no such file" in result.message


@pytest.mark.parametrize("name, fields", [
    ("get_traj_sample_status", '"sampleStatus":"1"'),          # the SDK aborts on a string
    ("get_exist_traj_file_name", '"trajTrackFileName":["a",3]'),
    ("get_exist_traj_file_name", '"trajTrackFileName":{"a":1}'),
    ("get_traj_config", '"xyz_interval":"0.1","rpy_interval":0.2,"vel":25.0,"acc":100.0'),
])
def test_what_would_abort_the_sdk_is_a_communication_error(fake, backend, name, fields):
    answer(fake, name, fields)
    call = {"get_traj_sample_status": backend.recording.sampling,
            "get_exist_traj_file_name": backend.recording.names,
            "get_traj_config": backend.recording.config}[name]
    assert call().code == -3


@pytest.mark.parametrize("call, words", [
    (lambda d: d.recording.set_sample_mode(True, "../etc"), "filename is '../etc'"),
    (lambda d: d.recording.rename("a", "b" * 101), "dest has 101 characters, at most 100"),
    (lambda d: d.recording.set_config(0.001, 0.2, 25, 100), "xyz_interval is 0.001 mm, "
                                                            "expected at least 0.01"),
    (lambda d: d.recording.set_config(0.1, 0.2, 25, -1), "acc is -1 mm/s²"),
])
def test_the_door_refuses_bad_fields_before_sending(fake, driver, call, words):
    before = len(fake.requests)
    result = call(driver)
    assert result.code == -2 and words in result.message, result.message
    traj = [r for r in fake.requests[before:] if "traj" in r.get("cmdName", "")]
    assert traj == []

"""RobotState.io — what ~io_states publishes — on both backends: an output set_io changed shows
in the first sample after set_io has answered, counted in samples, not wall time (the twin's 8 ms
cycles in simulated time; a controller's status packets, here the emulator's); every IO kind
the arm has is in it, as the twin's board or the controller's packet holds it."""
from __future__ import annotations

from support.emulated_arm import driver_on_emulator

from jaka_driver.driver import RobotDriver
from jaka_driver.sim import SimBackend
from jaka_driver.common.models import load_model


def _samples_until_shown(driver, key, index, value, limit: int = 10) -> int:
    """Samples after now until one shows IO ``key`` [``index``] == ``value`` (0: the latest one
    already does), at most ``limit``."""
    st = driver.state()
    count = 0
    while st.io[key][index] != value and count < limit:
        assert driver.wait_for_sample(st.stamp, 2.0)
        st = driver.states_since(st.stamp)[0]
        count += 1
    return count


def test_the_twin_shows_an_output_in_the_next_sample():
    driver = RobotDriver(SimBackend(load_model("zu5"), sim_time=True, real_time_factor=0))
    driver.start()
    try:
        io = driver.state().io
        assert {key[1] for key in io} == {0, 1, 2}            # cabinet, tool, extension
        for signal, io_type, index, value in (("digital", 0, 3, 1.0), ("analog", 0, 1, 2.5),
                                              ("digital", 1, 0, 1.0), ("analog", 2, 3, 4.0)):
            assert driver.set_io(signal, io_type, index, value).ok
            assert _samples_until_shown(driver, (signal, io_type, 1), index, value) <= 1
    finally:
        driver.shutdown()


def test_a_controller_shows_an_output_within_one_packet():
    with driver_on_emulator(programs=None) as (emu, driver):
        io = driver.state().io
        # the default profile's cabinet, tool, extension module, relays and fieldbus slaves
        assert {key[1] for key in io} == {0, 1, 2, 3, 4, 5, 6}
        assert len(io[("digital", 0, 1)]) == emu.model.io_sizes[("digital", 0, 1)]
        for signal, io_type, index, value in (("digital", 0, 3, 1), ("analog", 0, 1, 2.5),
                                              ("digital", 2, 5, 1)):
            assert driver.set_io(signal, io_type, index, value).ok
            assert _samples_until_shown(driver, (signal, io_type, 1), index, value) <= 1

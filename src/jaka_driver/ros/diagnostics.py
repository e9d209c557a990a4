"""``/diagnostics`` at 1 Hz: backend, connection, publish rate, last error, servo mode, speed
ratio, the conventions the driver reads requests in, what the backend describes of itself
(version, physics steps, ...) and the topic inputs' counts (accepted, refused, stops)."""
from __future__ import annotations

import threading

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from ..driver import RobotDriver
from ..host import realtime


class Diagnostics:
    def __init__(self, driver: RobotDriver, publisher_stats, name: str = "jaka_driver",
                 extra=dict):
        """``extra()``: more values (the topic inputs' counts)."""
        self._driver = driver
        self._extra = extra
        self._stats = publisher_stats
        self._name = name
        self._pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=5)
        threading.Thread(target=self._run, name="diagnostics", daemon=True).start()

    def status(self) -> DiagnosticStatus:
        st = self._driver.state()
        info = self._driver.describe()
        rate = self._stats()
        level, message = DiagnosticStatus.OK, "ready"
        if not st.connected:
            level, message = DiagnosticStatus.ERROR, "not connected to the controller"
        elif st.emergency_stop:
            level, message = DiagnosticStatus.ERROR, "emergency stop pressed"
        elif st.in_error:
            level, message = DiagnosticStatus.WARN, st.error_message or "error"
        elif not (st.powered and st.enabled):
            level, message = DiagnosticStatus.WARN, "not powered / enabled"
        elif st.on_limit:
            level, message = DiagnosticStatus.WARN, "a joint is on its soft limit"
        values = {"publish rate (Hz)": f"{rate:.1f}", "connected": str(st.connected),
                  "powered": str(st.powered), "enabled": str(st.enabled),
                  "servo mode": str(st.servo_mode), "drag mode": str(st.drag_mode),
                  "collision": str(st.collision), "on soft limit": str(st.on_limit),
                  "last error": st.error_message or "none",
                  "conventions": self._driver.conventions.name,
                  "servo increments": str(self._driver.conventions.servo_increment),
                  "speed ratio": f"{self._driver.speed_ratio():g}"}
        values.update({k: str(v) for k, v in info.items()})
        values.update(self._extra())
        return DiagnosticStatus(level=level, name=f"{self._name}: {info.get('backend')}",
                                message=message, hardware_id=f"JAKA {self._driver.model.name}",
                                values=[KeyValue(k, v) for k, v in values.items()])

    @realtime.runs_periodically
    def _run(self) -> None:
        while not rospy.is_shutdown():
            try:
                msg = DiagnosticArray(status=[self.status()])
                msg.header.stamp = rospy.Time.now()
                self._pub.publish(msg)
            except Exception as exc:  # noqa: BLE001
                rospy.logerr_throttle(10.0, f"diagnostics failed: {exc!r}")
            self._driver.clock.sleep(1.0)     # 1 Hz of the driver's time (sim or wall)

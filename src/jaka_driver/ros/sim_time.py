"""Start-up of ``sim_time``: the twin owns ROS time (docs/interface.md, *Simulated time*).

Three things have to happen before ``rospy.init_node``, because rospy reads ``/use_sim_time``
once, there: find out whether ``~sim_time`` was asked for, make sure no other live node already
publishes ``/clock`` (two clocks would each move time their own way: every stamp, timeout and
``rospy.sleep`` of every client would jump between them), and set ``/use_sim_time``.
"""
from __future__ import annotations

import sys
import xmlrpc.client

import rosgraph

CLOCK_TOPIC = "/clock"
PING_TIMEOUT = 1.0          # s; a registered node that does not answer this fast is gone


def node_name(argv: list[str], name: str) -> str:
    """The global name ``init_node(name)`` will give this node (``__ns``/``__name`` remaps)."""
    mappings = rosgraph.names.load_mappings(argv)
    ns = rosgraph.names.make_global_ns(mappings.get("__ns") or rosgraph.names.get_ros_namespace())
    return ns + mappings.get("__name", name)


def requested(argv: list[str], name: str) -> bool:
    """``~sim_time`` asked for, on the twin (the controller backend runs on the wall clock, so
    for it ``/use_sim_time`` must stay as it is: set with nobody publishing ``/clock``, every
    client's ``rospy.sleep`` would wait forever)."""
    return (_early_param(argv, name, "sim_time", "false").lower() in ("true", "1", "yes")
            and _early_param(argv, name, "backend", "sim") == "sim")


def _early_param(argv: list[str], name: str, key: str, default: str) -> str:
    """Private parameter ``key`` before ``init_node``, as text: from a ``_key:=`` argument,
    else from the parameter server (roslaunch), else ``default``."""
    for arg in argv[1:]:
        if arg.startswith(f"_{key}:="):
            return arg.split(":=", 1)[1].strip()
    private = rosgraph.names.ns_join(node_name(argv, name), key)
    try:
        return str(rosgraph.Master(f"/{name}").getParam(private)).strip()
    except (rosgraph.MasterError, OSError):
        return default                  # not set, or no master yet (init_node will wait)


def other_clock_publishers(own_name: str) -> list[str]:
    """Live nodes other than ``own_name`` that publish ``/clock``; empty if there is no master
    yet (then there is no other node either). A registration left by a node that was killed
    without unregistering does not count: each one is asked for its pid first."""
    master = rosgraph.Master(own_name)
    try:
        publishers = dict(master.getSystemState()[0])
    except (rosgraph.MasterError, OSError):
        return []
    live = []
    for node in publishers.get(CLOCK_TOPIC, []):
        if node != own_name and _answers(master, node):
            live.append(node)
    return live


def use_sim_time() -> None:
    """Set ``/use_sim_time`` so that this node's rospy and every client follow /clock."""
    try:
        rosgraph.Master("/jaka_driver").setParam("/use_sim_time", True)
    except OSError as exc:
        print(f"jaka_driver: cannot set /use_sim_time: {exc}", file=sys.stderr)


def _answers(master: rosgraph.Master, node: str) -> bool:
    try:
        uri = master.lookupNode(node)
        code, _, _ = xmlrpc.client.ServerProxy(uri, transport=_Timeout()).getPid(master.caller_id)
        return code == 1
    except (rosgraph.MasterError, OSError, xmlrpc.client.Error):
        return False


class _Timeout(xmlrpc.client.Transport):
    """XML-RPC over HTTP with a socket timeout: a node on a host that went away must not hang
    the start-up."""

    def make_connection(self, host):
        connection = super().make_connection(host)
        connection.timeout = PING_TIMEOUT
        return connection

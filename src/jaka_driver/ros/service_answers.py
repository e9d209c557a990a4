"""How a service answers, in one place for every ROS module of the node: a driver Result as a
``ret``/``message`` response (:func:`answer_with`), and a refusal logged once per call
(:func:`logged`)."""
from __future__ import annotations

import rospy

from ..common.results import Result


def answer_with(response_type):
    """A Result → ``response_type(ret, message)``."""
    def answer(result: Result):
        return response_type(ret=int(result.code), message=result.message)
    return answer


def logged(name: str, handler):
    """Log refusals once per call, at the level a user would want to see them."""
    def serve(request):
        response = handler(request)
        ret = getattr(response, "ret", None)
        if ret is not None and ret != 1:
            rospy.logwarn("%s refused (%d): %s", name, ret, response.message)
        return response
    return serve

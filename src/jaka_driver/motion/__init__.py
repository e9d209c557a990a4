"""Motion planning for jaka_driver: pure numpy, no ROS, no simulator, no kinematics library.

Kinematics comes in as callables (``ik(T, seed)``), so the planners are tested with fake arms
and serve both the MuJoCo twin and any other executor the same way.

- :mod:`.profiles`     time laws: 1-D trapezoid, synchronised joint move (joint_move)
- :mod:`.linear_path`  Cartesian straight line checked sample by sample (linear_move)
- :mod:`.trajectory`   :class:`JointTrajectory`, the sampled joint motion every executor plays
- :mod:`.jog`          velocity ramp for continuous jog
- :mod:`.spline`       waypoint interpolation for FollowJointTrajectory
"""

"""ROS 2 interface of the skill runtime (the optional extra ``a2l[ros]``; ``docs/ros.md``).

- :mod:`~a2l.ros.topics`: topic names, the high-level states as ``std_msgs/Bool``, message
  conversions;
- :mod:`~a2l.ros.skill_node`: a skill bundle run on a robot through ROS 2 (the C++ step on
  every joint state);
- :mod:`~a2l.ros.effects`: the effect tests the skill node runs from its topics (a push,
  ``grasped``, ``pressed``);
- :mod:`~a2l.ros.robot`: the robot a node runs (any robot entry, by default the bundle's);
- :mod:`~a2l.ros.orientation`: the orientation the skill node commands (the gripper
  pointing down, turned as the skill was learned);
- :mod:`~a2l.ros.sim_node`: a PyBullet scene on a robot behind the same topics;
- :mod:`~a2l.ros.spin`: rclpy's set-up, spinning, SIGINT;
- :mod:`~a2l.ros.run`: the two nodes run until done (``a2l ros skill``, ``a2l ros sim``).

rclpy and the message packages are imported only when a node is made, so ``import a2l.ros``
works without the extra.
"""

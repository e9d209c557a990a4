// A subscriber written for JAKA's driver code's tool_position (geometry_msgs/PoseStamped,
// position mm, orientation quaternion, since 2025-06): waits up to 10 s for one message on
// /jaka_driver/tool_position and prints "tool_position x y z qx qy qz qw frame_id"; exit 1
// when none comes (a TwistStamped publisher never connects to it: the types differ).
#include <cstdio>

#include <geometry_msgs/PoseStamped.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "jaka_pose_stamped_listener");
  ros::NodeHandle handle;
  auto msg = ros::topic::waitForMessage<geometry_msgs::PoseStamped>(
      "/jaka_driver/tool_position", handle, ros::Duration(10.0));
  if (!msg) {
    std::printf("no PoseStamped on /jaka_driver/tool_position in 10 s\n");
    return 1;
  }
  const auto& p = msg->pose.position;
  const auto& q = msg->pose.orientation;
  std::printf("tool_position %.6f %.6f %.6f %.9f %.9f %.9f %.9f %s\n", p.x, p.y, p.z, q.x, q.y,
              q.z, q.w, msg->header.frame_id.c_str());
  return 0;
}

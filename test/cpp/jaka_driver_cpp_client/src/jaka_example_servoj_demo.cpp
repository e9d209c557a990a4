// The calls JAKA's example servoj_demo (jaka_robot v2.2, src/jaka_driver/src/servoj_demo.cpp)
// makes, written anew for this project's tests (README.md here: the facts, and why JAKA's
// source is not in this repository).
//
// Waits for /jaka_driver/servo_j; servo_move_enable true; 1 s; 200 calls of servo_j with the
// float pose {0.001, 0, 0, 0, 0, 0.001}, back to back, each answer printed; 1 s; exit 0. Like
// the example it neither checks the answers nor leaves servo mode.
#include <cstdio>

#include <ros/ros.h>

#include <jaka_msgs/ServoMove.h>
#include <jaka_msgs/ServoMoveEnable.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "jaka_example_servoj_demo");
  ros::NodeHandle handle;
  ros::ServiceClient enable =
      handle.serviceClient<jaka_msgs::ServoMoveEnable>("/jaka_driver/servo_move_enable");
  ros::ServiceClient servo_j = handle.serviceClient<jaka_msgs::ServoMove>("/jaka_driver/servo_j");
  servo_j.waitForExistence();
  jaka_msgs::ServoMoveEnable on;
  on.request.enable = true;
  enable.call(on);
  ros::Duration(1.0).sleep();
  const float step[6] = {0.001f, 0.0f, 0.0f, 0.0f, 0.0f, 0.001f};   // rad, float as sent
  jaka_msgs::ServoMove call;
  call.request.pose.assign(step, step + 6);
  for (int i = 0; i < 200; ++i) {
    servo_j.call(call);
    std::printf("servo_j ret %d %s\n", static_cast<int>(call.response.ret),
                call.response.message.c_str());
  }
  ros::Duration(1.0).sleep();
  return 0;
}

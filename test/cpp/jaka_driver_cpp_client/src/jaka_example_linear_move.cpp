// The call JAKA's example client (jaka_robot v2.2, src/jaka_driver/src/client.cpp) makes,
// written anew for this project's tests (README.md here: the facts, and why JAKA's source is
// not in this repository).
//
//   jaka_example_linear_move A1 A2 A3 A4 A5 A6
//
// Like JAKA's example: exactly six arguments or exit 1; the six pose values are the numbers
// of argv[0]..argv[5] (argv[0] is the program's own path, which reads as 0: the first value
// is 0 and A6 is never read), mvvelo 100, mvacc 100, every other field left at its default;
// one call of /jaka_driver/linear_move. Prints "ret <n>"; exit 1 when the call fails.
#include <cstdio>
#include <cstdlib>

#include <ros/ros.h>

#include <jaka_msgs/Move.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "jaka_example_linear_move");
  if (argc != 7) {
    std::printf("expected 6 arguments, got %d\n", argc - 1);
    return 1;
  }
  ros::NodeHandle handle;
  ros::ServiceClient linear_move = handle.serviceClient<jaka_msgs::Move>("/jaka_driver/linear_move");
  jaka_msgs::Move call;
  for (int i = 0; i < 6; ++i) call.request.pose.push_back(std::atof(argv[i]));
  call.request.mvvelo = 100;
  call.request.mvacc = 100;
  if (!linear_move.call(call)) {
    std::printf("linear_move call failed\n");
    return 1;
  }
  std::printf("ret %d %s\n", static_cast<int>(call.response.ret), call.response.message.c_str());
  return 0;
}

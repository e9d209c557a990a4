// A roscpp client of jaka_driver, run by test/ros/test_catkin_workspace_and_cpp_client.py.
//
//   jaka_cpp_client services    joint_move, get_fk, linear_move, get_ik, set_io/get_io,
//                               servo_move_enable + servo_j (absolute targets), while
//                               subscribed to robot_states and joint_position
//   jaka_cpp_client increments  servo_j as JAKA's servoj_demo calls it (200 increments of
//                               {0.001, 0, 0, 0, 0, 0.001} rad): the driver runs with
//                               servo_increment:=true
//
// Every call is checked; the first failure exits 1 naming the call and the answer. What the
// test asserts is printed as "name value..." lines on stdout. Units: rad, mm + rotation vector.
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

#include <ros/ros.h>
#include <sensor_msgs/JointState.h>

#include <jaka_msgs/GetFK.h>
#include <jaka_msgs/GetIK.h>
#include <jaka_msgs/GetIO.h>
#include <jaka_msgs/Move.h>
#include <jaka_msgs/RobotMsg.h>
#include <jaka_msgs/ServoMove.h>
#include <jaka_msgs/ServoMoveEnable.h>
#include <jaka_msgs/SetIO.h>

namespace {

// s: the twin's cycle, and the gap after which it skips its stamps ahead (STALL_CYCLES = 25
// cycles of jaka_driver.common.constants: on a busy machine the twin, held that long, goes on
// from the wall clock's time instead of bursting through the cycles it missed)
const double CYCLE = 0.008;
const double STALL_GAP = 25 * CYCLE;

std::mutex lock;
std::vector<double> joints;        // latest joint_position, rad
double last_stamp = -1;            // s, the latest joint_position's header stamp
int joint_messages = 0;
double cycles = 0;                 // twin cycles between the stamps counted (skips left out)
int state_messages = 0;
int servo_state = -1;              // latest robot_states.servo_state

void on_joints(const sensor_msgs::JointState::ConstPtr& msg) {
  std::lock_guard<std::mutex> guard(lock);
  joints.assign(msg->position.begin(), msg->position.end());
  const double stamp = msg->header.stamp.toSec();
  if (last_stamp >= 0) {
    const double gap = stamp - last_stamp;
    cycles += gap > STALL_GAP ? 1 : gap / CYCLE;
  }
  last_stamp = stamp;
  ++joint_messages;
}

void on_state(const jaka_msgs::RobotMsg::ConstPtr& msg) {
  std::lock_guard<std::mutex> guard(lock);
  servo_state = msg->servo_state;
  ++state_messages;
}

std::vector<double> current_joints() {
  std::lock_guard<std::mutex> guard(lock);
  return joints;
}

[[noreturn]] void fail(const std::string& what);

// The joints of the first joint_position sample stamped now or later: where the arm is once
// a blocking call has answered. The latest message received can be older: on a busy machine
// the spinner runs behind, and the arm was still moving in the samples it has not read yet.
std::vector<double> joints_now() {
  const double now = ros::Time::now().toSec();
  const ros::WallTime t0 = ros::WallTime::now();
  while (true) {
    {
      std::lock_guard<std::mutex> guard(lock);
      if (last_stamp >= now) return joints;
    }
    if ((ros::WallTime::now() - t0).toSec() > 10) fail("no joint_position stamped now in 10 s");
    ros::WallDuration(0.005).sleep();
  }
}

[[noreturn]] void fail(const std::string& what) {
  std::printf("FAILED %s\n", what.c_str());
  std::fflush(stdout);
  std::exit(1);
}

template <class Srv>
void call(ros::NodeHandle& nh, const std::string& name, Srv& srv) {
  ros::ServiceClient client = nh.serviceClient<Srv>("/jaka_driver/" + name);
  if (!client.call(srv)) fail(name + ": the ROS call itself failed");
}

template <class Srv>
void call_ok(ros::NodeHandle& nh, const std::string& name, Srv& srv) {
  call(nh, name, srv);
  if (srv.response.ret != 1)
    fail(name + ": ret " + std::to_string(srv.response.ret) + " " + srv.response.message);
}

void print(const std::string& name, const std::vector<double>& values) {
  std::printf("%s", name.c_str());
  for (double v : values) std::printf(" %.6f", v);
  std::printf("\n");
}

template <class V>
std::vector<double> doubles(const V& values) {
  return std::vector<double>(values.begin(), values.end());
}

double max_gap(const std::vector<double>& a, const std::vector<double>& b, size_t n) {
  double gap = 0;
  for (size_t i = 0; i < n; ++i) gap = std::max(gap, std::fabs(a[i] - b[i]));
  return gap;
}

void services(ros::NodeHandle& nh) {
  const std::vector<double> pose = {0.5, 1.9, -1.4, 1.1, 1.57, 0.0};

  jaka_msgs::Move joint_move;
  joint_move.request.pose.assign(pose.begin(), pose.end());
  joint_move.request.mvvelo = 1.0;
  joint_move.request.mvacc = 2.0;
  call_ok(nh, "joint_move", joint_move);
  print("joint_move_arrived", joints_now());

  jaka_msgs::GetFK fk;
  fk.request.joint.assign(pose.begin(), pose.end());
  call(nh, "get_fk", fk);
  if (fk.response.cartesian_pose.size() != 6 || fk.response.cartesian_pose[0] == 9999)
    fail("get_fk: " + fk.response.message);
  print("get_fk", doubles(fk.response.cartesian_pose));

  jaka_msgs::Move linear_move;           // 50 mm straight down
  linear_move.request.pose = fk.response.cartesian_pose;
  linear_move.request.pose[2] -= 50.0;
  linear_move.request.mvvelo = 100;
  linear_move.request.mvacc = 500;
  call_ok(nh, "linear_move", linear_move);
  std::vector<double> after_line = joints_now();
  jaka_msgs::GetFK fk_after;
  fk_after.request.joint.assign(after_line.begin(), after_line.end());
  call(nh, "get_fk", fk_after);
  print("linear_move_arrived_tcp", doubles(fk_after.response.cartesian_pose));

  jaka_msgs::GetIK ik;
  ik.request.ref_joint.assign(pose.begin(), pose.end());
  ik.request.cartesian_pose = linear_move.request.pose;
  call(nh, "get_ik", ik);
  if (ik.response.joint.size() != 6 || ik.response.joint[0] == 9999)
    fail("get_ik: " + ik.response.message);
  print("get_ik", doubles(ik.response.joint));

  jaka_msgs::SetIO set_io;
  set_io.request.signal = "digital";
  set_io.request.type = 0;
  set_io.request.index = 3;
  set_io.request.value = 1;
  call_ok(nh, "set_io", set_io);
  jaka_msgs::GetIO get_io;
  get_io.request.signal = "digital";
  get_io.request.path = 1;
  get_io.request.type = 0;
  get_io.request.index = 3;
  call(nh, "get_io", get_io);
  print("get_io", {get_io.response.value});

  jaka_msgs::ServoMoveEnable enable;
  enable.request.enable = true;
  call_ok(nh, "servo_move_enable", enable);
  ros::Duration(0.1).sleep();
  {
    std::lock_guard<std::mutex> guard(lock);
    print("servo_state_in_servo_mode", {double(servo_state)});
  }
  // joint_6 +0.05 rad in 50 absolute targets, one per 8 ms cycle
  std::vector<double> start = joints_now();
  print("servo_j_start", start);
  jaka_msgs::ServoMove servo;
  ros::Rate cycle(125);
  for (int i = 1; i <= 50; ++i) {
    servo.request.pose.assign(start.begin(), start.end());
    servo.request.pose[5] = start[5] + 0.001 * i;
    call_ok(nh, "servo_j", servo);
    cycle.sleep();
  }
  ros::Duration(0.3).sleep();
  print("servo_j_end", joints_now());
  enable.request.enable = false;
  call_ok(nh, "servo_move_enable", enable);
}

void increments(ros::NodeHandle& nh) {
  // As JAKA's servoj_demo: enter servo mode, wait 1 s, 200 increments as fast as they go.
  jaka_msgs::ServoMoveEnable enable;
  enable.request.enable = true;
  call_ok(nh, "servo_move_enable", enable);
  ros::Duration(1.0).sleep();
  print("increments_start", joints_now());
  jaka_msgs::ServoMove servo;
  const float step[6] = {0.001, 0, 0, 0, 0, 0.001};
  servo.request.pose.assign(step, step + 6);
  for (int i = 0; i < 200; ++i) call_ok(nh, "servo_j", servo);
  ros::Duration(1.0).sleep();
  print("increments_end", joints_now());
  enable.request.enable = false;
  call_ok(nh, "servo_move_enable", enable);
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "jaka_cpp_client");
  const std::string mode = argc > 1 ? argv[1] : "services";
  ros::NodeHandle nh;
  // Queues long enough for every message of the session (topic_rates_hz counts what the node
  // published): on a busy machine the spinner falls behind, and a queue of 10 drops messages.
  ros::Subscriber joint_sub = nh.subscribe("/jaka_driver/joint_position", 2000, on_joints);
  ros::Subscriber state_sub = nh.subscribe("/jaka_driver/robot_states", 2000, on_state);
  ros::AsyncSpinner spinner(1);
  spinner.start();
  if (!ros::service::waitForService("/jaka_driver/servo_j", ros::Duration(60)))
    fail("no /jaka_driver/servo_j within 60 s");
  const ros::WallTime t0 = ros::WallTime::now();
  while (current_joints().size() < 6) {
    if ((ros::WallTime::now() - t0).toSec() > 10) fail("no joint_position within 10 s");
    ros::WallDuration(0.01).sleep();
  }
  int joints0, states0;
  double cycles0;
  {
    std::lock_guard<std::mutex> guard(lock);
    joints0 = joint_messages;
    states0 = state_messages;
    cycles0 = cycles;
  }
  if (mode == "services") services(nh);
  else if (mode == "increments") increments(nh);
  else fail("unknown mode " + mode);
  ros::Duration(0.2).sleep();      // what was published by the last call has arrived
  std::lock_guard<std::mutex> guard(lock);
  // The session's rates in the arm's time, messages per second of its samples' stamps (the
  // twin's 8 ms cycles), not of this client's clock: on a busy machine the spinner runs late
  // and in bursts, which says nothing of what the node published. robot_states has no stamp:
  // it goes out with each joint_position, so its rate is joint_position's times their ratio.
  const int joint_count = joint_messages - joints0, state_count = state_messages - states0;
  const double joint_hz = joint_count / ((cycles - cycles0) * CYCLE);
  print("topic_rates_hz", {joint_hz, joint_hz * state_count / joint_count});
  std::printf("OK\n");
  return 0;
}

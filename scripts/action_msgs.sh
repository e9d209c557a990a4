# Sourced by the message generators (gen_control_msgs.sh, gen_driver_msgs.sh): an action's
# seven messages by actionlib's convention, as catkin's genaction would derive them.
# derive_action_msgs ACTION_FILE MSG_DIR  →  MSG_DIR/<Name>{Goal,Result,Feedback}.msg and
# <Name>Action{Goal,Result,Feedback}.msg, <Name>Action.msg
derive_action_msgs() {
  local action=$1 dir=$2 name
  name=$(basename "$action" .action)
  # split the three sections on the '---' lines
  awk -v dir="$dir" -v n="$name" '
    BEGIN { part = 0; f[0] = "Goal"; f[1] = "Result"; f[2] = "Feedback" }
    /^---$/ { part++; next }
    { print > (dir "/" n f[part] ".msg") }' "$action"
  printf 'Header header\nactionlib_msgs/GoalID goal_id\n%sGoal goal\n' "$name" > "$dir/${name}ActionGoal.msg"
  printf 'Header header\nactionlib_msgs/GoalStatus status\n%sResult result\n' "$name" > "$dir/${name}ActionResult.msg"
  printf 'Header header\nactionlib_msgs/GoalStatus status\n%sFeedback feedback\n' "$name" > "$dir/${name}ActionFeedback.msg"
  printf '%sActionGoal action_goal\n%sActionResult action_result\n%sActionFeedback action_feedback\n' "$name" "$name" "$name" > "$dir/${name}Action.msg"
}

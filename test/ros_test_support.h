#pragma once
// What the rostests share beyond test_support.h: playing a bag into the live graph (roscpp, so kept out
// of the gtest-only tests' header).

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include <ros/ros.h>

namespace vocal_test {

// Plays `bag` with rosbag play once the graph subscribes to it (`options`: more of rosbag play's, e.g.
// --rate or --topics; rosbag waits for a subscriber of every topic it plays); fails the test when rosbag
// play fails or takes longer than `seconds` (killed then). Call with ASSERT_NO_FATAL_FAILURE.
inline void playBag(const std::string& bag, double seconds = 60.0, const std::vector<std::string>& options = {}) {
  std::vector<std::string> arguments = {"rosbag", "play", "--quiet", "--wait-for-subscribers", bag};
  arguments.insert(arguments.end(), options.begin(), options.end());
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  const pid_t player = ::fork();
  ASSERT_GE(player, 0);
  if (player == 0) {
    ::execvp("rosbag", argv.data());
    std::perror("exec rosbag");
    ::_exit(127);
  }
  int status = 0;
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  while (::waitpid(player, &status, WNOHANG) == 0) {
    if (ros::WallTime::now() > deadline) {
      ::kill(player, SIGKILL);
      ::waitpid(player, &status, 0);
      FAIL() << "rosbag play did not finish within " << seconds << " s";
    }
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "rosbag play failed";
}

}  // namespace vocal_test

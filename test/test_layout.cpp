// The package's layout as the robot sees it: the libraries a robot loads hold no simulator.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_support.h"

namespace {

using vocal_test::runCommand;

std::string libraryPath(const std::string& name) { return std::string(VOCAL_LIBRARY_DIR) + "/lib" + name + ".so"; }

TEST(Layout, WhatRunsOnARobotLinksNoSimulator) {
  // One public function from each simulation/ header, as nm prints it.
  const std::vector<std::string> simulator_functions = {
      "vocal::fractalNoise(",          "vocal::applyDepthSensorModel(", "vocal::exampleRig(",
      "vocal::surfaceLabelName(",      "vocal::parseLidarModel(",       "vocal::parseSceneVariant(",
      "vocal::renderSyntheticFrame(",  "vocal::generateSyntheticTrajectory("};
  // The check sees them where they are: in the simulation library.
  const vocal_test::RunResult simulation = runCommand("nm -DC --defined-only " + libraryPath("vocal_simulation"));
  ASSERT_EQ(simulation.exit_code, 0) << simulation.output;
  for (const std::string& function : simulator_functions) {
    EXPECT_NE(simulation.output.find(function), std::string::npos) << function << " not in vocal_simulation";
  }
  for (const char* library :
       {"vocal_core", "vocal_odometry", "vocal_calibration", "vocal_driver", "vocal_ros_conversions", "vocal_nodelets"}) {
    const vocal_test::RunResult linked = runCommand("ldd " + libraryPath(library));
    ASSERT_EQ(linked.exit_code, 0) << linked.output;
    EXPECT_EQ(linked.output.find("libvocal_simulation"), std::string::npos) << library << " links the simulators:\n"
                                                                            << linked.output;
    const vocal_test::RunResult defined = runCommand("nm -DC --defined-only " + libraryPath(library));
    ASSERT_EQ(defined.exit_code, 0) << defined.output;
    for (const std::string& function : simulator_functions) {
      EXPECT_EQ(defined.output.find(function), std::string::npos) << library << " defines " << function;
    }
  }
}

}  // namespace

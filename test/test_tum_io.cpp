#include <gtest/gtest.h>

#include <unistd.h>

#include "test_support.h"
#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/core/tum_sequence.h"
#include "vocal/core/tum_trajectory.h"

using vocal_test::makeTempFolder;
using vocal_test::writeText;

using vocal_test::inputErrorOf;

TEST(TumTrajectory, WriteReadRoundTripsExactly) {
  const std::string folder = makeTempFolder("trajectory");
  vocal::Trajectory trajectory;
  for (int i = 0; i < 50; ++i) {
    vocal::Vector6d twist;
    twist << 0.1 * i, std::sin(i), 1.0 / (i + 3), 0.01 * i, -0.02 * i, 0.3;
    trajectory.push_back({1305031102.175304 + i / 30.0, vocal::se3Exp(twist)});
    trajectory.back().stamp = std::round(trajectory.back().stamp * 1e6) / 1e6;
  }
  vocal::writeTumTrajectory(folder + "/t.txt", trajectory);
  const vocal::Trajectory back = vocal::readTumTrajectory(folder + "/t.txt");
  ASSERT_EQ(back.size(), trajectory.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back[i].stamp, trajectory[i].stamp);
    EXPECT_EQ(back[i].pose.translation(), trajectory[i].pose.translation());
    EXPECT_LT((back[i].pose.linear() - trajectory[i].pose.linear()).norm(), 1e-15);
  }
}

TEST(TumTrajectory, MalformedLinesNameFileAndLine) {
  const std::string folder = makeTempFolder("bad_trajectory");
  const std::string path = folder + "/t.txt";
  writeText(path, "# comment\n1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n");
  EXPECT_EQ(inputErrorOf([&] { vocal::readTumTrajectory(path); }),
            path + ":3: expected 8 fields 'timestamp tx ty tz qx qy qz qw', found 7");
  writeText(path, "1.0 0 0 0 0 0 0 1\n2.0 0 abc 0 0 0 0 1\n");
  EXPECT_EQ(inputErrorOf([&] { vocal::readTumTrajectory(path); }), path + ":2: ty 'abc' is not a finite number");
  writeText(path, "1.0 0 0 0 0 0 0 1\n2.0 0 nan 0 0 0 0 1\n");
  EXPECT_EQ(inputErrorOf([&] { vocal::readTumTrajectory(path); }), path + ":2: ty 'nan' is not a finite number");
  writeText(path, "1.0 0 0 0 0 0 0 1\n\n0.5 0 0 0 0 0 0 1\n");
  EXPECT_EQ(inputErrorOf([&] { vocal::readTumTrajectory(path); }),
            path + ":3: timestamp 0.500000 is not after the previous one (1.000000): stamps must be strictly increasing");
  writeText(path, "1.0 0 0 0 0 0 0 0\n");
  EXPECT_EQ(inputErrorOf([&] { vocal::readTumTrajectory(path); }), path + ":1: quaternion has norm 0.000000, expected 1");
  EXPECT_EQ(inputErrorOf([&] { vocal::readTumTrajectory(folder + "/none.txt"); }),
            folder + "/none.txt: cannot open file (No such file or directory)");
}

TEST(TumImageList, MissingImageNamesTheListLine) {
  const std::string folder = makeTempFolder("image_list");
  writeText(folder + "/a.png", "x");
  writeText(folder + "/rgb.txt", "# rgb\n1.0 a.png\n2.0 b.png\n");
  EXPECT_EQ(inputErrorOf([&] { vocal::readTumImageList(folder + "/rgb.txt", folder); }),
            folder + "/rgb.txt:3: image '" + folder + "/b.png' does not exist");
  writeText(folder + "/rgb.txt", "1.0 a.png extra\n");
  EXPECT_EQ(inputErrorOf([&] { vocal::readTumImageList(folder + "/rgb.txt", folder); }),
            folder + "/rgb.txt:1: expected 2 fields 'timestamp filename', found 3");
  writeText(folder + "/rgb.txt", "2.0 a.png\n1.0 a.png\n");
  EXPECT_NE(inputErrorOf([&] { vocal::readTumImageList(folder + "/rgb.txt", folder); }).find("rgb.txt:2: timestamp 1.000000 is not after"),
            std::string::npos);
}

TEST(TumSequence, EmptySequenceIsAnError) {
  const std::string folder = makeTempFolder("empty_sequence");
  writeText(folder + "/rgb.txt", "# nothing\n");
  writeText(folder + "/depth.txt", "# nothing\n");
  EXPECT_EQ(inputErrorOf([&] { vocal::TumSequence::open(folder); }),
            folder + ": empty sequence: rgb.txt lists 0 images and depth.txt 0, and no pair is within 0.020000 s");
  EXPECT_EQ(inputErrorOf([&] { vocal::TumSequence::open(folder + "/nowhere"); }),
            folder + "/nowhere/rgb.txt: cannot open file (No such file or directory)");
}

TEST(TumSequence, UnreadableImageIsNamedWhenLoaded) {
  const std::string folder = makeTempFolder("unreadable");
  vocal::writeSyntheticSequence(folder, vocal_test::smallSequenceOptions(3));
  const vocal::TumSequence sequence = vocal::TumSequence::open(folder);
  writeText(sequence.entry(1).depth.path, "not a png");
  EXPECT_EQ(inputErrorOf([&] { sequence.loadFrame(1); }),
            sequence.entry(1).depth.path + ": cannot read image (missing file or not an image)");
  // An 8-bit image where 16-bit depth is expected.
  ASSERT_EQ(std::system(("cp '" + sequence.entry(0).rgb.path + "' '" + sequence.entry(2).depth.path + "'").c_str()), 0);
  EXPECT_EQ(inputErrorOf([&] { sequence.loadFrame(2); }),
            sequence.entry(2).depth.path + ": expected a 16-bit single-channel depth image, found 3 channel(s) of 8-bit data");
}

TEST(TumSequence, RealDataOpensWithBenchmarkIntrinsics) {
  const std::string folder = vocal_test::tumDataFolder();
  if (folder.empty()) GTEST_SKIP() << "TUM data not present";
  const vocal::TumSequence sequence = vocal::TumSequence::open(folder);
  EXPECT_GE(sequence.size(), 290u);
  EXPECT_TRUE(sequence.hasGroundTruth());
  EXPECT_DOUBLE_EQ(sequence.camera().fx, 517.3);
  for (const vocal::TumFrameEntry& e : sequence.entries()) {
    EXPECT_LT(std::abs(e.rgb.stamp - e.depth.stamp), 0.02);
  }
  const vocal::RgbdFrame frame = sequence.loadFrame(0);
  EXPECT_EQ(frame.color.width(), 640);
  EXPECT_EQ(frame.depth.height(), 480);
  int valid = 0;
  for (float z : frame.depth.pixels()) valid += vocal::isValidDepth(z) && z > 0.3f && z < 10.0f;
  EXPECT_GT(valid, 640 * 480 / 2);
}

#include "vocal/tools/bag_tool_poses.h"

#include <algorithm>
#include <vector>

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>

#include "vocal/core/errors.h"
#include "vocal/tools/bag_file.h"

namespace vocal {

BagToolPoses readToolPosesFromBag(const std::string& bag_path, const std::string& reference_frame, const std::string& tool_frame,
                                  CalibrationSession* session) {
  rosbag::Bag bag;
  openBag(&bag, bag_path, rosbag::bagmode::Read);
  BagToolPoses summary;
  try {
    rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/tf", "/tf_static"}));
    if (view.size() == 0) {
      throw InputError(bag_path + ": holds no /tf or /tf_static: the pose of '" + tool_frame + "' in " + reference_frame +
                       " comes from tf (record /tf and /tf_static with the camera)");
    }
    // The whole recording's transforms in one buffer: its cache must reach back to the first.
    const double span = (view.getEndTime() - view.getBeginTime()).toSec();
    tf2::BufferCore buffer(ros::Duration(std::max(10.0, span + 10.0)));
    std::vector<ros::Time> stamps;
    for (const rosbag::MessageInstance& m : view) {
      const auto message = m.instantiate<tf2_msgs::TFMessage>();
      if (!message) continue;
      const bool is_static = m.getTopic() == "/tf_static";
      for (const geometry_msgs::TransformStamped& t : message->transforms) {
        buffer.setTransform(t, "bag", is_static);
        if (!is_static) stamps.push_back(t.header.stamp);
      }
    }
    std::sort(stamps.begin(), stamps.end());
    stamps.erase(std::unique(stamps.begin(), stamps.end()), stamps.end());
    for (const ros::Time& stamp : stamps) {
      try {
        const geometry_msgs::TransformStamped t = buffer.lookupTransform(reference_frame, tool_frame, stamp);
        session->addToolPose(stamp.toSec(), tf2::transformToEigen(t));
        ++summary.samples;
      } catch (const tf2::TransformException& e) {
        ++summary.failed_lookups;
        summary.last_failure = e.what();
      }
    }
  } catch (const rosbag::BagException& e) {
    throw InputError(bag_path + ": read failed (" + e.what() + ")");
  }
  if (summary.samples == 0) {
    throw InputError(bag_path + ": the pose of '" + tool_frame + "' in " + reference_frame + " could not be looked up in its /tf" +
                     (summary.last_failure.empty() ? std::string(" (no transform stamped in time)") : ": " + summary.last_failure));
  }
  return summary;
}

}  // namespace vocal

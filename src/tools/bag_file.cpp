#include "vocal/tools/bag_file.h"

#include <sys/stat.h>

#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>

#include "vocal/core/errors.h"
#include "vocal/nodelets/message_conversions.h"

namespace vocal {

void openBag(rosbag::Bag* bag, const std::string& path, rosbag::BagMode mode) {
  try {
    bag->open(path, mode);
  } catch (const rosbag::BagException& e) {
    if (mode == rosbag::bagmode::Write) throw InputError(path + ": cannot open bag for writing (" + e.what() + ")");
    std::string message = path + ": cannot open bag (" + e.what() + ")";
    // A bag whose index is missing: a recording cut off (full disk, rosbag record killed) or still being written.
    struct stat info {};
    if (::stat(path.c_str(), &info) == 0 && info.st_size > 0) {
      message += "; if the recording was cut off, `rosbag reindex " + path + "` recovers the messages it holds";
    }
    throw InputError(message);
  }
}

bool firstUsableCameraInfo(rosbag::Bag& bag, const std::string& topic, PinholeCamera* camera, LensDistortion* lens) {
  rosbag::View infos(bag, rosbag::TopicQuery(topic));
  for (const rosbag::MessageInstance& m : infos) {
    if (const auto info = m.instantiate<sensor_msgs::CameraInfo>()) {
      try {
        *camera = fromCameraInfo(*info, m.getTopic());
        *lens = lensDistortionFromCameraInfo(*info, m.getTopic());
        return true;
      } catch (const InputError&) {
        continue;
      }
    }
  }
  return false;
}

}  // namespace vocal

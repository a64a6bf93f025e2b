#include "vocal/tools/bag_file.h"

#include "vocal/core/errors.h"

namespace vocal {

void openBag(rosbag::Bag* bag, const std::string& path, rosbag::BagMode mode) {
  try {
    bag->open(path, mode);
  } catch (const rosbag::BagException& e) {
    throw InputError(path + (mode == rosbag::bagmode::Write ? ": cannot open bag for writing (" : ": cannot open bag (") + e.what() + ")");
  }
}

}  // namespace vocal

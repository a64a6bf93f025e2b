#include "vocal/tools/still_pose_bag.h"

#include <algorithm>
#include <filesystem>
#include <map>

#include <opencv2/imgcodecs.hpp>
#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>

#include "vocal/core/errors.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"
#include "vocal/core/yaml_file.h"
#include "vocal/nodelets/message_conversions.h"
#include "vocal/tools/bag_file.h"

namespace vocal {

namespace {
namespace fs = std::filesystem;

// NAME -> path of every file in `folder` whose extension is one of `extensions`.
std::map<std::string, std::string> filesByStem(const fs::path& folder, const std::vector<std::string>& extensions) {
  if (!fs::is_directory(folder)) throw InputError(folder.string() + ": no such folder");
  std::map<std::string, std::string> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    std::string extension = entry.path().extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
    if (std::find(extensions.begin(), extensions.end(), extension) != extensions.end())
      files[entry.path().stem().string()] = entry.path().string();
  }
  return files;
}

std::vector<double> numbers(const YAML::Node& node, const std::string& path, const std::string& key, std::size_t count) {
  if (!node || !node.IsSequence() || (count > 0 && node.size() != count)) {
    throw InputError(path + ": '" + key + "' must be a list" + (count > 0 ? " of " + std::to_string(count) + " numbers" : " of numbers"));
  }
  try {
    return node.as<std::vector<double>>();
  } catch (const YAML::Exception&) {
    throw InputError(path + ": '" + key + "' holds something that is not a number");
  }
}

// camera_info.yaml in ROS's layout (camera_matrix: {data}, distortion_coefficients: {data}, image_width)
// or the flat one (K, D, width, height).
sensor_msgs::CameraInfo readCameraInfoYaml(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "camera_info");
  const bool ros_layout = static_cast<bool>(root["camera_matrix"]);
  const YAML::Node k = ros_layout ? root["camera_matrix"]["data"] : root["K"];
  const YAML::Node d = ros_layout ? root["distortion_coefficients"]["data"] : root["D"];
  const YAML::Node width = root[ros_layout ? "image_width" : "width"], height = root[ros_layout ? "image_height" : "height"];
  if (!width || !height) throw InputError(path + ": no image size (" + std::string(ros_layout ? "image_width, image_height" : "width, height") + ")");
  sensor_msgs::CameraInfo info;
  try {
    info.width = width.as<unsigned>();
    info.height = height.as<unsigned>();
  } catch (const YAML::Exception&) {
    throw InputError(path + ": the image size is not two positive integers");
  }
  const std::vector<double> matrix = numbers(k, path, ros_layout ? "camera_matrix.data" : "K", 9);
  std::copy(matrix.begin(), matrix.end(), info.K.begin());
  info.D = numbers(d, path, ros_layout ? "distortion_coefficients.data" : "D", 0);
  info.distortion_model = root["distortion_model"] ? root["distortion_model"].as<std::string>() : "plumb_bob";
  if (info.distortion_model == "fisheye") info.distortion_model = "equidistant";  // OpenCV's name for it
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {info.K[0], info.K[1], info.K[2], 0, info.K[3], info.K[4], info.K[5], 0, 0, 0, 1, 0};
  // What calibrate_rig will make of it, checked now rather than per message.
  fromCameraInfo(info, path);
  lensDistortionFromCameraInfo(info, path);
  return info;
}

sensor_msgs::PointCloud2 readPcd(const std::string& path) {
  pcl::PCLPointCloud2 pcd;
  if (pcl::io::loadPCDFile(path, pcd) != 0) throw InputError(path + ": not a readable PCD file");
  sensor_msgs::PointCloud2 cloud;
  cloud.height = pcd.height;
  cloud.width = pcd.width;
  for (const pcl::PCLPointField& f : pcd.fields) {
    sensor_msgs::PointField field;
    field.name = f.name;
    field.offset = f.offset;
    field.datatype = f.datatype;  // PCL's type codes are sensor_msgs' (INT8 = 1 ... FLOAT64 = 8)
    field.count = f.count;
    cloud.fields.push_back(field);
  }
  cloud.is_bigendian = pcd.is_bigendian;
  cloud.point_step = pcd.point_step;
  cloud.row_step = pcd.row_step;
  cloud.is_dense = pcd.is_dense;
  cloud.data = std::move(pcd.data);
  return cloud;
}

sensor_msgs::Image readMono8(const std::string& path, const sensor_msgs::CameraInfo& info, const std::string& info_name) {
  const cv::Mat grey = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (grey.empty()) throw InputError(path + ": not a readable image");
  if (grey.cols != static_cast<int>(info.width) || grey.rows != static_cast<int>(info.height)) {
    throw InputError(path + ": the image is " + std::to_string(grey.cols) + "x" + std::to_string(grey.rows) + " but " + info_name + " says " +
                     std::to_string(info.width) + "x" + std::to_string(info.height));
  }
  sensor_msgs::Image image;
  image.width = grey.cols;
  image.height = grey.rows;
  image.encoding = sensor_msgs::image_encodings::MONO8;
  image.step = grey.cols;
  image.data.resize(static_cast<std::size_t>(grey.cols) * grey.rows);
  for (int v = 0; v < grey.rows; ++v) std::copy_n(grey.ptr<std::uint8_t>(v), grey.cols, image.data.begin() + static_cast<std::ptrdiff_t>(v) * grey.cols);
  return image;
}
}  // namespace

StillPoseBagSummary writeStillPoseBag(const std::string& folder, const std::string& bag_path, const StillPoseBagOptions& options) {
  if (!(options.still_seconds > 0.0 && options.moving_seconds >= 0.0 && options.camera_rate > 0.0 && options.lidar_rate > 0.0)) {
    throw InputError("still poses: the still time and the rates must be > 0 and the moving time >= 0");
  }
  const fs::path root(folder);
  const std::map<std::string, std::string> images = filesByStem(root / "images", {".jpg", ".jpeg", ".png"});
  const std::map<std::string, std::string> clouds = filesByStem(root / "clouds", {".pcd"});
  for (const auto& [name, path] : images)
    if (!clouds.count(name)) throw InputError(path + ": no cloud of the same pose (" + (root / "clouds" / (name + ".pcd")).string() + ")");
  for (const auto& [name, path] : clouds)
    if (!images.count(name)) throw InputError(path + ": no image of the same pose in " + (root / "images").string());
  std::vector<std::string> names;
  for (const auto& entry : images) names.push_back(entry.first);
  const int first = std::max(0, options.first_pose);
  const int end = options.pose_count < 0 ? static_cast<int>(names.size()) : std::min<int>(names.size(), first + options.pose_count);
  if (first >= end) {
    throw InputError(folder + ": no pose in the range asked for (" + std::to_string(names.size()) + " poses, from " + std::to_string(first) + ")");
  }
  // A stereo pair's second camera, checked whole before anything is written.
  const bool stereo = fs::is_directory(root / "images_right");
  std::map<std::string, std::string> right_images;
  if (stereo) {
    right_images = filesByStem(root / "images_right", {".jpg", ".jpeg", ".png"});
    for (int k = first; k < end; ++k)
      if (!right_images.count(names[k]))
        throw InputError(images.at(names[k]) + ": no right image of the same pose in " + (root / "images_right").string());
  }
  sensor_msgs::CameraInfo info = readCameraInfoYaml((root / "camera_info.yaml").string());
  info.header.frame_id = options.camera_frame;
  sensor_msgs::CameraInfo right_info;
  if (stereo) {
    if (!fs::exists(root / "camera_info_right.yaml"))
      throw InputError((root / "images_right").string() + ": the right camera's images, but no " + (root / "camera_info_right.yaml").string());
    right_info = readCameraInfoYaml((root / "camera_info_right.yaml").string());
    right_info.header.frame_id = options.right_camera_frame;
  }

  rosbag::Bag bag;
  openBag(&bag, bag_path, rosbag::bagmode::Write);
  StillPoseBagSummary summary;
  const double pose_seconds = options.still_seconds + options.moving_seconds;
  try {
    for (int k = first; k < end; ++k) {
      const std::string& name = names[k];
      sensor_msgs::Image image = readMono8(images.at(name), info, "camera_info.yaml");
      sensor_msgs::PointCloud2 cloud = readPcd(clouds.at(name));
      image.header.frame_id = options.camera_frame;
      sensor_msgs::Image right_image;
      if (stereo) {
        right_image = readMono8(right_images.at(name), right_info, "camera_info_right.yaml");
        right_image.header.frame_id = options.right_camera_frame;
      }
      cloud.header.frame_id = options.lidar_frame;
      // The sensors unsynchronised, as on a robot: the lidar 13 ms after the camera.
      const double start = 1000.0 + (k - first) * pose_seconds;
      for (int i = 0; i / options.camera_rate < options.still_seconds - 1e-9; ++i) {
        info.header.stamp = image.header.stamp = ros::Time(start + i / options.camera_rate);
        bag.write(options.camera_info_topic, info.header.stamp, info);
        bag.write(options.image_topic, image.header.stamp, image);
        ++summary.images;
        if (stereo) {  // a stereo pair's cameras are triggered together
          right_info.header.stamp = right_image.header.stamp = image.header.stamp;
          bag.write(options.right_camera_info_topic, right_info.header.stamp, right_info);
          bag.write(options.right_image_topic, right_image.header.stamp, right_image);
          ++summary.right_images;
        }
      }
      for (int i = 0; i / options.lidar_rate < options.still_seconds - 0.013 - 1e-9; ++i) {
        cloud.header.stamp = ros::Time(start + 0.013 + i / options.lidar_rate);
        bag.write(options.cloud_topic, cloud.header.stamp, cloud);
        ++summary.clouds;
      }
      summary.poses.push_back(name);
    }
  } catch (const rosbag::BagException& e) {
    throw InputError(bag_path + ": write failed (" + e.what() + ")");
  }
  bag.close();
  return summary;
}

}  // namespace vocal

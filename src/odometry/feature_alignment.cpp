#include "vocal/odometry/feature_alignment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

namespace vocal {

struct FrameFeatures {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  std::vector<Eigen::Vector3d> points;  // per keypoint; NaN where its depth is missing or on an edge
};

namespace {
cv::Mat grey(const ColorImage& image) {
  cv::Mat out(image.height(), image.width(), CV_8UC1);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) out.at<std::uint8_t>(y, x) = luma8(image(x, y));
  return out;
}

// Corners often sit on an object's outline, where the depth at the rounded pixel may belong to the
// background: such keypoints are skipped (any 3x3 neighbour missing or more than 2 % away).
bool onDepthEdge(const DepthImage& depth, int u, int v) {
  const float z = depth(u, v);
  for (int dv = -1; dv <= 1; ++dv) {
    for (int du = -1; du <= 1; ++du) {
      const int x = u + du, y = v + dv;
      if (x < 0 || y < 0 || x >= depth.width() || y >= depth.height()) return true;
      const float n = depth(x, y);
      if (!isValidDepth(n) || std::abs(n - z) > 0.02f * z) return true;
    }
  }
  return false;
}
}  // namespace

std::shared_ptr<const FrameFeatures> extractFrameFeatures(const RgbdFrame& frame, const PinholeCamera& camera,
                                                          const FeatureAlignmentOptions& options) {
  auto features = std::make_shared<FrameFeatures>();
  cv::Mat image = grey(frame.color);
  int scale = 1;
  while (image.cols > options.max_detection_width) {
    cv::resize(image, image, cv::Size(image.cols / 2, image.rows / 2), 0, 0, cv::INTER_AREA);
    scale *= 2;
  }
  cv::ORB::create(options.max_features)->detectAndCompute(image, cv::noArray(), features->keypoints, features->descriptors);
  // Back to full-resolution pixels: detection pixel u covers full pixels scale*u .. scale*u + scale-1.
  for (cv::KeyPoint& k : features->keypoints) k.pt = k.pt * scale + cv::Point2f(0.5f, 0.5f) * (scale - 1);
  const Eigen::Vector3d missing = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  for (const cv::KeyPoint& k : features->keypoints) {
    const int u = static_cast<int>(std::lround(k.pt.x)), v = static_cast<int>(std::lround(k.pt.y));
    const bool usable = camera.contains(u, v) && isValidDepth(frame.depth(u, v)) && !onDepthEdge(frame.depth, u, v);
    features->points.push_back(usable ? camera.backProject(k.pt.x, k.pt.y, frame.depth(u, v)) : missing);
  }
  return features;
}

FeatureAlignment alignByFeatures(const RgbdFrame& reference, const RgbdFrame& current, const PinholeCamera& camera,
                                 const FeatureAlignmentOptions& options) {
  return alignFrameFeatures(*extractFrameFeatures(reference, camera, options), *extractFrameFeatures(current, camera, options),
                            camera, options);
}

FeatureAlignment alignFrameFeatures(const FrameFeatures& reference, const FrameFeatures& current, const PinholeCamera& camera,
                                    const FeatureAlignmentOptions& options) {
  FeatureAlignment result;
  if (reference.descriptors.empty() || current.descriptors.empty()) return result;
  std::vector<cv::DMatch> matches;
  cv::BFMatcher(cv::NORM_HAMMING, true).match(current.descriptors, reference.descriptors, matches);

  // Reference keypoints lifted to 3D with their depth, paired with the current keypoints in pixels:
  // the motion is fitted on reprojection errors (PnP), so keypoints on depth edges and far away, whose
  // depth is least certain, are not trusted as 3D points on both sides.
  std::vector<cv::Point3d> reference_points;
  std::vector<cv::Point2d> current_pixels;
  for (const cv::DMatch& m : matches) {
    const Eigen::Vector3d& p = reference.points[m.trainIdx];
    if (!p.allFinite()) continue;
    const cv::Point2f pc = current.keypoints[m.queryIdx].pt;
    reference_points.emplace_back(p.x(), p.y(), p.z());
    current_pixels.emplace_back(pc.x, pc.y);
  }
  result.matches = static_cast<int>(reference_points.size());
  if (result.matches < std::max(options.min_inliers, 6)) return result;

  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  cv::Vec3d rvec, tvec;
  std::vector<int> inliers;
  if (!cv::solvePnPRansac(reference_points, current_pixels, K, cv::noArray(), rvec, tvec, false, options.iterations,
                          static_cast<float>(options.max_reprojection_px), 0.999, inliers, cv::SOLVEPNP_EPNP) ||
      inliers.size() < 6) {
    return result;
  }
  // Refined on the inliers by Levenberg-Marquardt on their reprojection errors.
  std::vector<cv::Point3d> inlier_points;
  std::vector<cv::Point2d> inlier_pixels;
  for (int i : inliers) inlier_points.push_back(reference_points[i]), inlier_pixels.push_back(current_pixels[i]);
  cv::solvePnP(inlier_points, inlier_pixels, K, cv::noArray(), rvec, tvec, true, cv::SOLVEPNP_ITERATIVE);
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  Eigen::Isometry3d current_from_reference = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) current_from_reference.linear()(r, c) = R(r, c);
    current_from_reference.translation()[r] = tvec[r];
  }
  result.inliers = static_cast<int>(inliers.size());
  result.found = result.inliers >= options.min_inliers && result.inliers >= options.min_inlier_fraction * result.matches;
  if (result.found) result.reference_from_current = current_from_reference.inverse();
  return result;
}

}  // namespace vocal

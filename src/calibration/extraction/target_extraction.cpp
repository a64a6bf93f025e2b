#include "vocal/calibration/extraction/target_extraction.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>
#include <optional>

#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>
#include <pcl/console/print.h>
#include <pcl/filters/crop_box.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/sac_segmentation.h>

#include "vocal/calibration/extraction/board_outline.h"
#include "vocal/calibration/extraction/lidar_ring_offsets.h"
#include "vocal/calibration/point_statistics.h"
#include "vocal/core/errors.h"

namespace vocal {

namespace {
// The widest gap along a ring counted as covered where a piece's end rings are trimmed again, as a share
// of the board's shorter side: a dark square that returns nothing (squares are under a quarter of the
// board's side on every board seen: 35 / 216, 60 / 700, 61.5 / 615, 95 / 610 mm).
constexpr double kBridgedSquareShare = 0.25;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Indices = std::vector<int>;

std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char text[200];
  std::snprintf(text, sizeof(text), pattern, a, b, c, d);
  return text;
}

Cloud::Ptr toPcl(const std::vector<Eigen::Vector3d>& points, const std::optional<CropBox>& crop) {
  // RANSAC drawing three collinear points is routine here (ring-sampled boards), yet PCL prints it as
  // an error on every draw; what goes wrong is reported by the checks that follow.
  static const bool quiet = [] {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    return true;
  }();
  (void)quiet;
  Cloud::Ptr cloud(new Cloud);
  cloud->reserve(points.size());
  for (const Eigen::Vector3d& p : points) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  if (!crop) return cloud;
  pcl::CropBox<pcl::PointXYZ> box;
  box.setMin(Eigen::Vector4f(crop->min.x(), crop->min.y(), crop->min.z(), 1.0f));
  box.setMax(Eigen::Vector4f(crop->max.x(), crop->max.y(), crop->max.z(), 1.0f));
  box.setInputCloud(cloud);
  Cloud::Ptr cropped(new Cloud);
  box.filter(*cropped);
  return cropped;
}

// The inliers of the model RANSAC finds among `indices` (deterministic: PCL seeds its sampler
// with a constant unless asked not to).
Indices fitModel(const Cloud::Ptr& cloud, const Indices& indices, pcl::SacModel model, double threshold, int iterations) {
  if (indices.size() < 3) return {};
  pcl::SACSegmentation<pcl::PointXYZ> segmentation;
  segmentation.setOptimizeCoefficients(true);
  segmentation.setModelType(model);
  segmentation.setMethodType(pcl::SAC_RANSAC);
  segmentation.setDistanceThreshold(threshold);
  segmentation.setMaxIterations(iterations);
  segmentation.setProbability(0.99);
  segmentation.setInputCloud(cloud);
  segmentation.setIndices(pcl::make_shared<Indices>(indices));
  pcl::PointIndices inliers;
  pcl::ModelCoefficients model_coefficients;
  segmentation.segment(inliers, model_coefficients);
  return inliers.indices;
}

std::vector<Indices> clustersOf(const Cloud::Ptr& cloud, const Indices& indices, double tolerance, int min_size) {
  if (indices.empty()) return {};
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  tree->setInputCloud(cloud, pcl::make_shared<Indices>(indices));
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> extraction;
  extraction.setClusterTolerance(tolerance);
  extraction.setMinClusterSize(min_size);
  extraction.setMaxClusterSize(std::numeric_limits<int>::max());
  extraction.setSearchMethod(tree);
  extraction.setInputCloud(cloud);
  extraction.setIndices(pcl::make_shared<Indices>(indices));
  std::vector<pcl::PointIndices> found;
  extraction.extract(found);
  std::vector<Indices> clusters;
  for (pcl::PointIndices& cluster : found) clusters.push_back(std::move(cluster.indices));
  return clusters;  // largest first
}

// The same on a voxel grid of half the gap (the clusters of the voxels' centroids, mapped back to the
// points): a room's walls hold tens of thousands of points, each with hundreds within a room-sized gap.
std::vector<Indices> coarseClustersOf(const Cloud::Ptr& cloud, const Indices& indices, double gap, int min_size) {
  if (indices.empty()) return {};
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setLeafSize(0.5 * gap, 0.5 * gap, 0.5 * gap);
  grid.setSaveLeafLayout(true);
  grid.setInputCloud(cloud);
  grid.setIndices(pcl::make_shared<Indices>(indices));
  Cloud::Ptr centroids(new Cloud);
  grid.filter(*centroids);
  Indices all(centroids->size());
  std::iota(all.begin(), all.end(), 0);
  std::vector<int> cluster_of(centroids->size(), -1);
  const std::vector<Indices> voxel_clusters = clustersOf(centroids, all, gap, 1);
  for (std::size_t c = 0; c < voxel_clusters.size(); ++c)
    for (int v : voxel_clusters[c]) cluster_of[v] = static_cast<int>(c);
  std::vector<Indices> clusters(voxel_clusters.size());
  for (int i : indices) {
    const int voxel = grid.getCentroidIndex(cloud->at(i));
    if (voxel >= 0 && cluster_of[voxel] >= 0) clusters[cluster_of[voxel]].push_back(i);
  }
  clusters.erase(std::remove_if(clusters.begin(), clusters.end(), [&](const Indices& c) { return static_cast<int>(c.size()) < min_size; }),
                 clusters.end());
  std::sort(clusters.begin(), clusters.end(), [](const Indices& a, const Indices& b) { return a.size() > b.size(); });
  return clusters;
}

Indices without(const Indices& all, Indices removed) {
  std::sort(removed.begin(), removed.end());
  Indices kept;
  for (int i : all)
    if (!std::binary_search(removed.begin(), removed.end(), i)) kept.push_back(i);
  return kept;
}

// A planar segment's shape in its own plane: minimum-area rectangle (longer side first) and hull area,
// the mean range and the cosine between its normal and the viewing ray.
struct Shape {
  Eigen::Vector2d size = Eigen::Vector2d::Zero();
  double area = 0.0, range = 0.0, facing = 1.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // the points' mean (the patch's is its rectangle's)
  std::vector<double> inset;  // per point: its distance inside the minimum-area rectangle's nearest side
  SurfacePatch patch;         // the plane and its minimum-area rectangle

  const Eigen::Vector3d& normal() const { return patch.normal; }
  bool inPlaneOf(const Shape& other, double max_angle, double max_offset) const {
    return std::abs(normal().dot(other.normal())) >= std::cos(max_angle) &&
           std::abs(other.normal().dot(centre - other.centre)) <= max_offset;
  }
};

Shape shapeOf(const Cloud& cloud, const Indices& indices) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i : indices) mean += cloud[i].getVector3fMap().cast<double>();
  mean /= indices.size();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int i : indices) {
    const Eigen::Vector3d d = cloud[i].getVector3fMap().cast<double>() - mean;
    scatter += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  std::vector<cv::Point2f> projected;
  for (int i : indices) {
    const Eigen::Vector3d d = cloud[i].getVector3fMap().cast<double>() - mean;
    projected.emplace_back(static_cast<float>(d.dot(eigen.eigenvectors().col(2))), static_cast<float>(d.dot(eigen.eigenvectors().col(1))));
  }
  Shape shape;
  const cv::RotatedRect rectangle = cv::minAreaRect(projected);
  shape.size = Eigen::Vector2d(std::max(rectangle.size.width, rectangle.size.height), std::min(rectangle.size.width, rectangle.size.height));
  const double c = std::cos(rectangle.angle * M_PI / 180.0), s = std::sin(rectangle.angle * M_PI / 180.0);
  for (const cv::Point2f& p : projected) {
    const double dx = p.x - rectangle.center.x, dy = p.y - rectangle.center.y;
    const double along = c * dx + s * dy, across = -s * dx + c * dy;
    shape.inset.push_back(std::min(0.5 * rectangle.size.width - std::abs(along), 0.5 * rectangle.size.height - std::abs(across)));
  }
  std::vector<cv::Point2f> hull;
  cv::convexHull(projected, hull);
  shape.area = cv::contourArea(hull);
  shape.range = mean.norm();
  shape.facing = std::max(0.05, std::abs(eigen.eigenvectors().col(0).dot(mean.normalized())));
  shape.centre = mean;
  shape.patch.normal = eigen.eigenvectors().col(0);
  shape.patch.centre = mean + rectangle.center.x * eigen.eigenvectors().col(2) + rectangle.center.y * eigen.eigenvectors().col(1);
  shape.patch.along = c * eigen.eigenvectors().col(2) + s * eigen.eigenvectors().col(1);
  shape.patch.half_along = 0.5 * rectangle.size.width;
  shape.patch.half_across = 0.5 * rectangle.size.height;
  return shape;
}

// The piece without points far off its plane: a hand over the board's edge lies a few centimetres in
// front of it, beyond three robust standard deviations of a depth sensor's noise (not of a lidar's).
Indices trimmedToPlane(const Cloud& cloud, const Indices& piece, const Shape& shape) {
  std::vector<double> distances;
  for (int i : piece) distances.push_back(std::abs(shape.normal().dot(cloud[i].getVector3fMap().cast<double>() - shape.centre)));
  const double limit = std::max(0.005, 3.0 * 1.4826 * median(distances));
  Indices kept;
  for (std::size_t k = 0; k < piece.size(); ++k)
    if (distances[k] <= limit) kept.push_back(piece[k]);
  return kept;
}

// How many returns land on `area` square metres facing the sensor at `facing` from `range`.
double expectedReturns(double area, const Shape& shape, const ScanSpacing& spacing) {
  return area * shape.facing / (shape.range * shape.range * spacing.horizontal * spacing.vertical);
}

// Least mismatch first; among equals (a 2D segment between the board's side and diagonal) the one
// with more points, the nearer.
void sortByMismatch(std::vector<TargetCandidate>* candidates) {
  std::stable_sort(candidates->begin(), candidates->end(), [](const TargetCandidate& a, const TargetCandidate& b) {
    return a.mismatch != b.mismatch ? a.mismatch < b.mismatch : a.points.size() > b.points.size();
  });
}

// Candidates in order; a rejection only when there is none (`nothing` when no segment was even checked).
TargetSearch finished(TargetSearch search, const char* nothing) {
  sortByMismatch(&search.candidates);
  if (!search.candidates.empty()) {
    search.rejection.clear(), search.check.clear();
  } else if (search.rejection.empty()) {
    search.rejection = nothing, search.check = "no segment";
  }
  return search;
}

// The points of `piece` inside the width x height rectangle, at any angle and place in the piece's
// plane, that holds the most of them (2 cm steps in place, 3 degrees in angle).
Indices boardRectangleIn(const Cloud& cloud, const Indices& piece, const SurfacePatch& plane, double width, double height) {
  const Eigen::Vector3d u = plane.along, v = plane.normal.cross(plane.along);
  std::vector<Eigen::Vector2d> in_plane;
  for (int i : piece) {
    const Eigen::Vector3d d = cloud[i].getVector3fMap().cast<double>() - plane.centre;
    in_plane.emplace_back(u.dot(d), v.dot(d));
  }
  constexpr double kCell = 0.02;
  constexpr int kAngles = 60;
  const int window_x = static_cast<int>(std::lround(width / kCell)), window_y = static_cast<int>(std::lround(height / kCell));
  int best = -1;
  double best_angle = 0.0;
  Eigen::Vector2d best_corner = Eigen::Vector2d::Zero();
  for (int step = 0; step < kAngles; ++step) {
    const double angle = step * M_PI / kAngles;
    const Eigen::Rotation2Dd rotation(-angle);
    std::vector<Eigen::Vector2d> turned;
    Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    for (const Eigen::Vector2d& p : in_plane) turned.push_back(rotation * p), low = low.cwiseMin(turned.back());
    // Points per cell, then per window from a summed-area table.
    int cells_x = 1, cells_y = 1;
    for (const Eigen::Vector2d& p : turned) {
      cells_x = std::max(cells_x, static_cast<int>((p.x() - low.x()) / kCell) + 1);
      cells_y = std::max(cells_y, static_cast<int>((p.y() - low.y()) / kCell) + 1);
    }
    std::vector<int> table((cells_x + 1) * (cells_y + 1), 0);
    const auto at = [&](int x, int y) -> int& { return table[y * (cells_x + 1) + x]; };
    for (const Eigen::Vector2d& p : turned) ++at(static_cast<int>((p.x() - low.x()) / kCell) + 1, static_cast<int>((p.y() - low.y()) / kCell) + 1);
    for (int y = 1; y <= cells_y; ++y)
      for (int x = 1; x <= cells_x; ++x) at(x, y) += at(x - 1, y) + at(x, y - 1) - at(x - 1, y - 1);
    for (int y0 = 0; y0 <= std::max(0, cells_y - window_y); ++y0)
      for (int x0 = 0; x0 <= std::max(0, cells_x - window_x); ++x0) {
        const int x1 = std::min(cells_x, x0 + window_x), y1 = std::min(cells_y, y0 + window_y);
        const int count = at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0);
        if (count > best) best = count, best_angle = angle, best_corner = low + kCell * Eigen::Vector2d(x0, y0);
      }
  }
  const Eigen::Rotation2Dd rotation(-best_angle);
  Indices inside;
  for (std::size_t k = 0; k < piece.size(); ++k) {
    const Eigen::Vector2d p = rotation * in_plane[k] - best_corner;
    if (p.x() >= 0.0 && p.x() <= width && p.y() >= 0.0 && p.y() <= height) inside.push_back(piece[k]);
  }
  return inside;
}

// The points of `piece` left once its parts narrower than half the board's shorter side are opened
// away in its plane (a morphological opening of its occupancy, cells `spacing` across): a stand's posts
// or a hand's arm in the board's plane go, the board stays whole. None where the cells are too coarse
// to tell a post from the board (a lidar's few rings across a small board).
Indices withoutThinParts(const Cloud& cloud, const Indices& piece, const SurfacePatch& plane, double shortest, double spacing) {
  const double cell = std::max(0.01, spacing);
  const int element = static_cast<int>(std::floor(0.5 * shortest / cell)) | 1;  // odd, cells
  if (element < 3) return {};
  const Eigen::Vector3d u = plane.along, v = plane.normal.cross(plane.along);
  std::vector<Eigen::Vector2d> in_plane;
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (int i : piece) {
    const Eigen::Vector3d d = cloud[i].getVector3fMap().cast<double>() - plane.centre;
    in_plane.emplace_back(u.dot(d), v.dot(d));
    low = low.cwiseMin(in_plane.back()), high = high.cwiseMax(in_plane.back());
  }
  const Eigen::Vector2i cells = ((high - low) / cell).cast<int>() + Eigen::Vector2i::Constant(1);
  if (static_cast<double>(cells.x()) * cells.y() > 4e6) return {};  // tens of metres across: a room surface, not a board on posts
  const auto cellOf = [&](const Eigen::Vector2d& p) { return cv::Point(static_cast<int>((p.x() - low.x()) / cell), static_cast<int>((p.y() - low.y()) / cell)); };
  cv::Mat occupied = cv::Mat::zeros(cells.y(), cells.x(), CV_8U);
  for (const Eigen::Vector2d& p : in_plane) occupied.at<std::uint8_t>(cellOf(p)) = 255;
  // Sampling gaps of a cell closed first, so that the board's own holes do not open it up.
  cv::morphologyEx(occupied, occupied, cv::MORPH_CLOSE, cv::Mat::ones(3, 3, CV_8U));
  cv::morphologyEx(occupied, occupied, cv::MORPH_OPEN, cv::Mat::ones(element, element, CV_8U));
  Indices kept;
  for (std::size_t k = 0; k < piece.size(); ++k)
    if (occupied.at<std::uint8_t>(cellOf(in_plane[k]))) kept.push_back(piece[k]);
  return kept;
}

// The ring of a spinning lidar's (elevations, ascending) nearest a point's elevation.
int nearestRing(const std::vector<double>& rings, const Eigen::Vector3f& p) {
  const double elevation = std::atan2(p.z(), std::hypot(p.x(), p.y()));
  const auto above = std::lower_bound(rings.begin(), rings.end(), elevation);
  std::size_t nearest = std::min<std::size_t>(above - rings.begin(), rings.size() - 1);
  if (nearest > 0 && elevation - rings[nearest - 1] < rings[nearest] - elevation) --nearest;
  return static_cast<int>(nearest);
}

// How many of a spinning lidar's rings hold three or more of `piece`'s points (fewer: strays from a
// neighbouring ring, a mixed pixel).
int ringsUnder(const Cloud& cloud, const Indices& piece, const std::vector<double>& rings) {
  if (rings.empty()) return 0;
  std::vector<int> on_ring(rings.size(), 0);
  for (int i : piece) ++on_ring[nearestRing(rings, cloud[i].getVector3fMap())];
  return static_cast<int>(std::count_if(on_ring.begin(), on_ring.end(), [](int n) { return n >= 3; }));
}

// `piece` without the rings at its top and bottom whose returns cover less than `least_cover` metres
// (gaps of over three beam spacings, or `bridged_gap` metres where wider, left out): a stand's posts or
// legs just behind a small board lie within the plane's threshold of it, and on a spinning lidar they are
// whole rings across the posts' width below the board, which tilt its plane. The piece as it is when
// fewer than three rings would be left.
Indices withoutNarrowEndRings(const Cloud& cloud, const Indices& piece, const ScanSpacing& spacing, double least_cover,
                              double bridged_gap = 0.0) {
  std::map<int, std::vector<std::pair<double, int>>> by_ring;  // ring -> (azimuth, index)
  for (int i : piece) {
    const Eigen::Vector3f p = cloud[i].getVector3fMap();
    by_ring[nearestRing(spacing.rings, p)].emplace_back(std::atan2(p.y(), p.x()), i);
  }
  std::vector<std::pair<int, double>> cover;  // ring, metres covered; rings ascending
  for (auto& [ring, points] : by_ring) {
    if (points.size() < 3) continue;
    std::sort(points.begin(), points.end());
    double covered = 0.0;
    for (std::size_t k = 1; k < points.size(); ++k) {
      const Eigen::Vector3f here = cloud[points[k].second].getVector3fMap();
      const double gap = (cloud[points[k - 1].second].getVector3fMap() - here).norm();
      if (gap <= std::max(3.0 * spacing.horizontal * here.norm(), bridged_gap)) covered += gap;
    }
    cover.emplace_back(ring, covered);
  }
  std::size_t first = 0, last = cover.size();
  while (first < last && cover[first].second < least_cover) ++first;
  while (last > first && cover[last - 1].second < least_cover) --last;
  if (last - first < 3 || (first == 0 && last == cover.size())) return piece;
  Indices kept;
  for (std::size_t r = first; r < last; ++r)
    for (const auto& point : by_ring[cover[r].first]) kept.push_back(point.second);
  std::sort(kept.begin(), kept.end());
  return kept;
}

// The points of `piece` in its dominant plane, trimmed to it (none when it has no plane).
Indices flatPartOf(const Cloud::Ptr& cloud, const Indices& piece, const TargetExtractionOptions& options) {
  const Indices inliers = fitModel(cloud, piece, pcl::SACMODEL_PLANE, options.plane_threshold, options.object_iterations);
  return inliers.size() < 3 ? inliers : trimmedToPlane(*cloud, inliers, shapeOf(*cloud, inliers));
}

void keepBestRejection(double mismatch, const char* check, const std::string& why, double* best, TargetSearch* search) {
  if (mismatch < *best) *best = mismatch, search->rejection = why, search->check = check;
}
}  // namespace

TargetSearch findTargetInCloud(const std::vector<Eigen::Vector3d>& points, double target_width, double target_height,
                               const ScanSpacing& spacing, const TargetExtractionOptions& options) {
  if (!(spacing.horizontal > 0.0 && spacing.vertical > 0.0)) {
    throw InputError("target extraction: the sensor's angular spacing must be > 0 (got " + format("%g x %g rad)", spacing.horizontal, spacing.vertical));
  }
  TargetSearch search;
  const Cloud::Ptr cloud = toPcl(points, options.crop_box);
  if (static_cast<int>(cloud->size()) < options.min_points) {
    search.rejection = format("only %.0f points", cloud->size()) + (options.crop_box ? " inside the crop box" : "");
    search.check = options.crop_box ? "crop box" : "no segment";
    return search;
  }
  const double longest = std::max(target_width, target_height), shortest = std::min(target_width, target_height);
  const double diagonal = std::hypot(target_width, target_height), board_area = target_width * target_height;
  const double widest_gap = std::max(spacing.horizontal, spacing.vertical);
  const auto larger_than_board = [&](const Shape& s) { return s.size[0] > diagonal + options.size_slack || s.size[1] > longest + options.size_slack; };

  // A spinning lidar's piece without the rings at its ends across a stand's posts only. A board whose dark
  // squares absorb has gaps a square wide along its rings, which pass as narrow: too few would be left,
  // nothing goes and the posts' rings stay. So where nothing went, again with those gaps bridged. Only
  // then: bridged always, a clean small board's camera came out 9.8 mrad off the others' board and
  // isolated, and in the room search (an earlier try) board and posts passed for a wall in a third of
  // the messages.
  const auto withoutPostRings = [&](const Indices& piece) {
    const Indices kept = withoutNarrowEndRings(*cloud, piece, spacing, 0.5 * shortest);
    return kept.size() < piece.size() ? kept : withoutNarrowEndRings(*cloud, piece, spacing, 0.5 * shortest, kBridgedSquareShare * shortest);
  };
  // Whether a piece may be a board with thin things in its plane: at most 2.5 m long and 8 board areas
  // (a board on posts down to the floor, an arm holding it), not a room surface.
  const auto mayHoldBoardOnThinParts = [&](const Shape& shape) { return shape.size[0] <= 2.5 && shape.area <= 8.0 * board_area; };
  // Such a piece without its thin things: opened in its plane, or, with too few returns across a post to
  // open it away, without a spinning lidar's rings across the posts only. None when nothing went or too
  // little is left.
  const auto withoutThinThings = [&](const Indices& piece, const Shape& shape) -> Indices {
    if (!mayHoldBoardOnThinParts(shape)) return {};
    Indices opened = withoutThinParts(*cloud, piece, shape.patch, shortest, widest_gap * shape.range);
    // Still larger than the board (posts about as wide as the opening): a spinning lidar's or a scanner's
    // rings across the posts only.
    const auto boardSized = [&](const Indices& rest) {
      return static_cast<int>(rest.size()) >= options.min_points && rest.size() < piece.size() && !larger_than_board(shapeOf(*cloud, rest));
    };
    if (!boardSized(opened) && !spacing.rings.empty()) {
      if (const Indices trimmed = withoutPostRings(piece); trimmed.size() < piece.size()) opened = trimmed;
    }
    if (static_cast<int>(opened.size()) < options.min_points || opened.size() == piece.size()) return {};
    return opened;
  };
  // ... and whether what is left is board-sized.
  const auto boardOnThinParts = [&](const Indices& piece, const Shape& shape) {
    const Indices opened = withoutThinThings(piece, shape);
    if (opened.empty()) return false;
    const Shape rest = shapeOf(*cloud, opened);
    return !larger_than_board(rest) && rest.area >= options.min_area_fraction * board_area && rest.area <= options.max_area_fraction * board_area;
  };

  // Room planes: the connected pieces of a plane larger than the board (floor, walls, ceiling) go;
  // the rest of the plane's points stay (the board's plane crosses the floor and walls).
  Indices remaining(cloud->size());
  std::iota(remaining.begin(), remaining.end(), 0);
  // Pieces of a room's surfaces join across 2.5 times the returns' spacing at 4 m (a VLP-16's rings
  // are 14 cm apart on a wall there).
  const double room_gap = std::clamp(2.5 * widest_gap * 4.0, 0.05, 0.3);
  std::vector<Shape> room_planes;  // a segment in one of these is a piece of floor or wall cut off by something in front
  // Planes without such a piece (the board's, a cabinet's) leave the search, not the cloud.
  Indices unexplained = remaining;
  for (int plane = 0; plane < options.max_room_planes && static_cast<int>(unexplained.size()) >= options.min_points; ++plane) {
    const Indices inliers = fitModel(cloud, unexplained, pcl::SACMODEL_PLANE, options.room_threshold, options.room_iterations);
    if (static_cast<int>(inliers.size()) < options.min_points) break;
    Indices room;
    for (const Indices& piece : coarseClustersOf(cloud, inliers, room_gap, options.min_points)) {
      const Shape shape = shapeOf(*cloud, piece);
      // Far larger than the board - far longer and not thin, or twice its area: not a strip where another
      // plane (the board's) crosses the floor, nor the board with the hands and arms that hold it.
      const bool far_longer = shape.size[0] > 1.5 * diagonal && shape.size[1] > 0.5 * shortest;
      if (!far_longer && shape.area <= 2.0 * board_area) continue;
      if (boardOnThinParts(piece, shape)) continue;  // a small board on its stand's posts: for the object search
      room.insert(room.end(), piece.begin(), piece.end());
      room_planes.push_back(shape);
      search.surfaces.push_back(shape.patch);
    }
    unexplained = without(unexplained, inliers);
    if (room.empty()) continue;
    remaining = without(remaining, room);
    if (!spacing.rings.empty()) {
      search.room_points.emplace_back();
      for (int i : room) search.room_points.back().push_back(cloud->at(i).getVector3fMap().cast<double>());
    }
  }

  // Objects left (the board with whoever holds it, furniture): planes in each, each plane's pieces checked.
  double best_rejected = std::numeric_limits<double>::infinity();
  // A plane's piece judged against the board: its shape, how unlike the board it is, and why it is
  // refused (nothing: a candidate).
  struct Judged {
    Shape shape;
    double mismatch = 0.0;
    std::string why;
    const char* check = "";
    bool larger = false;  // refused as larger than the board
  };
  const auto judge = [&](const Indices& piece, double penalty) {
    Judged judged;
    judged.shape = shapeOf(*cloud, piece);
    const Shape& shape = judged.shape;
    const double expected = expectedReturns(board_area, shape, spacing);
    judged.mismatch = penalty + std::abs(std::log(std::max(shape.area, 1e-6) / board_area)) +
                      std::abs(std::log(std::max(shape.size[0], 1e-3) / longest)) +
                      std::abs(std::log(std::max(shape.size[1], 1e-3) / shortest)) +
                      std::abs(std::log(static_cast<double>(piece.size()) / std::max(expected, 1.0)));
    const double expected_here = expectedReturns(shape.area, shape, spacing);
    const auto room_plane = std::find_if(room_planes.begin(), room_planes.end(), [&](const Shape& room) {
      return shape.inPlaneOf(room, 5.0 * M_PI / 180.0, options.room_threshold);
    });
    if (room_plane != room_planes.end()) {
      judged.check = "floor or wall";
      judged.why = format("a %.2f x %.2f m segment lies in the plane of a %.1f x %.1f m surface (floor or wall)", shape.size[0],
                          shape.size[1], room_plane->size[0], room_plane->size[1]);
    } else if (larger_than_board(shape) || shape.area > options.max_area_fraction * board_area) {
      judged.larger = true;
      judged.check = "larger than the board";
      judged.why = format("a %.2f x %.2f m segment is larger than the %.2f x %.2f m board", shape.size[0], shape.size[1], longest, shortest);
    } else if (const int rings = ringsUnder(*cloud, piece, spacing.rings); !spacing.rings.empty() && rings < options.min_rings) {
      judged.check = "too few rings";
      judged.why = format("a %.2f x %.2f m segment lies on %.0f of the lidar's rings, under the %.0f that fix a board's plane "
                          "(hold the board nearer, or use a larger one)", shape.size[0], shape.size[1], rings, options.min_rings);
    } else if (shape.area < options.min_area_fraction * board_area) {
      judged.check = "smaller than the board";
      judged.why = format("a %.2f x %.2f m segment (%.3f m^2) is under %.2f of the board's area", shape.size[0], shape.size[1],
                          shape.area, options.min_area_fraction);
    } else if (piece.size() < options.min_density_fraction * expected_here) {
      judged.check = "too few points";
      judged.why = format("a board-sized segment has %.0f points where the sensor's spacing predicts %.0f", piece.size(), expected_here);
    } else if (piece.size() > options.max_count_fraction * expected) {
      judged.check = "too many points";
      judged.why = format("a board-sized segment has %.0f points, more than the %.0f the whole board would give", piece.size(), expected);
    }
    return judged;
  };
  // A candidate: the piece's points without a margin along the outline, where hands hold the board
  // and a beam's footprint mixes it with what is behind.
  const auto take = [&](const Indices& piece, const Judged& judged, bool with_outline) {
    const Shape& shape = judged.shape;
    std::vector<Eigen::Vector3d> whole;
    for (int i : piece) whole.push_back(cloud->at(i).getVector3fMap().cast<double>());
    TargetCandidate candidate;
    for (std::size_t k = 0; k < piece.size(); ++k)
      if (shape.inset[k] >= options.edge_margin) candidate.points.push_back(whole[k]);
    if (with_outline) candidate.outline = boardOutlinePoints(whole, Plane{shape.normal(), -shape.normal().dot(shape.centre)}, spacing);
    if (static_cast<int>(candidate.points.size()) < options.min_points) candidate.points = std::move(whole);
    candidate.mismatch = judged.mismatch;
    search.candidates.push_back(std::move(candidate));
  };
  // The board-sized rectangle holding most of a piece's points, on its own plane (the piece's leans
  // towards what joined the board in it: a chest a hand's width behind), judged with the share of the
  // piece it leaves out as a penalty; nothing when it holds under min_held_share of the piece or is
  // refused. Its outline is not the board's all round (where the chest joined), so it gives none.
  const auto cutOut = [&](const Indices& piece, const Shape& shape) -> std::optional<std::pair<Indices, Judged>> {
    const Indices window = boardRectangleIn(*cloud, piece, shape.patch, longest, shortest);
    const Indices board = flatPartOf(cloud, window, options);
    if (board.size() < options.min_held_share * piece.size() || static_cast<int>(board.size()) < options.min_points) return std::nullopt;
    Judged cut = judge(board, std::log(static_cast<double>(piece.size()) / board.size()));
    if (!cut.why.empty()) return std::nullopt;
    return std::make_pair(board, std::move(cut));
  };
  // A board-sized piece larger and squarer than the board (the board with the chest behind it) gives
  // the board cut out of it when that is more board-like. A piece larger than the board but no longer
  // than its diagonal (the board with the arms or chest in its plane; not a long piece of furniture)
  // gives the cut-out if there is one. A piece refused as larger is a surface for the background model.
  const auto examine = [&](const Indices& found) {
    const Indices piece = spacing.rings.empty() ? found : withoutPostRings(found);
    const Judged judged = judge(piece, 0.0);
    const Shape& shape = judged.shape;
    if (judged.why.empty()) {
      if (shape.area > options.max_whole_area_fraction * board_area && shape.size[1] > shortest + 0.5 * options.size_slack) {
        const auto cut = cutOut(piece, shape);
        if (cut && cut->second.mismatch < judged.mismatch) return take(cut->first, cut->second, false);
      }
      return take(piece, judged, true);
    }
    if (judged.larger && shape.size[0] <= diagonal + options.size_slack && shape.area <= options.max_held_area_fraction * board_area) {
      if (const auto cut = cutOut(piece, shape)) return take(cut->first, cut->second, false);
    }
    if (judged.larger) {
      // The board with thin things in its plane (a stand's posts, an arm): what is left without them,
      // when that is the board. Else a surface for the background model.
      if (const Indices opened = withoutThinThings(piece, shape); !opened.empty()) {
        const Judged board = judge(opened, std::log(static_cast<double>(piece.size()) / opened.size()));
        if (board.why.empty()) return take(opened, board, false);
      }
      search.surfaces.push_back(shape.patch);
    }
    keepBestRejection(judged.mismatch, judged.check, judged.why, &best_rejected, &search);
  };
  for (const Indices& object : coarseClustersOf(cloud, remaining, room_gap, options.min_points)) {
    Indices left = object;
    for (int plane = 0; plane < options.max_planes_per_object && static_cast<int>(left.size()) >= options.min_points; ++plane) {
      const Indices inliers = fitModel(cloud, left, pcl::SACMODEL_PLANE, options.plane_threshold, options.object_iterations);
      if (static_cast<int>(inliers.size()) < options.min_points) break;
      left = without(left, inliers);
      double farthest = 0.0;
      for (int i : inliers) farthest = std::max(farthest, static_cast<double>(cloud->at(i).getVector3fMap().norm()));
      // Neighbours on the board lie up to one ring (row) apart, more where the board is tilted away.
      const double gap = std::clamp(2.0 * widest_gap * farthest, 0.04, 0.3);
      for (const Indices& found : clustersOf(cloud, inliers, gap, options.min_points)) {
        const Indices piece = trimmedToPlane(*cloud, found, shapeOf(*cloud, found));
        if (static_cast<int>(piece.size()) >= options.min_points) examine(piece);
      }
    }
  }
  return finished(std::move(search), "no plane is left once the room's are removed");
}

TargetSearch findTargetInScan(const std::vector<Eigen::Vector3d>& scan, double target_width, double target_height,
                              double beam_spacing, const TargetExtractionOptions& options) {
  if (!(beam_spacing > 0.0)) throw InputError("target extraction: the scan's beam spacing must be > 0 (got " + format("%g rad)", beam_spacing));
  TargetSearch search;
  const Cloud::Ptr cloud = toPcl(scan, options.crop_box);
  const double diagonal = std::hypot(target_width, target_height), shortest = std::min(target_width, target_height);
  constexpr int kMinSegmentPoints = 10;
  const auto point = [&](int i) { return cloud->at(i).getVector3fMap().cast<double>(); };
  const auto neighbours = [&](int a, int b) {
    return (point(a) - point(b)).norm() <= std::max(0.1, 4.0 * beam_spacing * std::max(point(a).norm(), point(b).norm()));
  };
  // Pieces of the scan between range jumps (beam order), then straight runs in each by RANSAC lines.
  std::vector<Indices> pieces(1);
  for (int i = 0; i < static_cast<int>(cloud->size()); ++i) {
    if (!pieces.back().empty() && !neighbours(pieces.back().back(), i)) pieces.emplace_back();
    pieces.back().push_back(i);
  }
  struct Run {
    Indices points;
    Eigen::Vector3d first, last;
    double length() const { return (last - first).norm(); }
  };
  std::vector<Run> runs;
  for (const Indices& piece : pieces) {
    Indices left = piece;
    for (int line = 0; line < options.max_planes_per_object && static_cast<int>(left.size()) >= kMinSegmentPoints; ++line) {
      Indices inliers = fitModel(cloud, left, pcl::SACMODEL_LINE, options.plane_threshold, options.object_iterations);
      if (static_cast<int>(inliers.size()) < kMinSegmentPoints) break;
      std::sort(inliers.begin(), inliers.end());
      left = without(left, inliers);
      Indices run;
      const auto close = [&] {
        if (static_cast<int>(run.size()) >= kMinSegmentPoints) runs.push_back({run, point(run.front()), point(run.back())});
        run.clear();
      };
      for (int i : inliers) {
        // Split where points off the line lie between (something in front; a lone one is noise) or
        // neighbours are far apart.
        const bool skipped = !run.empty() && std::count_if(left.begin(), left.end(), [&](int j) { return j > run.back() && j < i; }) > 1;
        if (!run.empty() && (skipped || !neighbours(run.back(), i))) close();
        run.push_back(i);
      }
      close();
    }
  }
  // A run longer than the board is a wall's; shorter runs on its line are pieces of that wall between
  // things in front of it.
  std::vector<std::pair<const Run*, SurfacePatch>> walls;
  for (const Run& run : runs) {
    if (run.length() <= diagonal + options.size_slack) continue;
    SurfacePatch wall;
    wall.along = (run.last - run.first).normalized();
    wall.normal = Eigen::Vector3d(-wall.along.y(), wall.along.x(), 0.0);
    wall.centre = 0.5 * (run.first + run.last);
    wall.half_along = 0.5 * run.length();
    walls.emplace_back(&run, wall);
    search.surfaces.push_back(wall);
  }
  const auto on_wall = [&](const Run& run) {
    return std::any_of(walls.begin(), walls.end(), [&](const std::pair<const Run*, SurfacePatch>& wall) {
      const SurfacePatch& line = wall.second;
      return wall.first != &run && std::abs(line.normal.dot(run.first - line.centre)) < options.plane_threshold &&
             std::abs(line.normal.dot(run.last - line.centre)) < options.plane_threshold;
    });
  };
  double best_rejected = std::numeric_limits<double>::infinity();
  for (const Run& run : runs) {
    const double length = run.length();
    const double mismatch = length > diagonal ? std::log(length / diagonal) : length < shortest ? std::log(shortest / length) : 0.0;
    const Eigen::Vector3d middle = 0.5 * (run.first + run.last), along = (run.last - run.first).normalized();
    const double facing = std::max(0.05, std::sqrt(std::max(0.0, 1.0 - std::pow(along.dot(middle.normalized()), 2))));
    const double expected_here = length * facing / (middle.norm() * beam_spacing);
    std::string why;
    const char* check = "";
    if (length > diagonal + options.size_slack) {
      check = "larger than the board";
      why = format("a %.2f m segment is longer than the board's %.2f m diagonal", length, diagonal);
    } else if (on_wall(run)) {
      check = "floor or wall";
      why = format("a %.2f m segment lies on the line of a longer one (a wall)", length);
    } else if (length < 0.5 * shortest) {
      check = "smaller than the board";
      why = format("a %.2f m segment is shorter than half the board's %.2f m side", length, shortest);
    } else if (run.points.size() < options.min_density_fraction * expected_here) {
      check = "too few points";
      why = format("a board-sized segment has %.0f points where the beam spacing predicts %.0f", run.points.size(), expected_here);
    }
    if (!why.empty()) {
      keepBestRejection(mismatch, check, why, &best_rejected, &search);
      continue;
    }
    // As in 3D: without points far off the run's line (hands over the board's ends, mixed pixels). The
    // line is the run's middle's: a hand at an end would tilt the line through the run's end points
    // towards itself and pass as on it.
    const auto fromEnds = [&](int i) { return std::min(along.dot(point(i) - run.first), along.dot(run.last - point(i))); };
    std::vector<Eigen::Vector3d> middle_points;
    for (int i : run.points)
      if (fromEnds(i) >= options.edge_margin) middle_points.push_back(point(i));
    Eigen::Vector3d across(-along.y(), along.x(), 0.0), on_middle = run.first;
    if (middle_points.size() >= 2) {
      const PrincipalAxes line = principalAxesOf(middle_points);
      across = Eigen::Vector3d(-line.axes(1, 0), line.axes(0, 0), 0.0).normalized();
      on_middle = line.centroid;
    }
    std::vector<double> distances;
    for (int i : run.points) distances.push_back(std::abs(across.dot(point(i) - on_middle)));
    const double limit = std::max(0.005, 3.0 * 1.4826 * median(distances));
    TargetCandidate candidate;
    for (std::size_t k = 0; k < run.points.size(); ++k)
      if (distances[k] <= limit && fromEnds(run.points[k]) >= options.edge_margin) candidate.points.push_back(point(run.points[k]));
    if (static_cast<int>(candidate.points.size()) < kMinSegmentPoints) continue;
    // The run's ends on the board's edges, unless the beam beyond an end hit something nearer (a hand
    // over the edge hides where it is).
    std::vector<Eigen::Vector3d> on_line;
    for (std::size_t k = 0; k < run.points.size(); ++k)
      if (distances[k] <= limit) on_line.push_back(point(run.points[k]));
    const std::vector<Eigen::Vector3d> ends =
        boardOutlinePoints(on_line, Plane{across, -across.dot(on_middle)}, ScanSpacing{beam_spacing, 0.0, ScanPattern::kSpinning});
    const auto hidden = [&](int end, int beyond) {
      return beyond >= 0 && beyond < static_cast<int>(cloud->size()) && point(beyond).norm() < point(end).norm() - options.plane_threshold;
    };
    // A run that goes on past the board's end off its line for two beams or more (a hand round the
    // edge; a mixed pixel is one) hides where the edge is.
    const auto offLineAtEnd = [&](bool front) {
      int count = 0;
      for (std::size_t k = 0; k < run.points.size() && distances[front ? k : run.points.size() - 1 - k] > limit; ++k) ++count;
      return count >= 2;
    };
    if (ends.size() == 2) {
      const int front = run.points.front(), back = run.points.back();
      if (!hidden(front, front - 1) && !offLineAtEnd(true)) candidate.outline.push_back(ends[0]);
      if (!hidden(back, back + 1) && !offLineAtEnd(false)) candidate.outline.push_back(ends[1]);
    }
    candidate.mismatch = mismatch;
    search.candidates.push_back(std::move(candidate));
  }
  return finished(std::move(search), "no straight segment of 10 points or more");
}

namespace {
// The azimuth steps (radians, ascending) between neighbouring returns of a cloud within `within` of
// elevation `band`: a ring's or a scan band's.
std::vector<double> azimuthStepsAlong(const std::vector<Eigen::Vector3d>& cloud, double band, double within) {
  std::vector<double> azimuths, steps;
  for (const Eigen::Vector3d& p : cloud)
    if (std::abs(std::atan2(p.z(), p.head<2>().norm()) - band) < within) azimuths.push_back(std::atan2(p.y(), p.x()));
  std::sort(azimuths.begin(), azimuths.end());
  for (std::size_t i = 1; i < azimuths.size(); ++i)
    if (azimuths[i] - azimuths[i - 1] > 1e-5) steps.push_back(azimuths[i] - azimuths[i - 1]);
  std::sort(steps.begin(), steps.end());
  return steps;
}
}  // namespace

ScanSpacing estimateScanSpacing(const std::vector<Eigen::Vector3d>& cloud) {
  ScanSpacing spacing;
  if (cloud.size() < 10) return spacing;
  // A spinning lidar: elevations fall into a few rings.
  const std::vector<LidarRing> rings = lidarRingsOf(cloud);
  if (rings.size() <= 128 && rings.size() >= 2 && cloud.size() / rings.size() >= 50) {
    std::vector<double> gaps, steps;
    for (std::size_t r = 1; r < rings.size(); ++r) gaps.push_back(rings[r].elevation - rings[r - 1].elevation);
    spacing.vertical = median(gaps);
    // Azimuth steps within the ring with the most points.
    const double ring = std::max_element(rings.begin(), rings.end(), [](const LidarRing& a, const LidarRing& b) { return a.returns < b.returns; })->elevation;
    steps = azimuthStepsAlong(cloud, ring, 0.1 * M_PI / 180.0);
    spacing.horizontal = median(steps);
    if (spacing.horizontal > 0.0) {
      for (const LidarRing& r : rings)
        if (r.returns >= 20) spacing.rings.push_back(r.elevation);  // a stray return's elevation is no ring
      return spacing;
    }
  }
  // Dense (a depth camera): the angle to each point's nearest neighbour, seen from the sensor.
  const Cloud::Ptr directions(new Cloud);
  for (const Eigen::Vector3d& p : cloud) {
    const Eigen::Vector3d d = p.normalized();
    directions->push_back(pcl::PointXYZ(d.x(), d.y(), d.z()));
  }
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(directions);
  std::vector<double> angles;
  std::vector<int> found(2);
  std::vector<float> distances(2);
  for (std::size_t i = 0; i < directions->size(); i += std::max<std::size_t>(1, directions->size() / 2000)) {
    if (tree.nearestKSearch(directions->at(i), 2, found, distances) == 2 && distances[1] > 0.0f) angles.push_back(std::sqrt(distances[1]));
  }
  spacing.horizontal = spacing.vertical = median(angles);
  spacing.pattern = ScanPattern::kScattered;
  // A non-repeating pattern (a Livox's rosette) lays its points along curves: the nearest neighbour is
  // close along the curve, the next curve far. What predicts a board's returns is the mean density over
  // the solid angle the cloud covers (2-degree cells holding 2 or more returns).
  constexpr double kCell = 2.0 * M_PI / 180.0;
  std::map<std::pair<int, int>, int> cells;
  for (const Eigen::Vector3d& p : cloud) {
    const double elevation = std::atan2(p.z(), p.head<2>().norm()), azimuth = std::atan2(p.y(), p.x());
    ++cells[{static_cast<int>(std::floor(azimuth / kCell)), static_cast<int>(std::floor(elevation / kCell))}];
  }
  double solid_angle = 0.0, covered = 0.0;
  for (const auto& [cell, count] : cells) {
    if (count < 2) continue;
    solid_angle += kCell * (std::sin((cell.second + 1) * kCell) - std::sin(cell.second * kCell));
    covered += count;
  }
  const double mean_spacing = covered > 0.0 ? std::sqrt(solid_angle / covered) : 0.0;
  if (mean_spacing > 1.5 * spacing.horizontal) spacing.horizontal = spacing.vertical = mean_spacing;
  return spacing;
}

std::vector<double> elevationBandsOf(const std::vector<Eigen::Vector3d>& cloud, std::size_t least_returns) {
  std::vector<double> elevations;
  elevations.reserve(cloud.size());
  for (const Eigen::Vector3d& p : cloud) elevations.push_back(std::atan2(p.z(), p.head<2>().norm()));
  std::sort(elevations.begin(), elevations.end());
  // Runs of elevations without a gap of over 0.05 degrees: a band (range noise lies along the beams and
  // leaves a band's elevation as it is); a pattern without bands runs on.
  constexpr double kWithinBand = 0.05 * M_PI / 180.0;
  std::vector<double> bands, widths;
  std::size_t in_bands = 0;
  for (std::size_t i = 0; i < elevations.size();) {
    std::size_t j = i + 1;
    while (j < elevations.size() && elevations[j] - elevations[j - 1] <= kWithinBand) ++j;
    if (j - i >= least_returns) {
      bands.push_back(std::accumulate(elevations.begin() + i, elevations.begin() + j, 0.0) / (j - i));
      widths.push_back(elevations[j - 1] - elevations[i]);
      in_bands += j - i;
    }
    i = j;
  }
  // Nearly every return on a band (a few strays: mixed pixels); a pattern without bands leaves many in
  // runs too short to count.
  if (bands.size() < 3 || in_bands < 0.9 * elevations.size()) return {};
  std::vector<double> gaps;
  for (std::size_t b = 1; b < bands.size(); ++b) gaps.push_back(bands[b] - bands[b - 1]);
  // Bands are what a scan's sweeps make only where they are far narrower than the gaps between them.
  if (!(median(widths) < 0.25 * median(gaps))) return {};
  return bands;
}

ScanSpacing estimateCroppedScanSpacing(const std::vector<Eigen::Vector3d>& cloud) {
  ScanSpacing spacing;
  const std::vector<double> bands = elevationBandsOf(cloud);
  if (bands.empty()) return spacing;
  std::vector<double> gaps;
  for (std::size_t b = 1; b < bands.size(); ++b) gaps.push_back(bands[b] - bands[b - 1]);
  // The smallest gaps are neighbouring bands; a band the crop or an absorbing square emptied doubles one.
  std::sort(gaps.begin(), gaps.end());
  gaps.resize((gaps.size() + 1) / 2);
  const double vertical = median(gaps);
  // Azimuth steps along the band with the most returns.
  std::vector<int> returns(bands.size(), 0);
  for (const Eigen::Vector3d& p : cloud) {
    const double elevation = std::atan2(p.z(), p.head<2>().norm());
    const auto nearest =
        std::min_element(bands.begin(), bands.end(), [&](double a, double b) { return std::abs(a - elevation) < std::abs(b - elevation); });
    if (std::abs(*nearest - elevation) < 0.25 * vertical) ++returns[nearest - bands.begin()];
  }
  const double fullest = bands[std::max_element(returns.begin(), returns.end()) - returns.begin()];
  std::vector<double> steps = azimuthStepsAlong(cloud, fullest, 0.25 * vertical);
  if (steps.empty()) return spacing;
  // Neighbouring returns: the smaller half of the steps (an absorbing square leaves gaps along the band).
  steps.resize((steps.size() + 1) / 2);
  spacing.horizontal = median(steps);
  spacing.vertical = vertical;
  spacing.rings = bands;
  spacing.rings_per_cloud = true;
  return spacing;
}

std::vector<Eigen::Vector3d> extractTargetPoints(const std::vector<Eigen::Vector3d>& cloud, double target_width,
                                                 double target_height, const TargetExtractionOptions& options) {
  const ScanSpacing spacing = estimateScanSpacing(cloud);
  if (!(spacing.horizontal > 0.0)) return {};
  TargetSearch search = findTargetInCloud(cloud, target_width, target_height, spacing, options);
  return search.candidates.empty() ? std::vector<Eigen::Vector3d>{} : std::move(search.candidates.front().points);
}

std::vector<Eigen::Vector3d> extractTargetSegment(const std::vector<Eigen::Vector3d>& scan, double target_width,
                                                  double target_height, double beam_spacing,
                                                  const TargetExtractionOptions& options) {
  TargetSearch search = findTargetInScan(scan, target_width, target_height, beam_spacing, options);
  return search.candidates.empty() ? std::vector<Eigen::Vector3d>{} : std::move(search.candidates.front().points);
}

}  // namespace vocal

#pragma once
// A spinning lidar's range offset per ring: what its factory calibration leaves, a few centimetres on
// a VLP-16, the same for every return of one laser. A board held at about one distance cannot tell
// these offsets from the extrinsic: their trend over elevation leans the board as the lidar's pitch
// would, and a ring's own offset tilts a plane fitted to the 4-8 rings on the board. The room can: a
// wall or the floor seen over a wide azimuth is flat, and ranges offset along each ray bend it in a
// way no plane takes up. So the room planes that extraction finds in every cloud anyway (floor, walls,
// large furniture) add to one least-squares problem in the offsets, each plane's own pose eliminated,
// and the board's points are moved back along their rays before the calibration.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace vocal {

// A ring of returns at one elevation (radians above the lidar's xy plane) and how many returns it holds.
struct LidarRing {
  double elevation = 0.0;
  std::size_t returns = 0;
};

// The rings of a spinning lidar's cloud, by ascending elevation: returns within 0.2 degrees of a ring's
// lowest join it. A dense cloud (a depth camera) gives many rings of a few returns each.
std::vector<LidarRing> lidarRingsOf(const std::vector<Eigen::Vector3d>& cloud);

struct RingOffsetOptions {
  bool enabled = true;
  // Prior on each offset (metres; a VLP-16's range accuracy is +-3 cm): a ring the room does not show
  // (a rig whose crop box leaves little of the room) keeps an offset near zero, not an arbitrary one.
  double prior_sigma = 0.03;
  std::size_t min_plane_points = 200;  // a plane with fewer returns adds nothing
  // Metres from another of the cloud's planes within which a plane's returns are left out: where walls
  // meet, the other wall's returns lie inside the plane's RANSAC band, off its plane at wide angles -
  // what a range offset common to all rings would look like.
  double corner_margin = 0.1;
  // A plane whose returns meet it at a median |cosine| (ray to normal) below this is left out: the
  // offsets move its returns almost within it, and a real scan's near-level rings each lie on a cone so
  // flat that RANSAC takes it for a plane through the lidar (on the office VLP-16 such "planes" alone
  // asked for +1.5 to +5.9 m).
  double min_incidence = 0.2;
  // Metres: a lidar's range specification (a VLP-16's range accuracy is +-3 cm). Offsets beyond it are
  // not applied on the room's word alone: either the room's planes do not fit the model (bent or
  // cluttered walls) or the driver's calibration is off; only the board can tell (CalibrationSession::
  // chooseRingOffsets), and when it agrees they are applied with a warning naming the driver's calibration.
  double max_offset = 0.03;
  double plane_agreement = 0.015;  // metres: a plane's own offset this close to the median agrees
};

struct RingOffsets {
  std::vector<double> elevations;  // radians, ascending
  double spacing = 0.0;            // radians between neighbouring rings (median)
  Eigen::VectorXd offsets;         // metres each ring's ranges read too long (negative: too short)
  Eigen::VectorXd sigmas;          // their standard deviations
  int planes = 0;                  // room planes they were estimated from
  std::size_t returns = 0;         // ... holding this many returns
  double rms = 0.0;                // metres: the returns' distance to their planes once corrected
  double rms_as_measured = 0.0;    // ... and with no offsets (each plane refitted): what the offsets explain
  // The planes one by one: each plane's own estimate of one offset all rings share (where its returns'
  // incidence varies enough to tell it from the plane's shift), their median weighted by that
  // information, and the share of the information within RingOffsetOptions::plane_agreement of it. A
  // lidar whose ranges all read long bends every flat surface alike; bent or cluttered walls each
  // ask for their own.
  double common_offset = 0.0;
  double planes_agreeing = 0.0;  // 0..1
  double agreement = 0.0;        // RingOffsetOptions::plane_agreement
  int grazing_planes = 0;          // planes left out as seen only at grazing incidence
  // Whether the board's returns are corrected by them, and why (or why not), in words for the user.
  // Within RingOffsetOptions::max_offset they are applied until CalibrationSession::chooseRingOffsets
  // has tried them on held-out board poses; beyond it they wait for that trial (applied = false,
  // beyond_specification = true) and, applied then, come with `warning`.
  bool applied = false;
  bool estimated = false;             // from room planes (false: zeros, and the verdict says why)
  bool beyond_specification = false;  // an offset beyond RingOffsetOptions::max_offset
  double specification = 0.0;         // that bound, metres
  std::string verdict;
  std::string warning;  // applied beyond the specification: the driver's calibration named

  // The offsets in a few words: "+50.0 to +50.4 mm".
  std::string range() const;

  // The ring whose elevation is nearest the point's, -1 when none lies within half the rings' spacing.
  int ringOf(const Eigen::Vector3d& point) const;
  // The point moved back along its ray by its ring's offset (unchanged when it is in no ring).
  Eigen::Vector3d corrected(const Eigen::Vector3d& point) const;
};

class RingOffsetEstimator {
 public:
  // Throws InputError for fewer than 2 rings (not a spinning lidar).
  explicit RingOffsetEstimator(std::vector<double> elevations, RingOffsetOptions options = {});

  // One static plane's returns (sensor frame). Linearised once about the plane fitted to them as
  // measured: the offsets are centimetres, the planes metres across.
  void addPlane(const std::vector<Eigen::Vector3d>& points);
  // One cloud's static planes (TargetSearch::room_points), each without its returns near the others.
  void addPlanes(const std::vector<std::vector<Eigen::Vector3d>>& planes);
  RingOffsets solve() const;

 private:
  RingOffsets rings_;  // elevations, for ringOf
  RingOffsetOptions options_;
  // The offsets' normal equations with each plane's tilt and distance eliminated (Schur complement),
  // and what is left of the squared residuals once the planes are fitted.
  Eigen::MatrixXd normal_;
  Eigen::VectorXd gradient_;
  double residual_squares_ = 0.0;
  // Each plane's own common offset, its information summed in 1 mm bins over +-1 m (the ends take what
  // lies beyond): RingOffsets::common_offset, bounded however long a live session runs.
  std::vector<double> plane_offset_information_;
  int planes_ = 0;
  int grazing_planes_ = 0;
  std::size_t returns_ = 0;
};

}  // namespace vocal

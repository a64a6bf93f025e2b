#pragma once
// The room a simulated calibration session happens in, for ray casting: what each range ray or camera
// pixel hits, labelled, so tests can count what target extraction took against the truth.
//   plain:     the floor (z = 0 of the rig frame) and one wall (x = 4.5 m) behind the target.
//   furnished: a closed room (walls all round, ceiling), a cabinet whose front is the target's size, a
//              table, a shelf and a sofa - static surfaces a plane extractor can take for the board -
//              and optionally a person holding the target by its sides (legs, torso, head behind it,
//              arms to its edges, hands over them), who moves with it.
//   either may have the target on a stand: two posts from its lower corners to the floor, feet across
//   them, carried with it (what an extractor may take for the board, or the board's edge).

#include <limits>
#include <vector>

#include <Eigen/Geometry>

namespace vocal {

struct TargetDescription;

enum class SurfaceLabel : unsigned char { kNone, kTarget, kFloor, kWall, kFurniture, kPerson, kMixed };
const char* surfaceLabelName(SurfaceLabel label);

struct RoomHit {
  double range = std::numeric_limits<double>::infinity();  // along the unit direction
  SurfaceLabel label = SurfaceLabel::kNone;
  Eigen::Vector2d on_target = Eigen::Vector2d::Zero();  // target-frame x, y where the target is hit
};

enum class RoomLayout { kPlain, kFurnished };

class SimulatedRoom {
 public:
  // The target (a width x height rectangle in its x-y plane) at its pose in the rig frame.
  // `on_stand`: the target stands on two posts down to the floor, each on a foot across it (any layout).
  SimulatedRoom(RoomLayout layout, const Eigen::Isometry3d& reference_from_target, const TargetDescription& target,
                bool person_holds_target, bool on_stand = false);

  // The nearest surface along a ray (rig frame, unit direction) within max_range; label kNone if none.
  RoomHit cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double max_range = 8.0) const;

 private:
  struct Box {  // an oriented box: its frame from the rig's (centre, axes), half extents along its axes
    Eigen::Isometry3d box_from_reference;
    Eigen::Vector3d centre, half;
    double radius;  // of its bounding sphere: most rays miss it without a slab test
    SurfaceLabel label;
  };
  void addBox(const Eigen::Isometry3d& reference_from_box, const Eigen::Vector3d& half, SurfaceLabel label);
  void addPerson();
  void addStand();
  // Columns: away from the rig behind the target (horizontal), to its side, up: how a person holding it
  // stands, and how a stand's feet lie.
  Eigen::Matrix3d uprightFrameBehindTarget() const;

  RoomLayout layout_;
  Eigen::Isometry3d reference_from_target_, target_from_reference_;
  double half_width_, half_height_;
  std::vector<Box> boxes_;
};

}  // namespace vocal

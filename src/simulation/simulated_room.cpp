#include "vocal/simulation/simulated_room.h"

#include <algorithm>
#include <cmath>

#include "vocal/calibration/rig_description.h"

namespace vocal {

namespace {
constexpr double kMinRange = 0.05;
constexpr double kWallX = 4.5;  // the wall behind the target (both layouts)
// The furnished room's inside: x, y, z bounds in the rig frame.
const Eigen::Vector3d kRoomLow(-3.0, -3.5, 0.0), kRoomHigh(kWallX, 3.5, 2.8);

Eigen::Isometry3d boxPose(const Eigen::Vector3d& centre, const Eigen::Matrix3d& axes = Eigen::Matrix3d::Identity()) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = axes;
  pose.translation() = centre;
  return pose;
}

// Entry and exit distances of a ray through an axis-aligned box (slab test); empty when missed.
bool slabs(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, const Eigen::Vector3d& low,
           const Eigen::Vector3d& high, double* entry, double* exit, int* exit_axis, bool* exit_high) {
  double near = -std::numeric_limits<double>::infinity(), far = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(direction[axis]) < 1e-12) {
      if (origin[axis] < low[axis] || origin[axis] > high[axis]) return false;
      continue;
    }
    double t0 = (low[axis] - origin[axis]) / direction[axis], t1 = (high[axis] - origin[axis]) / direction[axis];
    const bool flipped = t0 > t1;
    if (flipped) std::swap(t0, t1);
    near = std::max(near, t0);
    if (t1 < far) {
      far = t1;
      if (exit_axis) *exit_axis = axis;
      if (exit_high) *exit_high = !flipped;
    }
  }
  if (near > far) return false;
  *entry = near;
  *exit = far;
  return true;
}
}  // namespace

const char* surfaceLabelName(SurfaceLabel label) {
  switch (label) {
    case SurfaceLabel::kNone: return "nothing";
    case SurfaceLabel::kTarget: return "target";
    case SurfaceLabel::kFloor: return "floor";
    case SurfaceLabel::kWall: return "wall";
    case SurfaceLabel::kFurniture: return "furniture";
    case SurfaceLabel::kPerson: return "person";
    case SurfaceLabel::kMixed: return "mixed pixel";
  }
  return "?";
}

SimulatedRoom::SimulatedRoom(RoomLayout layout, const Eigen::Isometry3d& reference_from_target,
                             const TargetDescription& target, bool person_holds_target, bool on_stand)
    : layout_(layout),
      reference_from_target_(reference_from_target),
      target_from_reference_(reference_from_target.inverse()),
      half_width_(0.5 * target.width),
      half_height_(0.5 * target.height) {
  if (layout_ == RoomLayout::kFurnished) {
    const auto furniture = [&](const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
      addBox(boxPose(0.5 * (low + high)), 0.5 * (high - low), SurfaceLabel::kFurniture);
    };
    // A cabinet whose front faces the rig and is the target's size: only its stillness tells it apart.
    furniture({3.0, 1.3, 0.0}, {3.45, 1.3 + target.width, target.height + 0.05});
    // A table (top and four legs), a shelf against the far wall, a sofa behind the rig.
    furniture({2.0, -2.3, 0.70}, {2.8, -1.1, 0.74});
    for (const double x : {2.05, 2.7})
      for (const double y : {-2.25, -1.2}) furniture({x, y, 0.0}, {x + 0.05, y + 0.05, 0.70});
    furniture({4.1, -1.2, 0.0}, {4.5, 0.0, 1.9});
    furniture({-2.2, 1.2, 0.0}, {-1.4, 3.0, 0.45});
    if (person_holds_target) addPerson();
  }
  if (on_stand) addStand();
}

void SimulatedRoom::addBox(const Eigen::Isometry3d& reference_from_box, const Eigen::Vector3d& half,
                           SurfaceLabel label) {
  boxes_.push_back({reference_from_box.inverse(), reference_from_box.translation(), half, half.norm(), label});
}

Eigen::Matrix3d SimulatedRoom::uprightFrameBehindTarget() const {
  Eigen::Vector3d back = -reference_from_target_.linear().col(2);  // the target's z faces the rig
  back.z() = 0.0;
  back = back.norm() > 1e-6 ? back.normalized() : Eigen::Vector3d::UnitX();
  Eigen::Matrix3d frame;
  frame << back, Eigen::Vector3d::UnitZ().cross(back), Eigen::Vector3d::UnitZ();
  return frame;
}

void SimulatedRoom::addStand() {
  const Eigen::Matrix3d& R = reference_from_target_.linear();
  const Eigen::Vector3d centre = reference_from_target_.translation();
  // The board's edge axis nearer the vertical, pointing up; the other runs along its lower edge.
  const bool y_up = std::abs(R(2, 1)) >= std::abs(R(2, 0));
  Eigen::Vector3d up = y_up ? R.col(1) : R.col(0), along = y_up ? R.col(0) : R.col(1);
  if (up.z() < 0.0) up = -up;
  const double half_up = y_up ? half_height_ : half_width_, half_along = y_up ? half_width_ : half_height_;
  const Eigen::Matrix3d frame = uprightFrameBehindTarget();
  const Eigen::Vector3d behind = frame.col(0);
  for (const double sign : {-1.0, 1.0}) {
    // A post from 5 cm above the lower corner (held by a clamp), 3 cm behind the board, to the floor.
    const Eigen::Vector3d top = centre - (half_up - 0.05) * up + sign * (half_along - 0.08) * along + 0.03 * behind;
    if (top.z() <= 0.05) continue;
    const Eigen::Vector3d foot(top.x(), top.y(), 0.0);
    addBox(boxPose(0.5 * (top + foot)), {0.02, 0.02, 0.5 * top.z()}, SurfaceLabel::kFurniture);
    addBox(boxPose(foot + Eigen::Vector3d(0.0, 0.0, 0.02), frame), {0.3, 0.03, 0.02}, SurfaceLabel::kFurniture);
  }
}

void SimulatedRoom::addPerson() {
  const Eigen::Matrix3d& R = reference_from_target_.linear();
  const Eigen::Vector3d centre = reference_from_target_.translation();
  // Upright, facing the rig from behind the target.
  const Eigen::Matrix3d body = uprightFrameBehindTarget();
  const Eigen::Vector3d back = body.col(0);
  const Eigen::Vector3d feet = centre + 0.3 * back - Eigen::Vector3d(0, 0, centre.z());
  const auto part = [&](const Eigen::Vector3d& offset, const Eigen::Vector3d& half) {
    addBox(boxPose(feet + body * offset, body), half, SurfaceLabel::kPerson);
  };
  for (const double y : {-0.11, 0.11}) part({0.0, y, 0.43}, {0.08, 0.07, 0.43});
  part({0.0, 0.0, 1.16}, {0.12, 0.22, 0.30});
  part({0.0, 0.0, 1.60}, {0.10, 0.09, 0.12});
  // Arms from the shoulders to the middle of the target's left and right edges, hands over the edges.
  for (const double sign : {-1.0, 1.0}) {
    const Eigen::Vector3d grip = centre + sign * (half_width_ + 0.02) * R.col(0) - 0.03 * R.col(2);
    const Eigen::Vector3d shoulder = feet + body * Eigen::Vector3d(0.0, sign * 0.24, 1.38);
    const Eigen::Vector3d along = (grip - shoulder).normalized();
    const Eigen::Vector3d across = along.cross(Eigen::Vector3d::UnitZ()).normalized();
    Eigen::Matrix3d arm;
    arm << along, across, along.cross(across);
    addBox(boxPose(0.5 * (grip + shoulder), arm), {0.5 * (grip - shoulder).norm(), 0.045, 0.045}, SurfaceLabel::kPerson);
    addBox(boxPose(centre + sign * half_width_ * R.col(0), R), {0.04, 0.06, 0.035}, SurfaceLabel::kPerson);
  }
}

RoomHit SimulatedRoom::cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double max_range) const {
  RoomHit hit;
  const auto consider = [&](double range, SurfaceLabel label) {
    if (range > kMinRange && range < std::min(hit.range, max_range)) hit.range = range, hit.label = label;
  };
  if (layout_ == RoomLayout::kPlain) {
    if (std::abs(direction.z()) > 1e-9) consider(-origin.z() / direction.z(), SurfaceLabel::kFloor);
    if (std::abs(direction.x()) > 1e-9) consider((kWallX - origin.x()) / direction.x(), SurfaceLabel::kWall);
  } else {
    double entry, exit;
    int axis = 0;
    bool high = false;
    if (slabs(origin, direction, kRoomLow, kRoomHigh, &entry, &exit, &axis, &high)) {
      consider(exit, axis == 2 && !high ? SurfaceLabel::kFloor : SurfaceLabel::kWall);
    }
  }
  for (const Box& box : boxes_) {
    const Eigen::Vector3d to_centre = box.centre - origin;
    const double along = to_centre.dot(direction);
    if (along + box.radius < kMinRange || along - box.radius > std::min(hit.range, max_range) ||
        to_centre.squaredNorm() - along * along > box.radius * box.radius) {
      continue;
    }
    const Eigen::Vector3d o = box.box_from_reference * origin, d = box.box_from_reference.linear() * direction;
    double entry, exit;
    if (slabs(o, d, -box.half, box.half, &entry, &exit, nullptr, nullptr)) consider(entry, box.label);
  }
  // The target last: it replaces what is behind it, and a hand over its edge stays in front.
  const Eigen::Vector3d normal = reference_from_target_.linear().col(2);
  const double denominator = normal.dot(direction);
  if (std::abs(denominator) > 1e-9) {
    const double range = normal.dot(reference_from_target_.translation() - origin) / denominator;
    const Eigen::Vector3d local = target_from_reference_ * (origin + range * direction);
    if (std::abs(local.x()) <= half_width_ && std::abs(local.y()) <= half_height_ && range > kMinRange &&
        range < std::min(hit.range, max_range)) {
      hit.range = range;
      hit.label = SurfaceLabel::kTarget;
      hit.on_target = local.head<2>();
    }
  }
  return hit;
}

}  // namespace vocal

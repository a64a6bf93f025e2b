#pragma once
// What stays put in a range sensor's view over a calibration session: the board moves from pose to
// pose, while the room's furniture - a cabinet front as large as the board included - does not. Each
// message's board-shaped segments are kept as planes with a centre; a segment whose plane and centre
// recur throughout the session (in most tenths of the sensor's messages, however intermittently: a
// person walks in front of it, its outline changes) is background, while the board at one pose stays
// within the tenths its pose lasted. (Occupied voxels do not tell them apart: the board's poses
// overlap in space, so its voxels are occupied about as often as a cabinet's.)

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

namespace vocal {

class StaticBackground {
 public:
  struct Options {
    double angle = 3.0 * M_PI / 180.0;  // normals this close ...
    double offset = 0.03;               // ... planes this close along the normal ...
    double centre = 0.15;               // ... and centres this close are the same segment
  };
  StaticBackground() = default;
  explicit StaticBackground(const Options& options) : options_(options) {}

  // Where a segment lies: its plane's normal and its centre (a 2D scan's segment, in its plane z = 0:
  // the in-plane perpendicular of its line).
  struct Summary {
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(), centre = Eigen::Vector3d::Zero();
  };
  static Summary summarise(const std::vector<Eigen::Vector3d>& points);

  // One message's board-shaped segments (sensor frame).
  void addMessage(const std::vector<Summary>& segments);
  // The share of the session's tenths (by message count so far) with a segment matching this one
  // (0 before any message).
  double recurrence(const Summary& segment) const;
  int messages() const { return messages_; }

 private:
  struct Seen {
    Summary segment;
    int message;
  };
  std::uint64_t cellOf(const Eigen::Vector3d& centre) const;

  Options options_;
  int messages_ = 0;
  std::unordered_map<std::uint64_t, std::vector<Seen>> cells_;  // by centre, cells of options_.centre
};

}  // namespace vocal

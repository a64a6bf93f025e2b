#pragma once
// What stays put in a range sensor's view over a calibration session: the board moves from pose to
// pose, while the room's furniture - a cabinet front as large as the board included - does not. Each
// message's board-shaped segments are kept as planes with a centre; a segment whose plane and centre
// recur throughout the session (in most tenths of the sensor's messages, however intermittently: a
// person walks in front of it, its outline changes) is background, while the board at one pose stays
// within the tenths its pose lasted. A board-sized part of a larger surface (a shelf's front, the
// rest hidden by the person standing in front of it) is background too when that surface, seen whole
// as it is most of the time, covers it. (Occupied voxels do not tell them apart: the board's poses
// overlap in space, so its voxels are occupied about as often as a cabinet's.)

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "vocal/calibration/extraction/surface_patch.h"

namespace vocal {

class StaticBackground {
 public:
  struct Options {
    double angle = 3.0 * M_PI / 180.0;  // normals this close ...
    double offset = 0.03;               // ... planes this close along the normal ...
    double centre = 0.15;               // ... and centres this close are the same segment
    // A tenth counts when the segment is in this share of its messages (and one at least): the board
    // passes through a place in a message or a few while it is carried, whereas background is seen
    // whenever nothing stands in front of it.
    double part_share = 0.1;
  };
  StaticBackground() = default;
  explicit StaticBackground(const Options& options) : options_(options) {}

  // Where a board-shaped segment lies: its plane's normal and its centre (a 2D scan's segment, in its
  // plane z = 0: the in-plane perpendicular of its line), no extent.
  using Summary = SurfacePatch;
  static Summary summarise(const std::vector<Eigen::Vector3d>& points);

  // One message's board-shaped segments and the surfaces larger than the board it saw (sensor frame).
  void addMessage(const std::vector<Summary>& segments, const std::vector<SurfacePatch>& surfaces = {});
  // The share of the session's tenths (by message count so far; each message its own part in a
  // session of fewer than ten) with a segment matching this one, or a surface covering it, in
  // part_share of their messages (0 before any message).
  double recurrence(const Summary& segment) const;
  int messages() const { return messages_; }

 private:
  struct Seen {
    SurfacePatch segment;
    int message;
  };
  // A surface larger than the board and the messages it was seen in: a wall seen in every message is
  // kept once, so a query looks at each surface once however long the session.
  struct SeenSurface {
    SurfacePatch patch;
    std::vector<int> messages;
  };
  std::uint64_t cellOf(const Eigen::Vector3d& centre) const;
  // Whether `query`'s centre lies on `seen`: its plane, within its rectangle (+ options_.centre).
  bool covers(const SurfacePatch& seen, const Summary& query) const;
  // Tenths of the session (each message its own part in a session of fewer than ten).
  int partsOfTheSession() const { return std::min(10, messages_); }
  // The tenths of the session in whose messages `query` was seen in part_share of them.
  int partsWith(const Summary& query) const;

  Options options_;
  int messages_ = 0;
  std::unordered_map<std::uint64_t, std::vector<Seen>> cells_;  // segments by centre, cells of options_.centre
  std::vector<SeenSurface> surfaces_;  // each reaching over many cells
};

}  // namespace vocal

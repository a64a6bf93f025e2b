#pragma once
// Analytic indoor scenes for tests and the demo: every surface is an oriented rectangle, rendered by
// exact ray casting through pixel centres, so depth and colour are consistent across viewpoints to
// floating-point precision (ground truth for odometry tests).

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/core/image.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

struct SceneSurface {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX();  // unit, in the plane
  Eigen::Vector3d axis_v = Eigen::Vector3d::UnitY();  // unit, in the plane, orthogonal to axis_u
  double half_u = 1.0;                                // half extents along the axes, metres
  double half_v = 1.0;
  Eigen::Vector3d albedo = Eigen::Vector3d::Constant(0.7);  // linear RGB in [0, 1]
  bool textured = true;
  std::uint32_t texture_seed = 0;

  Eigen::Vector3d normal() const { return axis_u.cross(axis_v); }
};

// Where a camera may move in a scene and what it looks at: the centre of its path, the amplitude of
// its motion along world x/y/z, and its mean viewing direction with angular amplitudes (radians).
struct CameraWorkspace {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d amplitude = Eigen::Vector3d::Constant(0.3);
  double yaw = 0.0, pitch = 0.0;
  double yaw_amplitude = 0.2, pitch_amplitude = 0.1, roll_amplitude = 0.05;
};

enum class SceneVariant {
  kIndoorRoom,    // floor, walls, ceiling, a table and boxes, all textured
  kTexturedWall,  // one flat textured wall filling the view: no structure (ICP is degenerate)
  kBareRoom,      // the indoor room untextured, uniform grey: no texture (DVO is degenerate)
  // The indoor room with a blank panel (one untextured plane, 4 x 2.8 m) 1.5 m to the left of the
  // path: facing it, vision sees one plane and no texture (ICP leaves three directions free, DVO all).
  kBlankWall,
};

// Parses "room", "wall", "bare_room" or "blank_wall"; throws InputError naming the value otherwise.
SceneVariant parseSceneVariant(const std::string& name);
std::string sceneVariantName(SceneVariant variant);

struct RenderedView {
  ColorImage color;
  DepthImage depth;  // z in the camera frame, metres; 0 where the ray hits nothing
};

class SyntheticScene {
 public:
  static SyntheticScene make(SceneVariant variant);

  const std::vector<SceneSurface>& surfaces() const { return surfaces_; }
  const CameraWorkspace& workspace() const { return workspace_; }

  // Nearest hit along the ray origin + t * direction (t > 0); returns false when nothing is hit.
  bool intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double* t,
                 int* surface_index) const;

  // Colour of a surface point (view independent: texture times a fixed directional light).
  Rgb8 shade(int surface_index, const Eigen::Vector3d& point) const;

  // world_from_camera is the optical frame's pose in the world (z up).
  RenderedView render(const PinholeCamera& camera, const Eigen::Isometry3d& world_from_camera) const;

 private:
  std::vector<SceneSurface> surfaces_;
  CameraWorkspace workspace_;
};

}  // namespace vocal

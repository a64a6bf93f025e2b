#include "vocal/simulation/synthetic_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/procedural_texture.h"

namespace vocal {

namespace {

class SceneBuilder {
 public:
  explicit SceneBuilder(bool textured) : textured_(textured) {}

  void addRectangle(const Eigen::Vector3d& center, const Eigen::Vector3d& axis_u, const Eigen::Vector3d& axis_v,
                    double half_u, double half_v, const Eigen::Vector3d& albedo) {
    SceneSurface s;
    s.center = center;
    s.axis_u = axis_u.normalized();
    s.axis_v = axis_v.normalized();
    s.half_u = half_u;
    s.half_v = half_v;
    s.albedo = textured_ ? albedo : Eigen::Vector3d::Constant(0.6);
    s.textured = textured_;
    s.texture_seed = 1000u + static_cast<std::uint32_t>(surfaces_.size()) * 7u;
    surfaces_.push_back(s);
  }

  // Axis-aligned in its own frame, turned by `yaw` about world z; size is the full extent.
  void addBox(const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw, const Eigen::Vector3d& albedo) {
    const Eigen::Matrix3d R = rotationFromRollPitchYaw(0.0, 0.0, yaw);
    const Eigen::Vector3d half = 0.5 * size;
    for (int axis = 0; axis < 3; ++axis) {
      const int a = (axis + 1) % 3;
      const int b = (axis + 2) % 3;
      for (double sign : {-1.0, 1.0}) {
        // Face normal sign * e_axis; u x v points outwards for sign > 0, inwards otherwise, which
        // does not matter: shading uses |n . L| and intersection is two-sided.
        addRectangle(center + sign * half[axis] * R.col(axis), R.col(a), R.col(b), half[a], half[b],
                     albedo);
      }
    }
  }

  std::vector<SceneSurface> take() { return std::move(surfaces_); }

 private:
  bool textured_;
  std::vector<SceneSurface> surfaces_;
};

// Room 7 x 6 x 2.8 m around the origin, floor at z = 0.
void addIndoorRoom(SceneBuilder* b) {
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(), Z = Eigen::Vector3d::UnitZ();
  b->addRectangle({0, 0, 0}, X, Y, 3.5, 3.0, {0.55, 0.45, 0.35});    // floor
  b->addRectangle({0, 0, 2.8}, X, Y, 3.5, 3.0, {0.85, 0.85, 0.8});   // ceiling
  b->addRectangle({3.5, 0, 1.4}, Y, Z, 3.0, 1.4, {0.8, 0.7, 0.6});   // far wall
  b->addRectangle({-3.5, 0, 1.4}, Y, Z, 3.0, 1.4, {0.6, 0.7, 0.8});  // back wall
  b->addRectangle({0, 3.0, 1.4}, X, Z, 3.5, 1.4, {0.7, 0.8, 0.65});  // left wall
  b->addRectangle({0, -3.0, 1.4}, X, Z, 3.5, 1.4, {0.8, 0.65, 0.7}); // right wall
  // Table: top and four legs.
  b->addBox({1.2, 0.3, 0.73}, {1.4, 0.8, 0.04}, 0.15, {0.6, 0.4, 0.25});
  for (double sx : {-0.62, 0.62}) {
    for (double sy : {-0.33, 0.33}) {
      const Eigen::Vector3d leg = Eigen::Vector3d(1.2, 0.3, 0.0) + rotationFromRollPitchYaw(0, 0, 0.15) *
                                                                      Eigen::Vector3d(sx, sy, 0.0);
      b->addBox({leg.x(), leg.y(), 0.355}, {0.05, 0.05, 0.71}, 0.15, {0.3, 0.3, 0.3});
    }
  }
  b->addBox({1.0, 0.35, 0.85}, {0.25, 0.2, 0.2}, 0.5, {0.8, 0.3, 0.2});   // on the table
  b->addBox({2.3, -1.3, 0.25}, {0.5, 0.5, 0.5}, 0.3, {0.3, 0.5, 0.8});
  b->addBox({0.9, -1.9, 0.35}, {0.6, 0.4, 0.7}, -0.4, {0.3, 0.7, 0.3});
  b->addBox({2.7, 1.9, 0.45}, {0.7, 0.5, 0.9}, 0.1, {0.8, 0.8, 0.3});
  b->addBox({-0.3, 2.3, 0.3}, {0.6, 0.6, 0.6}, 0.7, {0.7, 0.4, 0.7});
}

}  // namespace

SceneVariant parseSceneVariant(const std::string& name) {
  if (name == "room") return SceneVariant::kIndoorRoom;
  if (name == "wall") return SceneVariant::kTexturedWall;
  if (name == "bare_room") return SceneVariant::kBareRoom;
  if (name == "blank_wall") return SceneVariant::kBlankWall;
  throw InputError("scene '" + name + "' is unknown: expected room, wall, bare_room or blank_wall");
}

std::string sceneVariantName(SceneVariant variant) {
  switch (variant) {
    case SceneVariant::kIndoorRoom: return "room";
    case SceneVariant::kTexturedWall: return "wall";
    case SceneVariant::kBareRoom: return "bare_room";
    case SceneVariant::kBlankWall: return "blank_wall";
  }
  return "unknown";
}

SyntheticScene SyntheticScene::make(SceneVariant variant) {
  SyntheticScene scene;
  if (variant == SceneVariant::kTexturedWall) {
    SceneBuilder builder(true);
    // 8 m x 6 m wall 2 m in front of the path: fills the view for every pose of the workspace.
    builder.addRectangle({2.0, 0, 1.5}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 4.0, 3.0,
                         {0.75, 0.7, 0.6});
    scene.surfaces_ = builder.take();
    scene.workspace_.center = {0.0, 0.0, 1.4};
    scene.workspace_.amplitude = {0.2, 0.4, 0.2};
    scene.workspace_.yaw_amplitude = 0.15;
    scene.workspace_.pitch_amplitude = 0.1;
    scene.workspace_.roll_amplitude = 0.08;
    return scene;
  }
  SceneBuilder builder(variant != SceneVariant::kBareRoom);
  addIndoorRoom(&builder);
  scene.surfaces_ = builder.take();
  if (variant == SceneVariant::kBlankWall) {
    // A painted partition beside the path, floor to ceiling (x -3.5..0.5 m at y = 1.5 m): from the path's
    // centre, facing it (yaw +90 deg), it fills a Kinect's view for +-12 deg of yaw and +-15 cm of travel.
    SceneSurface panel;
    panel.center = {-1.5, 1.5, 1.4};
    panel.axis_u = Eigen::Vector3d::UnitX();
    panel.axis_v = Eigen::Vector3d::UnitZ();
    panel.half_u = 2.0;
    panel.half_v = 1.4;
    panel.albedo = Eigen::Vector3d::Constant(0.6);
    panel.textured = false;
    scene.surfaces_.push_back(panel);
    scene.workspace_.center = {-1.5, 0.0, 1.4};
    scene.workspace_.amplitude = {0.15, 0.1, 0.08};
    scene.workspace_.yaw = M_PI / 2;
    scene.workspace_.yaw_amplitude = 0.2;
    scene.workspace_.pitch_amplitude = 0.08;
    scene.workspace_.roll_amplitude = 0.05;
    return scene;
  }
  scene.workspace_.center = {-1.5, 0.0, 1.4};
  scene.workspace_.amplitude = {0.4, 0.6, 0.2};
  scene.workspace_.pitch = 0.25;
  scene.workspace_.yaw_amplitude = 0.35;
  scene.workspace_.pitch_amplitude = 0.1;
  scene.workspace_.roll_amplitude = 0.08;
  return scene;
}

bool SyntheticScene::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double* t,
                               int* surface_index) const {
  double best = std::numeric_limits<double>::infinity();
  int best_index = -1;
  for (std::size_t i = 0; i < surfaces_.size(); ++i) {
    const SceneSurface& s = surfaces_[i];
    const Eigen::Vector3d n = s.normal();
    const double denominator = direction.dot(n);
    if (std::abs(denominator) < 1e-12) continue;
    const double distance = (s.center - origin).dot(n) / denominator;
    if (distance <= 1e-9 || distance >= best) continue;
    const Eigen::Vector3d offset = origin + distance * direction - s.center;
    if (std::abs(offset.dot(s.axis_u)) <= s.half_u && std::abs(offset.dot(s.axis_v)) <= s.half_v) {
      best = distance;
      best_index = static_cast<int>(i);
    }
  }
  if (best_index < 0) return false;
  *t = best;
  *surface_index = best_index;
  return true;
}

Rgb8 SyntheticScene::shade(int surface_index, const Eigen::Vector3d& point) const {
  const SceneSurface& s = surfaces_[surface_index];
  static const Eigen::Vector3d kLight = Eigen::Vector3d(0.3, 0.5, 0.8).normalized();
  const double light = 0.55 + 0.45 * std::abs(s.normal().dot(kLight));
  Eigen::Vector3d colour = s.albedo * light;
  if (s.textured) {
    const Eigen::Vector3d offset = point - s.center;
    const double a = offset.dot(s.axis_u), b = offset.dot(s.axis_v);
    const double brightness = 0.25 + 0.75 * fractalNoise(a, b, s.texture_seed);
    const double tint = fractalNoise(0.5 * a, 0.5 * b, s.texture_seed + 1u) - 0.5;
    colour = colour.cwiseProduct(Eigen::Vector3d(1.0 + 0.4 * tint, 1.0, 1.0 - 0.4 * tint)) * brightness;
  }
  auto to8 = [](double c) { return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(c, 0.0, 1.0))); };
  return {to8(colour.x()), to8(colour.y()), to8(colour.z())};
}

RenderedView SyntheticScene::render(const PinholeCamera& camera, const Eigen::Isometry3d& world_from_camera) const {
  RenderedView view{ColorImage(camera.width, camera.height), DepthImage(camera.width, camera.height, 0.0f)};
  const Eigen::Matrix3d R = world_from_camera.linear();
  const Eigen::Vector3d origin = world_from_camera.translation();
#pragma omp parallel for schedule(dynamic, 8)
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      // A camera ray with unit z: the hit distance along it is the depth z itself.
      const Eigen::Vector3d ray_camera((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0);
      const Eigen::Vector3d ray_world = R * ray_camera;
      double depth = 0.0;
      int surface = -1;
      if (intersect(origin, ray_world, &depth, &surface)) {
        view.depth(u, v) = static_cast<float>(depth);
        view.color(u, v) = shade(surface, origin + depth * ray_world);
      }
    }
  }
  return view;
}

}  // namespace vocal

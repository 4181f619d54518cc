#include "semfuse/synthetic/room.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace semfuse::synthetic {
namespace {

constexpr double kShellThickness = 0.2;

Eigen::Matrix3d yawRotation(double yaw_rad) {
  return Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

OrientedBox box(const Eigen::Vector3d& center, const Eigen::Vector3d& half, double yaw_rad = 0.0) {
  return OrientedBox{center, half, yawRotation(yaw_rad)};
}

// A box resting on the floor (or on another surface at z = base), rotated about z.
OrientedBox standingBox(double x, double y, double base, const Eigen::Vector3d& half, double yaw_rad) {
  return box({x, y, base + half.z()}, half, yaw_rad);
}

void addShell(LabeledScene& scene, const RoomOptions& o) {
  const double hx = 0.5 * o.size_x, hy = 0.5 * o.size_y, t = kShellThickness;
  const double outer_x = hx + t, outer_y = hy + t;
  scene.add({"floor",
             box({0, 0, -0.5 * t}, {outer_x, outer_y, 0.5 * t}),
             labels::kFloor,
             {182, 150, 110},
             Texture::kChecker});
  const double wall_half_z = 0.5 * o.height;
  // The four walls are one instance: one surface around the room, as the floor is one.
  const std::size_t first_wall = scene.add({"wall +x",
                                            box({hx + 0.5 * t, 0, wall_half_z}, {0.5 * t, outer_y, wall_half_z}),
                                            labels::kWall,
                                            {205, 200, 185},
                                            Texture::kStripes});
  const uint32_t walls = scene.instanceOf(first_wall);
  scene.add({"wall -x",
             box({-hx - 0.5 * t, 0, wall_half_z}, {0.5 * t, outer_y, wall_half_z}),
             labels::kWall,
             {205, 200, 185},
             Texture::kStripes,
             walls});
  scene.add({"wall +y",
             box({0, hy + 0.5 * t, wall_half_z}, {outer_x, 0.5 * t, wall_half_z}),
             labels::kWall,
             {190, 205, 215},
             Texture::kStripes,
             walls});
  scene.add({"wall -y",
             box({0, -hy - 0.5 * t, wall_half_z}, {outer_x, 0.5 * t, wall_half_z}),
             labels::kWall,
             {190, 205, 215},
             Texture::kStripes,
             walls});
  if (o.ceiling) {
    scene.add({"ceiling",
               box({0, 0, o.height + 0.5 * t}, {outer_x, outer_y, 0.5 * t}),
               labels::kCeiling,
               {235, 235, 230},
               Texture::kNoise});
  }
}

void addTable(LabeledScene& scene) {
  const Rgb wood{140, 90, 50};
  const double x = 0.2, y = 0.1, top_z = 0.75;
  const uint32_t table = scene.instanceOf(
      scene.add({"table top", box({x, y, top_z - 0.03}, {0.6, 0.4, 0.03}), labels::kTable, wood, Texture::kStripes}));
  for (double sx : {-1.0, 1.0}) {
    for (double sy : {-1.0, 1.0}) {
      scene.add({"table leg", UprightCylinder{{x + sx * 0.52, y + sy * 0.32}, 0.03, 0.0, top_z - 0.06}, labels::kTable,
                 wood, Texture::kNoise, table});
    }
  }
}

// Seat, backrest and four legs; yaw turns the chair about its centre (0 = backrest towards -y).
void addChair(LabeledScene& scene, double x, double y, double yaw_rad, const Rgb& color) {
  const Eigen::Matrix3d r = yawRotation(yaw_rad);
  const Eigen::Vector3d c(x, y, 0);
  auto at = [&](double lx, double ly, double z) {
    return Eigen::Vector3d(c + r * Eigen::Vector3d(lx, ly, 0) + Eigen::Vector3d(0, 0, z));
  };
  const double seat_z = 0.45;
  const uint32_t chair =
      scene.instanceOf(scene.add({"chair seat", OrientedBox{at(0, 0, seat_z - 0.025), {0.22, 0.22, 0.025}, r},
                                  labels::kChair, color, Texture::kNoise}));
  scene.add({"chair back", OrientedBox{at(0, -0.2, seat_z + 0.25), {0.22, 0.02, 0.25}, r}, labels::kChair, color,
             Texture::kNoise, chair});
  for (double sx : {-1.0, 1.0}) {
    for (double sy : {-1.0, 1.0}) {
      const Eigen::Vector3d foot = at(sx * 0.18, sy * 0.18, 0);
      scene.add({"chair leg", UprightCylinder{foot.head<2>(), 0.02, 0.0, seat_z - 0.05}, labels::kChair, color,
                 Texture::kNoise, chair});
    }
  }
}

}  // namespace

LabeledScene makeRoom(const RoomOptions& options) {
  RoomOptions o = options;
  o.size_x = std::max(o.size_x, 4.6);
  o.size_y = std::max(o.size_y, 3.6);
  o.height = std::max(o.height, 2.0);
  LabeledScene scene(o.seed);
  addShell(scene, o);
  addTable(scene);
  addChair(scene, 0.2, -0.75, 0.0, {40, 90, 160});
  addChair(scene, -0.85, 0.1, -M_PI / 2, {40, 140, 90});

  scene.add({"box",
             standingBox(-1.7, -1.3, 0.0, {0.25, 0.2, 0.2}, 20.0 * M_PI / 180),
             labels::kBox,
             {200, 150, 60},
             Texture::kNoise});
  scene.add({"box",
             standingBox(-1.7, -1.3, 0.4, {0.15, 0.12, 0.1}, -10.0 * M_PI / 180),
             labels::kBox,
             {210, 170, 90},
             Texture::kNoise});
  scene.add({"box",
             standingBox(1.4, -1.45, 0.0, {0.2, 0.2, 0.15}, -30.0 * M_PI / 180),
             labels::kBox,
             {180, 120, 70},
             Texture::kNoise});

  scene.add({"sphere", Sphere{{-1.2, 1.25, 0.3}, 0.3}, labels::kSphere, {200, 50, 50}, Texture::kNoise});
  scene.add({"sphere", Sphere{{0.45, 0.25, 0.87}, 0.12}, labels::kSphere, {230, 200, 40}, Texture::kNoise});

  // The cabinet stands against the +x wall; it touches it, as furniture does.
  const double wall_x = 0.5 * o.size_x;
  scene.add({"cabinet",
             standingBox(wall_x - 0.22, 0.8, 0.0, {0.22, 0.5, 0.9}, 0.0),
             labels::kCabinet,
             {110, 110, 125},
             Texture::kStripes});
  return scene;
}

}  // namespace semfuse::synthetic

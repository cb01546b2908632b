// Obstacles: shapes, poses, voxel files, masks and the two treatments.
#include "sim/obstacle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "sim/water.h"

namespace ripple::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string TempPath(const std::string& name) {
  return ::testing::TempDir() + "/" + name;
}

Obstacle Cylinder(double r, double height, double x, double y) {
  Obstacle o;
  o.shape = Obstacle::Shape::kCylinder;
  o.radius_m = r;
  o.height_m = height;
  o.tank_from_obstacle = RigidTransform::FromTranslation(x, y, 0);
  return o;
}

TEST(RigidTransformTest, QuaternionInverseAndCompose) {
  const double a = 0.7;
  const RigidTransform t = RigidTransform::FromQuaternion(
      std::cos(a / 2), 0, 0, std::sin(a / 2), {0.1, -0.2, 0.3});
  const auto p = t.Apply({1, 0, 0});
  EXPECT_NEAR(p[0], 0.1 + std::cos(a), 1e-12);
  EXPECT_NEAR(p[1], -0.2 + std::sin(a), 1e-12);
  EXPECT_NEAR(p[2], 0.3, 1e-12);
  const auto q = (t.Inverse() * t).Apply({0.4, 0.5, 0.6});
  EXPECT_NEAR(q[0], 0.4, 1e-12);
  EXPECT_NEAR(q[1], 0.5, 1e-12);
  EXPECT_NEAR(q[2], 0.6, 1e-12);
  RigidTransform bad;
  bad.translation[1] = std::nan("");
  EXPECT_FALSE(bad.IsFinite());
}

TEST(ObstacleTest, ShapesAreTestedInTheirOwnFrame) {
  Obstacle box;
  box.shape = Obstacle::Shape::kBox;
  box.box_size_m = {0.04, 0.01, 0.1};
  // Rotated 90 degrees about z: the long side now runs along tank y.
  box.tank_from_obstacle = RigidTransform::FromQuaternion(
      std::cos(kPi / 4), 0, 0, std::sin(kPi / 4), {0.01, 0, 0});
  EXPECT_TRUE(box.ContainsInTank({0.01, 0.015, 0.02}));
  EXPECT_FALSE(box.ContainsInTank({0.025, 0, 0.02}));
  const Obstacle cyl = Cylinder(0.01, 0.03, 0.02, 0.0);
  EXPECT_TRUE(cyl.ContainsInTank({0.025, 0.005, 0.02}));
  EXPECT_FALSE(cyl.ContainsInTank({0.02, 0.0, 0.035}));   // above the top
  EXPECT_FALSE(cyl.ContainsInTank({0.02, 0.0, -0.001}));  // below the base
  EXPECT_FALSE(cyl.ContainsInTank({0.031, 0.0, 0.01}));
}

TEST(ObstacleTest, ValidationRejectsNonsense) {
  std::string error;
  Obstacle o = Cylinder(0, 0.03, 0, 0);
  EXPECT_FALSE(o.IsValid(&error));
  o = Cylinder(0.01, 0.03, 0, 0);
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.tank_from_obstacle.translation[0] = INFINITY;
  EXPECT_FALSE(o.IsValid(&error));
  Obstacle v;
  v.shape = Obstacle::Shape::kVoxels;
  EXPECT_FALSE(v.IsValid(&error));
  Obstacle b;
  b.shape = Obstacle::Shape::kBox;
  b.box_size_m = {0.1, std::nan(""), 0.1};
  EXPECT_FALSE(b.IsValid(&error));
}

VoxelVolume LShape() {
  // 4 x 3 x 2 voxels of 1 cm: an L in the bottom layer, one voxel on top.
  VoxelVolume v;
  v.nx = 4;
  v.ny = 3;
  v.nz = 2;
  v.voxel_size_m = 0.01;
  v.occupied.assign(24, 0);
  for (int a = 0; a < 4; ++a) v.occupied[a] = 1;  // row b = 0
  v.occupied[0 + 4 * 1] = 1;                      // (0, 1, 0)
  v.occupied[0 + 4 * 2] = 1;                      // (0, 2, 0)
  v.occupied[3 + 4 * (2 + 3 * 1)] = 1;            // (3, 2, 1)
  return v;
}

TEST(VoxelTest, FileRoundTripAndOccupancy) {
  const VoxelVolume v = LShape();
  const std::string path = TempPath("l.rvox");
  std::string error;
  ASSERT_TRUE(SaveVoxelVolume(v, path, &error)) << error;
  VoxelVolume back;
  ASSERT_TRUE(LoadVoxelVolume(path, 0.01, &back, &error)) << error;
  EXPECT_EQ(back.nx, 4);
  EXPECT_EQ(back.ny, 3);
  EXPECT_EQ(back.nz, 2);
  EXPECT_EQ(back.occupied, v.occupied);
  Obstacle o;
  o.shape = Obstacle::Shape::kVoxels;
  o.voxels = std::make_shared<VoxelVolume>(back);
  // Volume frame: x in [-2, 2) cm, y in [-1.5, 1.5) cm, z in [0, 2) cm.
  EXPECT_TRUE(o.ContainsInObstacle({-0.015, -0.012, 0.005}));  // (0,0,0)
  EXPECT_TRUE(o.ContainsInObstacle({0.015, -0.012, 0.005}));   // (3,0,0)
  EXPECT_FALSE(o.ContainsInObstacle({0.015, 0.0, 0.005}));     // (3,1,0)
  EXPECT_TRUE(o.ContainsInObstacle({0.015, 0.012, 0.015}));    // (3,2,1)
  EXPECT_FALSE(o.ContainsInObstacle({0.015, 0.012, 0.025}));   // above
  EXPECT_FALSE(o.ContainsInObstacle({0.025, -0.012, 0.005}));  // outside x
}

TEST(VoxelTest, BadFilesGiveOneLineErrors) {
  struct Bad {
    const char* text;
    const char* expect;
  };
  const std::vector<Bad> cases = {
      {"hello 1\n1 1 1\n1\n", "not a voxel file"},
      {"ripple-voxels 2\n1 1 1\n1\n", "version"},
      {"ripple-voxels 1\n2 1\n", "dimensions"},
      {"ripple-voxels 1\n0 1 1\n", "out of range"},
      {"ripple-voxels 1\n2 1 1\n1\n", "expected 2 voxels"},
      {"ripple-voxels 1\n1 1 1\n11\n", "more voxels"},
      {"ripple-voxels 1\n2 1 1\n1x\n", "unexpected character"},
  };
  for (const Bad& b : cases) {
    const std::string path = TempPath("bad.rvox");
    std::ofstream(path) << b.text;
    VoxelVolume v;
    std::string error;
    EXPECT_FALSE(LoadVoxelVolume(path, 0.01, &v, &error)) << b.text;
    EXPECT_NE(error.find(b.expect), std::string::npos) << error;
    EXPECT_NE(error.find(path), std::string::npos) << error;
  }
  VoxelVolume v;
  std::string error;
  EXPECT_FALSE(LoadVoxelVolume(TempPath("missing.rvox"), 0.01, &v, &error));
  // Comments and free layout are fine.
  const std::string path = TempPath("ok.rvox");
  std::ofstream(path) << "# a pillar\nripple-voxels 1 # v1\n1 1 2\n1\n  1\n";
  ASSERT_TRUE(LoadVoxelVolume(path, 0.01, &v, &error)) << error;
  EXPECT_EQ(v.occupied, std::vector<std::uint8_t>({1, 1}));
}

GridSpec Grid(int n = 40) { return GridSpec::ForTank(0.16, 0.12, 0.025, n); }

TEST(WaterObstacleTest, MaskMarksCellCentresAtTheRestSurface) {
  Water water(Grid(), WaterOptions());
  const Obstacle pillar = Cylinder(0.02, 0.05, 0.03, -0.01);
  ASSERT_EQ(water.AddObstacle(pillar, nullptr), 0);
  const HeightFieldView view = water.View();
  int blocked = 0;
  for (int j = 0; j < view.ny; ++j) {
    for (int i = 0; i < view.nx; ++i) {
      const bool inside = pillar.ContainsInTank(
          {view.CellCentreX(i), view.CellCentreY(j), view.rest_level_m});
      EXPECT_EQ(view.water[j * view.nx + i] == 0, inside) << i << "," << j;
      blocked += inside;
    }
  }
  // pi r^2 / d^2 = pi * 0.02^2 / 0.004^2 ~ 78.5 cells.
  EXPECT_NEAR(blocked, 78.5, 8);
  EXPECT_EQ(water.num_water_cells(), view.nx * view.ny - blocked);
  // Obstacles that do not reach the rest surface block nothing.
  EXPECT_EQ(water.AddObstacle(Cylinder(0.02, 0.01, -0.03, 0), nullptr), 1);
  Obstacle hovering = Cylinder(0.02, 0.01, -0.03, 0);
  hovering.tank_from_obstacle.translation[2] = 0.03;
  EXPECT_EQ(water.AddObstacle(hovering, nullptr), 2);
  EXPECT_EQ(water.num_water_cells(), view.nx * view.ny - blocked);
}

TEST(WaterObstacleTest, MaskIsRecomputedOnlyWhenTheObstacleMoves) {
  Water water(Grid(), WaterOptions());
  Obstacle box;
  box.shape = Obstacle::Shape::kBox;
  box.box_size_m = {0.018, 0.018, 0.1};  // edges 1 mm from cell centres
  const int id = water.AddObstacle(box, nullptr);
  ASSERT_GE(id, 0);
  water.Advance(0.1);  // settles the wake-up from adding it
  while (!water.at_rest()) water.Advance(0.1);
  const auto counter = water.counter();
  const int wet = water.num_water_cells();
  // The same pose: nothing recomputed, nothing woken.
  EXPECT_TRUE(water.SetObstaclePose(id, box.tank_from_obstacle));
  EXPECT_EQ(water.counter(), counter);
  water.Advance(1.0 / 60);
  EXPECT_FALSE(water.stats().changed);
  // Moved by a tenth of a cell: pose differs, mask identical, stays asleep.
  EXPECT_TRUE(
      water.SetObstaclePose(id, RigidTransform::FromTranslation(0.0004, 0, 0)));
  EXPECT_EQ(water.counter(), counter);
  // Moved by 2 cm: the mask changes and the water wakes.
  EXPECT_TRUE(
      water.SetObstaclePose(id, RigidTransform::FromTranslation(0.02, 0, 0)));
  EXPECT_NE(water.counter(), counter);
  EXPECT_EQ(water.num_water_cells(), wet);
  water.Advance(1.0 / 60);
  EXPECT_TRUE(water.stats().changed);
  // Unknown ids and non-finite poses are refused.
  EXPECT_FALSE(water.SetObstaclePose(5, RigidTransform()));
  RigidTransform nan_pose;
  nan_pose.translation[0] = std::nan("");
  EXPECT_FALSE(water.SetObstaclePose(id, nan_pose));
}

// A wave train hits a wall-like obstacle. The reflecting treatment keeps
// the volume; the paper's h = v = 0 leaks it and inverts the reflection.
TEST(WaterObstacleTest, ReflectingConservesVolumeZeroLeaksAndInverts) {
  auto run = [](ObstacleMode mode, double* volume_ratio,
                double* reflected_sign) {
    WaterOptions o;
    o.viscosity_per_s = 0;
    o.rest_speed_m_per_s = 0;
    o.rest_height_m = 0;
    o.obstacles = mode;
    o.max_substeps = 100000;
    GridSpec g;
    g.nx = 120;
    g.ny = 4;
    g.cell_m = 0.002;
    Water water(g, o);
    // A slab across the channel at x in [0.06, 0.07) (cells 90..94).
    Obstacle slab;
    slab.shape = Obstacle::Shape::kBox;
    slab.box_size_m = {0.01, 0.1, 0.1};
    slab.tank_from_obstacle = RigidTransform::FromTranslation(0.065, 0, 0);
    ASSERT_GE(water.AddObstacle(slab, nullptr), 0);
    // A positive bump (1-D, uniform in y) at cell 60 travelling both ways.
    std::vector<float> h(g.nx * g.ny);
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        h[j * g.nx + i] = 1e-3f * std::exp(-(i - 60.0) * (i - 60.0) / 8.0);
    ASSERT_TRUE(water.SetState(h));
    water.Advance(0);
    const double v0 = water.stats().volume_m3;
    // The right-going half travels 29 cells to the slab and back to x = 75:
    // sample where the reflection passes, before the left half returns.
    const double d = g.cell_m, c = o.wave_speed_m_per_s;
    water.Advance((29 + 14) * d / c);
    double peak = 0;
    for (int i = 70; i < 88; ++i) {
      const double v = water.heights()[i];
      if (std::abs(v) > std::abs(peak)) peak = v;
    }
    *reflected_sign = peak;
    water.Advance(200 * d / c);
    *volume_ratio = water.stats().volume_m3 / v0;
  };
  double ratio = 0, sign = 0;
  run(ObstacleMode::kReflect, &ratio, &sign);
  EXPECT_NEAR(ratio, 1.0, 1e-5);
  EXPECT_GT(sign, 1e-4);  // upright reflection
  run(ObstacleMode::kZero, &ratio, &sign);
  EXPECT_LT(ratio, 0.99);  // leaks into the obstacle
  EXPECT_LT(sign, -1e-4);  // inverted reflection
}

TEST(WaterObstacleTest, ObstacleCoveringEverythingIsHarmless) {
  WaterOptions o;
  Water water(Grid(16), o);
  Obstacle big;
  big.shape = Obstacle::Shape::kBox;
  big.box_size_m = {1, 1, 1};
  ASSERT_GE(water.AddObstacle(big, nullptr), 0);
  EXPECT_EQ(water.num_water_cells(), 0);
  water.SetPenTip({0, 0, 0.0});
  for (int f = 0; f < 10; ++f) ASSERT_TRUE(water.Advance(1.0 / 30));
  for (int c = 0; c < 16 * 12; ++c) EXPECT_EQ(water.heights()[c], 0.f);
  EXPECT_EQ(water.stats().volume_m3, 0);
}

TEST(WaterObstacleTest, VoxelObstacleBlocksItsFootprint) {
  Water water(Grid(80), WaterOptions());
  Obstacle o;
  o.shape = Obstacle::Shape::kVoxels;
  auto v = std::make_shared<VoxelVolume>(LShape());
  v->voxel_size_m = 0.01;
  o.voxels = v;
  // Stand it on the floor: the bottom layer is [0, 1) cm, below the 2.5 cm
  // surface; raise it so the bottom layer cuts the surface.
  o.tank_from_obstacle = RigidTransform::FromTranslation(0, 0, 0.02);
  ASSERT_GE(water.AddObstacle(o, nullptr), 0);
  // Bottom layer: an L of 6 voxels of 1 cm^2 = 6 cm^2 = 150 cells of 2 mm.
  const int blocked = 80 * 60 - water.num_water_cells();
  EXPECT_NEAR(blocked, 150, 20);
}

}  // namespace
}  // namespace ripple::sim

// The height-field view the renderer consumes: layout, cell centres,
// gradients and point sampling.
#include "sim/height_field.h"

#include <gtest/gtest.h>

#include <vector>

#include "sim/water.h"

namespace ripple::sim {
namespace {

TEST(HeightFieldViewTest, CellCentresAreCentredOnTheTank) {
  const GridSpec g = GridSpec::ForTank(0.17, 0.11, 0.025, 128);
  Water water(g, WaterOptions());
  const HeightFieldView v = water.View();
  EXPECT_EQ(v.nx, 128);
  EXPECT_EQ(v.ny, 83);
  EXPECT_DOUBLE_EQ(v.cell_m, 0.17 / 128);
  EXPECT_DOUBLE_EQ(v.rest_level_m, 0.025);
  EXPECT_EQ(v.heights, water.heights());
  // First and last centres half a cell inside the grid edges +-nx*d/2.
  EXPECT_NEAR(v.CellCentreX(0), -0.085 + 0.5 * v.cell_m, 1e-15);
  EXPECT_NEAR(v.CellCentreX(127), 0.085 - 0.5 * v.cell_m, 1e-15);
  EXPECT_NEAR(v.CellCentreY(0) + v.CellCentreY(82), 0, 1e-15);
  EXPECT_DOUBLE_EQ(v.SurfaceZ(3, 4), 0.025);
}

TEST(HeightFieldViewTest, RowMajorIAlongXAndJAlongY) {
  GridSpec g;
  g.nx = 8;
  g.ny = 5;
  g.cell_m = 0.01;
  Water water(g, WaterOptions());
  std::vector<float> h(40);
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 8; ++i) h[j * 8 + i] = 0.001f * i + 0.0001f * j;
  ASSERT_TRUE(water.SetState(h));
  const HeightFieldView v = water.View();
  EXPECT_FLOAT_EQ(v.Height(7, 0), 0.007f);
  EXPECT_FLOAT_EQ(v.Height(0, 4), 0.0004f);
  // Bilinear sampling at a cell centre returns that cell; between centres
  // it interpolates linearly.
  EXPECT_NEAR(water.HeightAtPoint(v.CellCentreX(2), v.CellCentreY(3)),
              0.002 + 0.0003, 1e-7);
  EXPECT_NEAR(water.HeightAtPoint(0.5 * (v.CellCentreX(2) + v.CellCentreX(3)),
                                  v.CellCentreY(1)),
              0.0025 + 0.0001, 1e-7);
  // Outside the grid it clamps to the edge.
  EXPECT_NEAR(water.HeightAtPoint(1.0, v.CellCentreY(0)), 0.007, 1e-7);
}

TEST(HeightFieldViewTest, GradientsOfAPlane) {
  GridSpec g;
  g.nx = 10;
  g.ny = 6;
  g.cell_m = 0.005;
  Water water(g, WaterOptions());
  std::vector<float> h(60);
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 10; ++i)
      h[j * 10 + i] =
          static_cast<float>(0.02 * (i * 0.005) - 0.01 * (j * 0.005));
  ASSERT_TRUE(water.SetState(h));
  std::vector<float> gx, gy;
  ComputeGradients(water.View(), &gx, &gy);
  ASSERT_EQ(gx.size(), 60u);
  for (int c = 0; c < 60; ++c) {
    EXPECT_NEAR(gx[c], 0.02, 1e-5) << c;  // one-sided at the walls too
    EXPECT_NEAR(gy[c], -0.01, 1e-5) << c;
  }
}

TEST(HeightFieldViewTest, GradientsIgnoreBlockedCells) {
  GridSpec g;
  g.nx = 10;
  g.ny = 10;
  g.cell_m = 0.01;
  Water water(g, WaterOptions());
  Obstacle box;
  box.shape = Obstacle::Shape::kBox;
  box.box_size_m = {0.02, 0.02, 1};
  ASSERT_GE(water.AddObstacle(box, nullptr), 0);
  std::vector<float> h(100);
  for (int c = 0; c < 100; ++c) h[c] = 0.001f * (c % 10);
  ASSERT_TRUE(water.SetState(h));  // blocked cells are forced to 0
  std::vector<float> gx, gy;
  ComputeGradients(water.View(), &gx, &gy);
  for (int c = 0; c < 100; ++c) {
    if (!water.View().water[c]) continue;
    EXPECT_NEAR(gx[c], 0.1, 1e-5) << c;
    EXPECT_NEAR(gy[c], 0.0, 1e-6) << c;
  }
}

}  // namespace
}  // namespace ripple::sim

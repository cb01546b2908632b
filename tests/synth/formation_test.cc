// The point-sampled formation (a second, independent image formation) against
// the exact-area one: its edges are really different (staircases of 1/N^2
// steps, not the exact coverage ramp), yet unbiased (a rendered tag's edges
// land where the projection puts them, on average over an edge).
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "tests/synth/one_tag_scene.h"
#include "tracking/synth/synth.h"
#include "tracking/synth/variant.h"

namespace ripple::synth {
namespace {

using testing::BlackFraction;
using testing::OneTagRig;
using testing::TestCamera;

using Eigen::Vector2d;
using Eigen::Vector3d;
using tracking::Camera;
using tracking::Rig;

FormationOptions PointSampled(int n) {
  FormationOptions f;
  f.formation = Formation::kPointSampled;
  f.samples_per_axis = n;
  return f;
}

SceneState ObliqueView() {
  SceneState scene;
  scene.flat_lighting = true;
  scene.cam_from_tank =
      tracking::LookAt({0.06, -0.05, 0.2}, {0.02, 0.0, 0}, {0, 1, 0}).Inverse();
  return scene;
}

// Inside the tag's paper square only paper and ink are seen, so with flat
// light a point-sampled pixel is a whole number of ninths of ink; the exact
// formation's edge pixels are not, and the two differ by up to a sample's
// share.
TEST(FormationTest, PointSampledEdgesAreStaircasesNotTheExactRamp) {
  const Camera cam = TestCamera();
  const Rig rig = OneTagRig(0.05);
  const SceneState scene = ObliqueView();
  const cv::Mat exact = SceneRenderer(cam, rig).RenderLinear(scene);
  const cv::Mat sampled =
      SceneRenderer(cam, rig, FloorPattern(), PointSampled(3))
          .RenderLinear(scene);
  // The tag's paper square (black square plus one white cell) in the image.
  const Pose cam_from_tag =
      scene.cam_from_tank * rig.tank_tags[0].object_from_tag;
  const double half = 0.05 * 10.0 / 8.0 / 2 - 1e-3;
  std::vector<cv::Point> square;
  for (auto [x, y] :
       {std::pair{-half, -half}, {half, -half}, {half, half}, {-half, half}}) {
    const Vector2d p = cam.Project(Vector3d(cam_from_tag * Vector3d(x, y, 0)));
    square.emplace_back(int(std::lround(p.x())), int(std::lround(p.y())));
  }
  cv::Mat mask(cam.height, cam.width, CV_8U, cv::Scalar(0));
  cv::fillConvexPoly(mask, square, cv::Scalar(255));
  cv::erode(mask, mask, cv::Mat(), cv::Point(-1, -1), 2);
  int pixels = 0, edge_pixels = 0, off_ninths_exact = 0;
  double max_off_ninths = 0, max_diff = 0, sum_diff = 0;
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      if (!mask.at<uint8_t>(v, u)) continue;
      ++pixels;
      const double s = 9 * BlackFraction(sampled, u, v);
      max_off_ninths = std::max(max_off_ninths, std::abs(s - std::round(s)));
      const double e = BlackFraction(exact, u, v);
      if (e > 0.01 && e < 0.99) {
        ++edge_pixels;
        const double e9 = 9 * e;
        off_ninths_exact += std::abs(e9 - std::round(e9)) > 0.05;
        max_diff = std::max(max_diff, std::abs(s / 9 - e));
        sum_diff += s / 9 - e;
      }
    }
  ASSERT_GT(pixels, 2000);
  ASSERT_GT(edge_pixels, 300);
  EXPECT_LT(max_off_ninths, 1e-3);                    // a staircase of ninths
  EXPECT_GT(off_ninths_exact, edge_pixels / 2);       // the exact ramp is not
  EXPECT_GT(max_diff, 0.04);                          // really different...
  EXPECT_LT(std::abs(sum_diff / edge_pixels), 0.01);  // ...yet unbiased
}

// The rendered outer edge of a tag under strong lens distortion sits where
// cv::projectPoints puts it: per image row the black area across the edge
// gives its position. Point sampling quantises each row's edge to a third
// of a pixel per sample row (errors up to ~1/6 px), but the mean over the
// rows is the projected edge.
TEST(FormationTest, PointSampledEdgeIsUnbiasedUnderDistortion) {
  const double edge = 0.1;
  Camera cam = TestCamera();
  cam.dist = {-0.25, 0.08, 0.001, -0.0008, 0, 0, 0, 0};
  const Rig rig = OneTagRig(edge);
  const SceneState scene = ObliqueView();
  for (int n : {3, 4}) {
    const cv::Mat img = SceneRenderer(cam, rig, FloorPattern(), PointSampled(n))
                            .RenderLinear(scene);
    const Pose cam_from_tag =
        scene.cam_from_tank * rig.tank_tags[0].object_from_tag;
    cv::Mat k = (cv::Mat_<double>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy,
                 0, 0, 1);
    const std::vector<double> dist(cam.dist.begin(), cam.dist.begin() + 5);
    cv::Mat rvec, r_cv(3, 3, CV_64F);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        r_cv.at<double>(i, j) = cam_from_tag.R()(i, j);
    cv::Rodrigues(r_cv, rvec);
    const cv::Mat tvec =
        (cv::Mat_<double>(3, 1) << cam_from_tag.translation.x(),
         cam_from_tag.translation.y(), cam_from_tag.translation.z());
    std::vector<cv::Point3d> edge_pts;
    for (int i = 0; i <= 2000; ++i)
      edge_pts.emplace_back(-edge / 2, -edge / 2 + edge * i / 2000.0, 0);
    std::vector<cv::Point2d> edge_px;
    cv::projectPoints(edge_pts, rvec, tvec, k, dist, edge_px);
    const double cell_px = std::abs(edge_px[2000].y - edge_px[0].y) / 8;
    int rows = 0;
    double sum_err = 0, max_err = 0;
    for (int v = int(edge_px[600].y); v < int(edge_px[1400].y); ++v) {
      double u_edge = 0;
      for (int i = 0; i < 2000; ++i)
        if ((edge_px[i].y - v) * (edge_px[i + 1].y - v) <= 0) {
          const double t =
              (v - edge_px[i].y) / (edge_px[i + 1].y - edge_px[i].y);
          u_edge = edge_px[i].x + t * (edge_px[i + 1].x - edge_px[i].x);
        }
      const int u0 = int(std::floor(u_edge)) - 4,
                u1 = int(std::floor(u_edge + 0.4 * cell_px));
      double black = 0;
      for (int u = u0; u <= u1; ++u) black += BlackFraction(img, u, v);
      const double err = (u1 + 0.5 - black) - u_edge;
      sum_err += err;
      max_err = std::max(max_err, std::abs(err));
      ++rows;
    }
    ASSERT_GT(rows, 20);
    EXPECT_LT(std::abs(sum_err / rows), 0.02) << n << " x " << n;
    EXPECT_LT(max_err, 0.6 / n) << n << " x " << n;
    EXPECT_GT(max_err, 0.02) << n << " x " << n;  // quantised, not exact
  }
}

// A disc kernel of radius 2 sigma blurs an edge as much (same per-axis
// variance) as the Gaussian of sigma, with its own profile, and moves it
// nowhere.
TEST(FormationTest, DiscDefocusKeepsTheEdgeWithAnotherProfile) {
  Camera cam = TestCamera();
  const Rig rig = OneTagRig(0.05);
  SceneState scene = ObliqueView();
  const SceneRenderer renderer(cam, rig);
  ImagingOptions gauss, disc;
  gauss.defocus_sigma_px = disc.defocus_sigma_px = 1.0;
  disc.defocus_kernel = DefocusKernel::kDisc;
  const cv::Mat sharp = renderer.Render(scene, ImagingOptions(), 1).image;
  const cv::Mat g = renderer.Render(scene, gauss, 1).image;
  const cv::Mat d = renderer.Render(scene, disc, 1).image;
  // Different images, the same grey-level sum (blur conserves energy away
  // from the borders: the paper square is far from them).
  EXPECT_GT(cv::norm(g, d, cv::NORM_INF), 3.0);
  const cv::Rect inner(40, 40, cam.width - 80, cam.height - 80);
  const double s0 = cv::sum(sharp(inner))[0], s1 = cv::sum(g(inner))[0],
               s2 = cv::sum(d(inner))[0];
  EXPECT_NEAR(s1 / s0, 1.0, 2e-3);
  EXPECT_NEAR(s2 / s0, 1.0, 2e-3);
}

TEST(FormationTest, VariantsAndOptions) {
  for (const std::string& name : DataVariantNames()) {
    DataVariant v;
    ASSERT_TRUE(GetDataVariant(name, &v)) << name;
    std::string error;
    EXPECT_TRUE(v.formation.IsValid(&error)) << name << ": " << error;
  }
  DataVariant v;
  EXPECT_FALSE(GetDataVariant("ideal", &v));
  ASSERT_TRUE(GetDataVariant("webcam", &v));
  const Camera cam = VariantCamera(v, TestCamera());
  EXPECT_TRUE(cam.HasDistortion());
  EXPECT_EQ(cam.transfer, geometry::Transfer::kSrgb);
  ImagingOptions imaging;
  ApplyVariant(v, &imaging);
  EXPECT_TRUE(imaging.srgb);
  EXPECT_EQ(imaging.defocus_kernel, DefocusKernel::kDisc);
  FormationOptions bad;
  bad.busy_table = true;  // the exact formation draws the plain table only
  std::string error;
  EXPECT_FALSE(bad.IsValid(&error));
  bad = PointSampled(0);
  EXPECT_FALSE(bad.IsValid(&error));
  Formation f;
  EXPECT_TRUE(ParseFormation("supersampled", &f));
  EXPECT_EQ(f, Formation::kPointSampled);
  EXPECT_STREQ(FormationName(f), "supersampled");
  EXPECT_FALSE(ParseFormation("area", &f));
}

}  // namespace
}  // namespace ripple::synth

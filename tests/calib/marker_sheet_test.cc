// Marker sheets: geometry (board tags where the rig puts them, the cube net
// folds onto the rig's faces), exact page sizes in PDF/SVG/PNG, and the
// printed tags as the detector sees them in the PNG.
#include "calib/marker_sheet.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>

#include "calib/sheet_geometry.h"
#include "calib/sheet_writer.h"
#include "calib/tip_check.h"
#include "tracking/synth/floor_pattern.h"
#include "tracking/tag_detector.h"

namespace ripple::calib {
namespace {

tracking::Rig LoadRigFile(const std::string& name) {
  std::string error;
  auto rig = tracking::LoadRig(
      std::string(RIPPLE_SOURCE_DIR) + "/data/rig/" + name, &error);
  EXPECT_TRUE(rig) << error;
  return *rig;
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

TEST(MarkerSheetTest, BoardTagsSitWhereTheRigPutsThem) {
  const tracking::Rig rig = LoadRigFile("default.yml");
  for (const PaperSize& paper : {PaperA4(), PaperLetter()}) {
    Sheet sheet;
    std::string error;
    ASSERT_TRUE(MakeBoardSheet(rig, paper, &sheet, &error)) << error;
    EXPECT_DOUBLE_EQ(sheet.width_m, paper.height_m);  // landscape
    ASSERT_EQ(sheet.tags.size(), rig.tank_tags.size());
    const Eigen::Vector2d centre(sheet.width_m / 2, sheet.height_m / 2);
    for (size_t i = 0; i < sheet.tags.size(); ++i) {
      for (int k = 0; k < 4; ++k) {
        // Sheet (x right, y down) = tank (x, -y) about the page centre.
        const Eigen::Vector3d c = rig.tank_tags[i].CornerInObject(k);
        EXPECT_NEAR((sheet.tags[i].Corner(k) -
                     (centre + Eigen::Vector2d(c.x(), -c.y())))
                        .norm(),
                    0, 1e-12);
      }
    }
  }
}

TEST(MarkerSheetTest, BoardThatDoesNotFitIsRefused) {
  Sheet sheet;
  std::string error;
  EXPECT_FALSE(
      MakeBoardSheet(LoadRigFile("visp_board.yml"), PaperA4(), &sheet, &error));
  EXPECT_NE(error.find("does not fit"), std::string::npos) << error;
}

TEST(MarkerSheetTest, CubeNetFoldsOntoTheRigFaces) {
  const tracking::Rig rig = LoadRigFile("default.yml");
  Sheet sheet;
  std::vector<NetFace> faces;
  std::string error;
  ASSERT_TRUE(MakeCubeNetSheet(rig, PaperA4(), &sheet, &faces, &error))
      << error;
  ASSERT_EQ(faces.size(), 6u);
  ASSERT_EQ(sheet.tags.size(), rig.pen->faces.size());
  // Every tag's printed corners land on the rig's corners once folded.
  for (const SheetTag& tag : sheet.tags) {
    const NetFace* face = nullptr;
    for (const NetFace& f : faces)
      if (f.tag_id == tag.id) face = &f;
    ASSERT_NE(face, nullptr);
    const tracking::TagPlacement* placement = rig.FindPenFace(tag.id);
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(
          (face->PenPoint(tag.Corner(k)) - placement->CornerInObject(k)).norm(),
          0, 1e-12)
          << "tag " << tag.id << " corner " << k;
  }
  // The folded net is a closed cube: six distinct outward normals, each
  // face's page axes orthonormal with the printed side out.
  for (const NetFace& f : faces) {
    EXPECT_NEAR((f.pen_from_page.transpose() * f.pen_from_page -
                 Eigen::Matrix3d::Identity())
                    .norm(),
                0, 1e-12);
    EXPECT_NEAR(f.pen_from_page.determinant(), 1, 1e-12);
    EXPECT_NEAR((f.pen_from_page.col(2) + f.normal_in_pen).norm(), 0, 1e-12);
    for (const NetFace& g : faces) {
      if (&f != &g) {
        EXPECT_GT((f.normal_in_pen - g.normal_in_pen).norm(), 1);
      }
    }
  }
  // 7 glue tabs (one per open cube edge): 3 cut lines each, plus 7 cut
  // edges without a tab, plus the 5 folds between faces and 7 at the tabs.
  int cut = 0, fold = 0;
  for (const SheetLine& l : sheet.lines) {
    cut += l.style == SheetLine::Style::kCut;
    fold += l.style == SheetLine::Style::kFold;
  }
  EXPECT_EQ(fold, 5 + 7);
  EXPECT_EQ(cut, 7 * 3 + 7);
}

TEST(MarkerSheetTest, FilesHaveExactPhysicalSizeAndDetectableTags) {
  const tracking::Rig rig = LoadRigFile("default.yml");
  const std::string dir = ::testing::TempDir() + "/ripple_markers_test";
  std::filesystem::create_directories(dir);
  Sheet sheet;
  std::string error;
  ASSERT_TRUE(MakeBoardSheet(rig, PaperA4(), &sheet, &error)) << error;
  std::vector<std::string> written;
  const double dpi = 200;
  ASSERT_TRUE(WriteSheet(sheet, dir + "/board", dpi, &written, &error))
      << error;
  ASSERT_EQ(written.size(), 3u);
  // PDF: A4 landscape in points.
  const std::string pdf = ReadFile(dir + "/board.pdf");
  EXPECT_NE(pdf.find("/MediaBox [ 0 0 841.889764 595.275591 ]"),
            std::string::npos)
      << pdf.substr(0, 600);
  // SVG: width and height in millimetres.
  const std::string svg = ReadFile(dir + "/board.svg");
  EXPECT_NE(svg.find("width=\"297mm\""), std::string::npos);
  EXPECT_NE(svg.find("height=\"210mm\""), std::string::npos);
  // PNG: the page at `dpi`, with the resolution recorded.
  const std::string png_bytes = ReadFile(dir + "/board.png");
  EXPECT_NE(png_bytes.find("pHYs"), std::string::npos);
  const cv::Mat png = cv::imread(dir + "/board.png", cv::IMREAD_GRAYSCALE);
  const double px_per_m = dpi / 0.0254;
  EXPECT_EQ(png.cols, std::lround(0.297 * px_per_m));
  EXPECT_EQ(png.rows, std::lround(0.210 * px_per_m));
  // Every tag decodes with its own id, its corners where the sheet says
  // (sheet metres -> pixel centres: x * px_per_m - 0.5).
  tracking::TagDetectorOptions options;
  tracking::TagDetector detector(options);
  const auto detections = detector.Detect(png);
  std::map<int, tracking::TagDetection> by_id;
  for (const auto& d : detections) by_id[d.id] = d;
  ASSERT_EQ(by_id.size(), rig.tank_tags.size());
  double worst = 0;
  for (const SheetTag& tag : sheet.tags) {
    ASSERT_TRUE(by_id.count(tag.id)) << tag.id;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d expected =
          tag.Corner(k) * px_per_m - Eigen::Vector2d(0.5, 0.5);
      worst = std::max(worst, (by_id[tag.id].corners[k] - expected).norm());
    }
  }
  std::printf("worst printed-corner error %.3f px at %g dpi\n", worst, dpi);
  EXPECT_LT(worst, 0.5);
}

TEST(MarkerSheetTest, CubeNetTagsDecode) {
  const tracking::Rig rig = LoadRigFile("default.yml");
  const std::string dir = ::testing::TempDir() + "/ripple_markers_test";
  std::filesystem::create_directories(dir);
  Sheet sheet;
  std::vector<NetFace> faces;
  std::string error;
  ASSERT_TRUE(MakeCubeNetSheet(rig, PaperLetter(), &sheet, &faces, &error));
  std::vector<std::string> written;
  ASSERT_TRUE(WriteSheet(sheet, dir + "/net", 200, &written, &error)) << error;
  const cv::Mat png = cv::imread(dir + "/net.png", cv::IMREAD_GRAYSCALE);
  tracking::TagDetector detector{tracking::TagDetectorOptions()};
  std::set<int> ids;
  for (const auto& d : detector.Detect(png)) ids.insert(d.id);
  EXPECT_EQ(ids, (std::set<int>{10, 11, 12, 13, 14}));
}

synth::FloorPattern MakeFloor(const tracking::Rig& rig,
                              const synth::FloorOptions& options) {
  std::string error;
  auto floor = synth::FloorPattern::Create(options, rig.tank, &error);
  EXPECT_TRUE(floor) << error;
  return floor.value_or(synth::FloorPattern());
}

// The tank's interior on a board sheet (page centre = tank origin, tank y up
// the page).
Eigen::AlignedBox2d TankOnSheet(const tracking::Rig& rig, const Sheet& sheet) {
  const Eigen::Vector2d c(sheet.width_m / 2, sheet.height_m / 2);
  const Eigen::Vector2d h(rig.tank.size_x_m / 2, rig.tank.size_y_m / 2);
  return Eigen::AlignedBox2d(c - h, c + h);
}

TEST(MarkerSheetTest, TiledFloorKeepsEverythingPrintedOffIt) {
  const tracking::Rig rig = LoadRigFile("default.yml");
  const synth::FloorPattern tiles = MakeFloor(rig, synth::FloorOptions());
  sheet::FamilyInfo f;
  std::string error;
  ASSERT_TRUE(sheet::GetFamily(rig.family, &f, &error));
  for (const PaperSize& paper : {PaperA4(), PaperLetter()}) {
    Sheet plain, tiled;
    ASSERT_TRUE(MakeBoardSheet(rig, paper, &plain, &error)) << error;
    ASSERT_TRUE(MakeBoardSheet(rig, paper, tiles, &tiled, &error)) << error;
    EXPECT_EQ(plain.floor.kind(), synth::FloorKind::kPlain);
    EXPECT_EQ(tiled.floor.kind(), synth::FloorKind::kTiles);
    const Eigen::AlignedBox2d tank = TankOnSheet(rig, tiled);
    EXPECT_NEAR((tiled.tank_origin_m - tank.center()).norm(), 0, 1e-12);
    // The same tags and check points as on the plain sheet.
    ASSERT_EQ(tiled.tags.size(), plain.tags.size());
    for (size_t i = 0; i < tiled.tags.size(); ++i)
      EXPECT_NEAR((tiled.tags[i].centre_m - plain.tags[i].centre_m).norm(), 0,
                  1e-12);
    ASSERT_EQ(tiled.circles.size(), BoardCheckPoints(rig).size());
    for (const CheckPoint& p : BoardCheckPoints(rig)) {
      bool named = false;
      for (const SheetText& t : tiled.texts) named |= t.text == p.name;
      EXPECT_TRUE(named) << p.name;
    }
    // Tag labels keep off the floor; scale-bar blocks on the floor sit on a
    // white ground.
    for (const SheetTag& tag : tiled.tags)
      EXPECT_FALSE(sheet::TagBox(tag, f).intersects(tank)) << tag.id;
    for (const Eigen::AlignedBox2d& b : tiled.black_boxes) {
      if (!b.intersects(tank)) continue;
      bool grounded = false;
      for (const Eigen::AlignedBox2d& w : tiled.white_boxes)
        grounded |= w.contains(b);
      EXPECT_TRUE(grounded) << paper.name;
    }
  }
  // A floor made for another tank is refused.
  const synth::FloorPattern other =
      *synth::FloorPattern::Create(synth::FloorOptions(), 0.1, 0.1, &error);
  Sheet sheet;
  EXPECT_FALSE(MakeBoardSheet(rig, PaperA4(), other, &sheet, &error));
}

TEST(MarkerSheetTest, PrintedFloorHasItsColoursAndTagsStillDecode) {
  const tracking::Rig rig = LoadRigFile("default.yml");
  const std::string dir = ::testing::TempDir() + "/ripple_markers_floor";
  std::filesystem::create_directories(dir);
  const synth::FloorOptions options;
  Sheet sheet;
  std::string error;
  ASSERT_TRUE(
      MakeBoardSheet(rig, PaperA4(), MakeFloor(rig, options), &sheet, &error))
      << error;
  std::vector<std::string> written;
  const double dpi = 200, px_per_m = dpi / 0.0254;
  ASSERT_TRUE(WriteSheet(sheet, dir + "/board", dpi, &written, &error))
      << error;
  const cv::Mat png = cv::imread(dir + "/board.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(png.empty());
  // A tank point's pixel (tank y up the page).
  auto pixel = [&](double x, double y) {
    const Eigen::Vector2d s = sheet.tank_origin_m + Eigen::Vector2d(x, -y);
    return png.at<cv::Vec3b>(static_cast<int>(s.y() * px_per_m),
                             static_cast<int>(s.x() * px_per_m));
  };
  // Printed value: sRGB of albedo relative to the paper.
  auto printed = [](const cv::Vec3f& albedo, int k) {
    const double c = albedo[k] / synth::kPaperBgr[k];
    return 255 *
           (c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055);
  };
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(pixel(0.010, 0.010)[k], printed(options.tile_a_bgr, k), 1.5);
    EXPECT_NEAR(pixel(0.020, 0.010)[k], printed(options.tile_b_bgr, k), 1.5);
    EXPECT_NEAR(pixel(0.015, 0.012)[k], printed(options.grout_bgr, k), 1.5);
    EXPECT_EQ(pixel(0.0, 0.065)[k], 255);  // paper between tank and tags
  }
  // The board's tags decode where the sheet says, floor or not.
  cv::Mat gray;
  cv::cvtColor(png, gray, cv::COLOR_BGR2GRAY);
  tracking::TagDetector detector{tracking::TagDetectorOptions()};
  std::map<int, tracking::TagDetection> by_id;
  for (const auto& d : detector.Detect(gray)) by_id[d.id] = d;
  ASSERT_EQ(by_id.size(), rig.tank_tags.size());
  double worst = 0;
  for (const SheetTag& tag : sheet.tags) {
    ASSERT_TRUE(by_id.count(tag.id)) << tag.id;
    for (int k = 0; k < 4; ++k)
      worst = std::max(worst,
                       (by_id[tag.id].corners[k] -
                        (tag.Corner(k) * px_per_m - Eigen::Vector2d(0.5, 0.5)))
                           .norm());
  }
  EXPECT_LT(worst, 0.5);
}

TEST(MarkerSheetTest, ImageFloorIsPrintedOverTheTankAsGiven) {
  const tracking::Rig rig = LoadRigFile("default.yml");
  const std::string dir = ::testing::TempDir() + "/ripple_markers_image";
  std::filesystem::create_directories(dir);
  // 2 x 2: red, green on top; blue, grey below.
  cv::Mat img(2, 2, CV_8UC3);
  img.at<cv::Vec3b>(0, 0) = {0, 0, 255};
  img.at<cv::Vec3b>(0, 1) = {0, 255, 0};
  img.at<cv::Vec3b>(1, 0) = {255, 0, 0};
  img.at<cv::Vec3b>(1, 1) = {128, 128, 128};
  ASSERT_TRUE(cv::imwrite(dir + "/floor.png", img));
  synth::FloorOptions options;
  options.kind = synth::FloorKind::kImage;
  options.image_path = dir + "/floor.png";
  Sheet sheet;
  std::string error;
  ASSERT_TRUE(
      MakeBoardSheet(rig, PaperA4(), MakeFloor(rig, options), &sheet, &error))
      << error;
  std::vector<std::string> written;
  const double dpi = 100, px_per_m = dpi / 0.0254;
  ASSERT_TRUE(WriteSheet(sheet, dir + "/board", dpi, &written, &error))
      << error;
  const cv::Mat png = cv::imread(dir + "/board.png", cv::IMREAD_COLOR);
  auto pixel = [&](double x, double y) {
    const Eigen::Vector2d s = sheet.tank_origin_m + Eigen::Vector2d(x, -y);
    return png.at<cv::Vec3b>(static_cast<int>(s.y() * px_per_m),
                             static_cast<int>(s.x() * px_per_m));
  };
  // Quadrant centres, away from the check points.
  const std::pair<Eigen::Vector2d, cv::Vec3b> expected[] = {
      {{-0.06, 0.04}, img.at<cv::Vec3b>(0, 0)},
      {{0.06, 0.04}, img.at<cv::Vec3b>(0, 1)},
      {{-0.06, -0.04}, img.at<cv::Vec3b>(1, 0)},
      {{0.06, -0.04}, img.at<cv::Vec3b>(1, 1)}};
  for (const auto& [at, bgr] : expected)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(pixel(at.x(), at.y())[k], bgr[k], 2) << at.transpose();
}

TEST(MarkerSheetTest, ChessboardFitsA4AndLetter) {
  for (const PaperSize& paper : {PaperA4(), PaperLetter()}) {
    Sheet sheet;
    std::string error;
    ASSERT_TRUE(MakeChessboardSheet(9, 6, 0.025, paper, &sheet, &error))
        << error;
    EXPECT_EQ(sheet.black_boxes.size(), 35u + 5u);  // 10x7 squares + bar
  }
}

}  // namespace
}  // namespace ripple::calib

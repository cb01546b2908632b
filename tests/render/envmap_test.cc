// The environment cube map (render/pass_envmap.h): the fold's geometry (the
// square-to-quad homography, GL's cube face convention), golden faces of a
// synthetic frame with one colour per piece of the fold, the projective fix
// of the trapezoid artefact, and the reflected-ray lookup through the whole
// renderer for known surface normals. GL parts on EGL/llvmpipe; they skip
// without a context (fail under CI=true).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "render/frame_state.h"
#include "render/gl.h"
#include "render/gl_objects.h"
#include "render/optics.h"
#include "render/pass_envmap.h"
#include "render/renderer.h"
#include "tests/render/render_test_util.h"

namespace ripple::render {
namespace {

using internal::CubeFaceOf;
using internal::EnvMapBox;
using internal::EnvMapFaceQuad;
using internal::SquareToQuad;

TEST(SquareToQuadTest, MapsTheCornersAndTheCentreToTheDiagonalsCrossing) {
  // A trapezoid like a side face's piece: short edge at the box, long edge
  // at the image border.
  const std::array<glm::dvec2, 4> q = {
      {{0.3, 0.3}, {0.7, 0.3}, {1.0, 0.0}, {0.0, 0.0}}};
  const SquareToQuad m = SquareToQuad::FromCorners(q);
  const double uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int i = 0; i < 4; ++i) {
    const glm::dvec2 p = m.Map(uv[i][0], uv[i][1]);
    EXPECT_NEAR(p.x, q[i].x, 1e-12);
    EXPECT_NEAR(p.y, q[i].y, 1e-12);
  }
  // A projective map keeps lines and incidence: the square's centre (where
  // its diagonals cross) goes to where the quad's diagonals cross, here at
  // y = 0.3 * 1 / (1 + 0.4) of the way (the similar triangles of the two
  // parallel edges, 1.0 and 0.4 long).
  const glm::dvec2 c = m.Map(0.5, 0.5);
  EXPECT_NEAR(c.x, 0.5, 1e-12);
  EXPECT_NEAR(c.y, 0.3 / 1.4, 1e-12);
  // Two affine triangles would put it at the middle of the shared diagonal
  // (0,0)-(1,1): 0.15 instead of 0.214, the trapezoid artefact's crease.
  EXPECT_GT(std::abs(c.y - 0.5 * (q[0].y + q[2].y)), 0.05);
}

TEST(CubeFaceTest, FollowsGlsFaceConvention) {
  glm::dvec2 st;
  EXPECT_EQ(CubeFaceOf({1, 0, 0}, &st), internal::kPosX);
  EXPECT_NEAR(st.x, 0.5, 1e-12);
  EXPECT_NEAR(st.y, 0.5, 1e-12);
  EXPECT_EQ(CubeFaceOf({0, -1, 0}, nullptr), internal::kNegY);
  EXPECT_EQ(CubeFaceOf({0, 0, -2}, nullptr), internal::kNegZ);
  // +x face: s runs against z, t against y (table 8.19).
  CubeFaceOf({1, -0.5, 0.5}, &st);
  EXPECT_NEAR(st.x, 0.25, 1e-12);
  EXPECT_NEAR(st.y, 0.75, 1e-12);
  // -y face: s with x, t against z.
  EXPECT_EQ(CubeFaceOf({0.5, -1, 0.5}, &st), internal::kNegY);
  EXPECT_NEAR(st.x, 0.75, 1e-12);
  EXPECT_NEAR(st.y, 0.25, 1e-12);
}

// Whether normalised point p lies inside the convex quad q (either winding).
bool InQuad(const std::array<glm::dvec2, 4>& q, const glm::dvec2& p) {
  int pos = 0, neg = 0;
  for (int i = 0; i < 4; ++i) {
    const glm::dvec2 a = q[i], b = q[(i + 1) % 4];
    const double c = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
    pos += c > 0;
    neg += c < 0;
  }
  return pos == 0 || neg == 0;
}

// One colour (linear RGB) per piece of the fold; the frame's centre box
// black (kPosZ), the face behind the camera has no piece of its own.
const glm::vec3 kPieceColor[5] = {
    {1, 0, 1},  // kPosX, right: magenta
    {1, 1, 0},  // kNegX, left: yellow
    {0, 0, 1},  // kPosY, bottom: blue
    {0, 1, 0},  // kNegY, top: green
    {0, 0, 0},  // kPosZ, the box: black
};

// A w x h RGBA float frame (top row first) painted by piece for `box`.
std::vector<glm::vec4> PaintPieces(int w, int h, const glm::dvec4& box) {
  std::vector<glm::vec4> px(static_cast<size_t>(w) * h, glm::vec4(0.5f));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const glm::dvec2 p((x + 0.5) / w, (y + 0.5) / h);
      for (int f = internal::kPosZ; f >= internal::kPosX; --f) {
        if (InQuad(EnvMapFaceQuad(f, box), p)) {
          px[static_cast<size_t>(y) * w + x] = glm::vec4(kPieceColor[f], 1.0f);
          break;
        }
      }
    }
  }
  return px;
}

struct FaceImages {
  int n = 0;
  std::vector<glm::vec4> face[internal::kNumFaces];  // row t, column s
  glm::vec3 At(int f, double s, double t) const {
    const int i = std::clamp(int(s * n), 0, n - 1);
    const int j = std::clamp(int(t * n), 0, n - 1);
    return glm::vec3(face[f][static_cast<size_t>(j) * n + i]);
  }
};

FaceImages ReadFaces(const internal::EnvMapPass& pass) {
  FaceImages out;
  out.n = pass.options().face_size;
  internal::Framebuffer fbo;
  fbo.Create();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
  for (int f = 0; f < internal::kNumFaces; ++f) {
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                           GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, pass.texture(),
                           0);
    out.face[f].resize(static_cast<size_t>(out.n) * out.n);
    glReadPixels(0, 0, out.n, out.n, GL_RGBA, GL_FLOAT, out.face[f].data());
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return out;
}

class EnvMapGlTest : public ::testing::Test {
 protected:
  static constexpr int kW = 640, kH = 480, kSrcW = 160, kSrcH = 120;
  void SetUp() override {
    k_ = testing::MakeIntrinsics(kW, kH);
    cam_from_tank_ = testing::LookAt({0.0, -0.24, 0.22}, {0, 0, 0});
  }
  // Builds the cube map from `src` (kSrcW x kSrcH linear RGBA floats).
  bool Build(const std::vector<glm::vec4>& src, internal::EnvMapPass* pass) {
    std::string error;
    if (!pass->Create({}, &error)) {
      ADD_FAILURE() << error;
      return false;
    }
    glActiveTexture(GL_TEXTURE0);
    internal::AllocTexture(&source_, GL_RGBA16F, kSrcW, kSrcH, GL_RGBA,
                           GL_FLOAT, GL_LINEAR, GL_CLAMP_TO_EDGE, src.data());
    pass->Rebuild(source_.id(), k_, cam_from_tank_, tank_,
                  std::vector<std::uint8_t>(3 * 32 * 24, 0), 0);
    return glGetError() == GL_NO_ERROR;
  }
  Intrinsics k_;
  glm::dmat4 cam_from_tank_{1.0};
  TankGeometry tank_;
  internal::Texture source_;
};

TEST_F(EnvMapGlTest, EachPieceOfTheFrameLandsOnItsFace) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, 64, 64);
  const internal::EnvMapPass::Options defaults;
  const glm::dvec4 box = EnvMapBox(k_, cam_from_tank_, tank_,
                                   defaults.box_scale, defaults.box_margin);
  // The box holds the tank and lies inside the frame's margins.
  EXPECT_GE(box.x, defaults.box_margin - 1e-12);
  EXPECT_LE(box.z, 1 - defaults.box_margin + 1e-12);
  EXPECT_LT(box.x, box.z);
  EXPECT_LT(box.y, box.w);
  internal::EnvMapPass pass;
  ASSERT_TRUE(Build(PaintPieces(kSrcW, kSrcH, box), &pass));
  const FaceImages faces = ReadFaces(pass);
  // Away from the faces' edges (where the pieces' borders blur over a
  // source texel), every texel of a side face or of the box's face has its
  // piece's colour; tolerance: bilinear filtering at the pieces' diagonal
  // borders reaches 1 source texel (1/64 of the face at most) inward.
  int checked = 0;
  for (int f = internal::kPosX; f <= internal::kPosZ; ++f) {
    for (double t = 0.2; t <= 0.8; t += 0.05) {
      for (double s = 0.2; s <= 0.8; s += 0.05) {
        const glm::vec3 c = faces.At(f, s, t);
        const glm::vec3 e = kPieceColor[f];
        ASSERT_LT(glm::length(c - e), 0.05f)
            << "face " << f << " at (" << s << ", " << t << ")";
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 600);
  // Behind the camera: the whole frame mirrored left to right, so its
  // centre is the box's colour and its edges meet the side faces: its s = 0
  // edge (towards +x) shows the frame's right border (magenta), s = 1 the
  // left (yellow), t = 0 the bottom (blue), t = 1 the top (green).
  EXPECT_LT(glm::length(faces.At(internal::kNegZ, 0.5, 0.5) - kPieceColor[4]),
            0.05f);
  EXPECT_LT(glm::length(faces.At(internal::kNegZ, 0.02, 0.5) - kPieceColor[0]),
            0.05f);
  EXPECT_LT(glm::length(faces.At(internal::kNegZ, 0.98, 0.5) - kPieceColor[1]),
            0.05f);
  EXPECT_LT(glm::length(faces.At(internal::kNegZ, 0.5, 0.02) - kPieceColor[2]),
            0.05f);
  EXPECT_LT(glm::length(faces.At(internal::kNegZ, 0.5, 0.98) - kPieceColor[3]),
            0.05f);
  // Neighbouring faces agree along their shared edge: +x's outer edge
  // (s = 1) and -z's s = 0 edge are the frame's right border.
  for (double t = 0.1; t < 0.95; t += 0.1) {
    EXPECT_LT(glm::length(faces.At(internal::kPosX, 0.99, t) -
                          faces.At(internal::kNegZ, 0.01, t)),
              0.05f);
  }
}

TEST_F(EnvMapGlTest, TrapezoidsMapProjectivelyWithoutACrease) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, 64, 64);
  const internal::EnvMapPass::Options defaults;
  const glm::dvec4 box = EnvMapBox(k_, cam_from_tank_, tank_,
                                   defaults.box_scale, defaults.box_margin);
  // A bright dot where the top piece's diagonals cross, on black: the
  // projective map puts it at the face's centre; two affine triangles split
  // along a diagonal would move it along that diagonal.
  const auto quad = EnvMapFaceQuad(internal::kNegY, box);
  const glm::dvec2 centre = SquareToQuad::FromCorners(quad).Map(0.5, 0.5);
  std::vector<glm::vec4> src(static_cast<size_t>(kSrcW) * kSrcH,
                             glm::vec4(0, 0, 0, 1));
  for (int y = 0; y < kSrcH; ++y) {
    for (int x = 0; x < kSrcW; ++x) {
      const double dx = (x + 0.5) / kSrcW - centre.x;
      const double dy = (y + 0.5) / kSrcH - centre.y;
      if (std::hypot(dx * kSrcW, dy * kSrcH) < 1.6)
        src[static_cast<size_t>(y) * kSrcW + x] = glm::vec4(1.0f);
    }
  }
  internal::EnvMapPass pass;
  ASSERT_TRUE(Build(src, &pass));
  const FaceImages faces = ReadFaces(pass);
  // The dot's centroid on the top face.
  const int n = faces.n;
  double sum = 0, su = 0, sv = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double v = faces.face[internal::kNegY][j * n + i].g;
      sum += v;
      su += v * (i + 0.5) / n;
      sv += v * (j + 0.5) / n;
    }
  }
  ASSERT_GT(sum, 1.0);
  EXPECT_NEAR(su / sum, 0.5, 1.0 / n);
  EXPECT_NEAR(sv / sum, 0.5, 1.0 / n);
  // The affine split's centre: the middle of the quad's (0,0)-(1,1)
  // diagonal, mapped back into the face by the true homography, is far
  // from the centre: the test tells the two apart.
  const glm::dvec2 affine = 0.5 * (quad[0] + quad[2]);
  EXPECT_GT(glm::length(affine - centre) * kSrcH, 3.0);
}

// The test scene over a frame painted by piece (PaintPieces, the tank's box
// black), without shadows, caustics and walls, the light placed so that no
// glint falls near the tank's centre.
testing::TestScene PaintedScene(int w, int h, testing::View view,
                                const EnvMapOptions& e,
                                const glm::dmat4* cam_from_tank = nullptr) {
  testing::TestScene s = testing::MakeScene(w, h, view, false);
  SceneInputs& in = s.inputs;
  if (cam_from_tank != nullptr) in.cam_from_tank = *cam_from_tank;
  const glm::dvec4 box =
      EnvMapBox(s.k, in.cam_from_tank, in.tank, e.box_scale, e.box_margin);
  const std::vector<glm::vec4> pieces = PaintPieces(w, h, box);
  for (size_t i = 0; i < pieces.size(); ++i) {
    for (int ch = 0; ch < 3; ++ch)  // BGR8
      s.video[3 * i + ch] = static_cast<std::uint8_t>(255 * pieces[i][2 - ch]);
  }
  in.effects.shadows = in.effects.caustics = in.effects.walls = false;
  in.light_in_tank = {-0.3, -1.0, 0.4};
  return s;
}

// The renderer with the cube map over a frame painted by piece (the tank's
// box black, so the water shows only its reflection): the reflection of the
// water's centre takes the colour of the face its reflected ray points at,
// for flat water seen from the front (the frame's top) and for surfaces
// tilted either way along x seen from above (the frame's right and left).
TEST(EnvMapLookupTest, ReflectedRayFindsTheExpectedFace) {
  constexpr int kW = 320, kH = 240;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  RendererOptions options;
  options.reflection_map = ReflectionMap::kCubeMap;
  // Rays climbing over 20 degrees blend towards the overhead sky (radiance
  // the ambient share, see SteepReflectionsSeeTheSkyOverhead): a black sky
  // keeps each face's chromaticity.
  options.optics.ambient_share = 0.0f;
  const Intrinsics k0 = testing::MakeIntrinsics(kW, kH);
  std::string error;
  auto renderer = Renderer::TryCreate(ctx.get(), k0, options, &error);
  ASSERT_NE(renderer, nullptr) << error;
  std::vector<std::uint8_t> out(static_cast<size_t>(kW) * kH * 3);
  const struct {
    testing::View view;
    double slope;  // dh/dx at the centre
    int face;      // where its reflected ray points
  } cases[] = {{testing::View::kFront, 0.0, internal::kNegY},
               {testing::View::kTop, 0.6, internal::kNegX},
               {testing::View::kTop, -0.6, internal::kPosX}};
  int rebuilds = 0;
  std::uint64_t counter = 0;
  for (const auto& c : cases) {
    SCOPED_TRACE(c.slope);
    testing::TestScene s = PaintedScene(kW, kH, c.view, options.envmap);
    SceneInputs& in = s.inputs;
    // h = slope * x * exp(-x^2 / (2 sigma^2)): the normal (-slope, 0, 1)
    // at the centre, the surface within 2.5 mm of the rest level.
    const int nx = 256, ny = 166;
    const float d = in.tank.size_x / nx;
    const double sigma = 0.006;
    std::vector<float> heights(nx * ny);
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const double x = (i + 0.5 - 0.5 * nx) * d;
        heights[j * nx + i] = static_cast<float>(
            c.slope * x * std::exp(-x * x / (2 * sigma * sigma)));
      }
    }
    in.water = {heights.data(), nx, ny, d, ++counter};  // a new surface
    ASSERT_TRUE(renderer->Render(in));
    rebuilds += renderer->timings().envmap_rebuilt;
    ASSERT_TRUE(renderer->ReadBgr(out.data()));
    // The expected face from the geometry.
    const glm::dvec3 centre(0.0, 0.0, in.tank.water_level);
    const glm::dvec3 eye(glm::inverse(in.cam_from_tank)[3]);
    const glm::dvec3 n = glm::normalize(glm::dvec3(-c.slope, 0.0, 1.0));
    const glm::dvec3 r = glm::reflect(glm::normalize(centre - eye), n);
    const int face = CubeFaceOf(glm::dmat3(in.cam_from_tank) * r, nullptr);
    ASSERT_EQ(face, c.face);
    // The pixel's colour is the face's piece's times Fresnel (a few per
    // cent, over the black floor): compare its chromaticity.
    const glm::dvec4 p = in.cam_from_tank * glm::dvec4(centre, 1.0);
    const int u = static_cast<int>(std::lround(s.k.fx * p.x / p.z + s.k.cx));
    const int v = static_cast<int>(std::lround(s.k.fy * p.y / p.z + s.k.cy));
    glm::dvec3 px(0.0);
    for (int dv = -1; dv <= 1; ++dv)
      for (int du = -1; du <= 1; ++du)
        for (int ch = 0; ch < 3; ++ch)
          px[2 - ch] += out[3 * ((v + dv) * kW + u + du) + ch];
    ASSERT_GT(std::max({px.r, px.g, px.b}), 9 * 20.0);
    const glm::dvec3 want(kPieceColor[face]);
    const glm::dvec3 got = px / std::max({px.r, px.g, px.b});
    EXPECT_LT(glm::length(got - want), 0.35)
        << "face " << face << ", pixel " << px.r / 9 << " " << px.g / 9 << " "
        << px.b / 9;
  }
  // A new view is a new fold; the same view and frame again is not.
  EXPECT_EQ(rebuilds, 2);  // front, then top (the tilt alone changes nothing)
}

// What the water's reflection adds at the tank's centre, in linear light per
// band (r, g, b), over a frame painted in saturated pieces, the sky alone
// lighting the board (radiance 1); `r` gets the reflected ray there.
// cam_from_tank, if given, replaces the view's pose; video, if given, gets
// the painted frame (BGR8).
bool ReflectionAddedAtCentre(Context* ctx, ReflectionMap map,
                             testing::View view, glm::dvec3* added,
                             glm::dvec3* r,
                             const glm::dmat4* cam_from_tank = nullptr,
                             std::vector<std::uint8_t>* video = nullptr) {
  constexpr int kW = 320, kH = 240;
  RendererOptions options;
  options.reflection_map = map;
  options.optics.ambient_share = 1.0f;
  const Intrinsics k0 = testing::MakeIntrinsics(kW, kH);
  std::string error;
  auto renderer = Renderer::TryCreate(ctx, k0, options, &error);
  if (renderer == nullptr) {
    ADD_FAILURE() << error;
    return false;
  }
  testing::TestScene s =
      PaintedScene(kW, kH, view, options.envmap, cam_from_tank);
  if (video != nullptr) *video = s.video;
  SceneInputs& in = s.inputs;
  in.effects.refraction = false;  // the water shows its reflection only
  std::vector<std::uint8_t> on(static_cast<size_t>(kW) * kH * 3);
  std::vector<std::uint8_t> off(on.size());
  if (!renderer->Render(in) || !renderer->ReadBgr(on.data())) return false;
  in.effects.reflection = false;
  if (!renderer->Render(in) || !renderer->ReadBgr(off.data())) return false;
  const glm::dvec3 centre(0.0, 0.0, in.tank.water_level);
  const glm::dvec3 eye(glm::inverse(in.cam_from_tank)[3]);
  *r = glm::reflect(glm::normalize(centre - eye), glm::dvec3(0.0, 0.0, 1.0));
  const glm::dvec4 p = in.cam_from_tank * glm::dvec4(centre, 1.0);
  const int u = static_cast<int>(std::lround(s.k.fx * p.x / p.z + s.k.cx));
  const int v = static_cast<int>(std::lround(s.k.fy * p.y / p.z + s.k.cy));
  for (int ch = 0; ch < 3; ++ch) {
    const size_t i = 3 * (static_cast<size_t>(v) * kW + u) + ch;
    (*added)[2 - ch] =
        SrgbToLinear(on[i] / 255.0) - SrgbToLinear(off[i] / 255.0);
  }
  return true;
}

// No camera looking at a table sees what is overhead: reflected rays that
// climb steeply take the sky the lighting assumes (uniform, of radiance the
// ambient share), whatever the frame shows, with the fold and the cube map
// alike. Flat water seen from straight above over a frame painted in
// saturated pieces reflects grey, Fresnel times the sky: R(0) a.
TEST(EnvMapLookupTest, SteepReflectionsSeeTheSkyOverhead) {
  constexpr int kW = 320, kH = 240;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  for (ReflectionMap map : {ReflectionMap::kFold, ReflectionMap::kCubeMap}) {
    SCOPED_TRACE(static_cast<int>(map));
    glm::dvec3 added, r;
    ASSERT_TRUE(ReflectionAddedAtCentre(ctx.get(), map, testing::View::kTop,
                                        &added, &r));
    ASSERT_GT(r.z, 0.9);  // the reflected ray at the centre climbs steeply
    // Fresnel at normal incidence for water: ((n - 1) / (n + 1))^2 = 0.0204,
    // times the sky's radiance 1; the 8-bit levels near the floor's colour
    // are about 0.004 apart in linear light.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(added[c], 0.0204, 0.006) << c;
  }
}

// The fold reads the frame only where the camera looks: a reflected ray
// whose direction lies outside the image sees what no frame shows, the sky,
// not the image's border. From the front (the reflected ray 42 degrees up,
// its vanishing point 76 degrees above the optical axis, the image's half
// height 23), flat water reflects grey: R(theta) a, with no trace of the
// painted frame.
TEST(EnvMapLookupTest, TheFoldReadsTheFrameOnlyWhereTheCameraLooks) {
  constexpr int kW = 320, kH = 240;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  glm::dvec3 added, r;
  ASSERT_TRUE(ReflectionAddedAtCentre(ctx.get(), ReflectionMap::kFold,
                                      testing::View::kFront, &added, &r));
  ASSERT_LT(r.z, 0.8);  // the elevation blend alone would keep the frame
  const double fresnel = FresnelReflectance(r.z, 1.0, WaterOptics{}.ior);
  ASSERT_GT(fresnel, 0.025);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(added[c], fresnel, 0.004) << c;
}

// A ray reflected upwards never comes down to the table, so the fold reads
// each direction at its vanishing point (the surroundings far away), not at
// a point at a finite distance, which a grazing view finds on the table
// beyond the tank.
// - Grazing (the camera 17 degrees down, the reflected ray 15 degrees up):
//   a point 0.3 m along the ray lies 15 degrees above the optical axis,
//   inside the image, on the painted table; the direction itself lies 32
//   degrees above the axis, outside the image (half height 23): the water
//   reflects the sky, R(theta) a.
// - Almost level (the camera 6 degrees down): the direction lies 12 degrees
//   above the axis, inside the image, and the water reflects the frame
//   there, R(theta) times its colour.
TEST(EnvMapLookupTest, TheFoldReadsEachDirectionAtItsVanishingPoint) {
  constexpr int kW = 320, kH = 240;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  const double ior = WaterOptics{}.ior;
  {
    SCOPED_TRACE("grazing");
    const glm::dmat4 pose = testing::LookAt({0.0, -0.35, 0.12}, {0, 0, 0.015});
    glm::dvec3 added, r;
    ASSERT_TRUE(ReflectionAddedAtCentre(ctx.get(), ReflectionMap::kFold,
                                        testing::View::kFront, &added, &r,
                                        &pose));
    const glm::dvec3 c = glm::dmat3(pose) * r;
    ASSERT_LT(c.y / c.z, -std::tan(23.5 * M_PI / 180.0));  // above the top
    const double fresnel = FresnelReflectance(r.z, 1.0, ior);
    ASSERT_GT(fresnel, 0.1);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(added[ch], fresnel, 0.006) << ch;
  }
  {
    SCOPED_TRACE("level");
    const glm::dmat4 pose = testing::LookAt({0.0, -0.45, 0.075}, {0, 0, 0.025});
    glm::dvec3 added, r;
    std::vector<std::uint8_t> video;
    ASSERT_TRUE(ReflectionAddedAtCentre(ctx.get(), ReflectionMap::kFold,
                                        testing::View::kFront, &added, &r,
                                        &pose, &video));
    const glm::dvec3 c = glm::dmat3(pose) * r;
    const Intrinsics k = testing::MakeIntrinsics(kW, kH);
    const int u = static_cast<int>(std::lround(k.fx * c.x / c.z + k.cx));
    const int v = static_cast<int>(std::lround(k.fy * c.y / c.z + k.cy));
    ASSERT_GT(v, kH / 8);  // well inside the image, clear of the fade
    // The painted frame is one colour 16 px around the vanishing point, so
    // the blurred copy the fold reads holds that colour there.
    const size_t at = 3 * (static_cast<size_t>(v) * kW + u);
    for (int dy = -16; dy <= 16; dy += 4) {
      for (int dx = -16; dx <= 16; dx += 4) {
        const size_t i = 3 * (static_cast<size_t>(v + dy) * kW + u + dx);
        for (int ch = 0; ch < 3; ++ch) ASSERT_EQ(video[i + ch], video[at + ch]);
      }
    }
    const double fresnel = FresnelReflectance(r.z, 1.0, ior);
    ASSERT_GT(fresnel, 0.3);
    for (int ch = 0; ch < 3; ++ch) {
      const double seen = SrgbToLinear(video[at + 2 - ch] / 255.0);
      EXPECT_NEAR(added[ch], fresnel * seen, 0.02) << ch;
    }
    // The frame's pieces differ in colour, so the sky alone would not do.
    double off_sky = 0.0;
    for (int ch = 0; ch < 3; ++ch)
      off_sky = std::max(off_sky, std::abs(added[ch] - fresnel));
    EXPECT_GT(off_sky, 0.1);
  }
}

}  // namespace
}  // namespace ripple::render

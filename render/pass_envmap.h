// Environment cube map pass (internal to render/): the camera image folded
// into the six faces of a cube map, after Ropinski, Wachenfeld & Hinrichs,
// "Virtual reflections for augmented reality environments" (ICAT 2004), as
// Milsap & Bourland build it with an FBO in their mobile AR renderer
// ("Advanced Rendering for Augmented Reality on Mobile Devices").
//
// The cube's frame is the camera's at the last rebuild (OpenCV axes: x
// right, y down, z forward). The tank's projected bounding box (tank and
// walls, grown about its centre and clamped inside the image, EnvMapBox)
// cuts the frame into five pieces: the box itself is what lies behind the
// tank (+z), the four trapezoids between the box and the image corners are
// the sides (+x right, -x left, -y top, +y bottom; each face's edge at the
// box meets the +z face, its outer edge the image border), and the whole
// frame, mirrored left to right, is the face behind the camera (-z): its
// border is the outer border the side faces end on, so the six faces join
// without seams. Each face is one quad whose texture coordinates are
// homogeneous (s q, t q, q) from the homography of the face's square onto
// its piece of the image: interpolated linearly and divided per fragment,
// they map the square onto the trapezoid projectively, not as two affine
// triangles with a crease along the diagonal (the method's fix for its
// trapezoid artefact). Reflections look the cube up by their ray rotated
// into the cube's frame (u_cube_from_tank).
//
// Redraw key (EnvMapPass::NeedsRebuild): rebuilt at most once per frame,
// only when the camera turned by more than rebuild_turn_rad or the box moved
// by more than rebuild_box_px since the last rebuild (the fold's geometry),
// or the image changed: the mean absolute difference of a 32 x 24 thumbnail
// (VideoBackgroundPass::thumbnail) from the last rebuild's above
// rebuild_mean_levels (8-bit levels). Camera noise is far below that; a
// hand entering the frame or the room light changing is above it.
#ifndef RIPPLE_RENDER_PASS_ENVMAP_H_
#define RIPPLE_RENDER_PASS_ENVMAP_H_

#include <array>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/gl_objects.h"
#include "render/scene.h"

namespace ripple::render::internal {

// A projective map of the unit square onto a quadrilateral (Heckbert,
// "Fundamentals of Texture Mapping and Image Warping", 1989, 2.2.3): the
// square's corners (0,0), (1,0), (1,1), (0,1) go to q[0..3] and (u, v) to
// (a u + b v + c, d u + e v + f) / (g u + h v + 1).
struct SquareToQuad {
  double a = 1, b = 0, c = 0, d = 0, e = 1, f = 0, g = 0, h = 0;
  static SquareToQuad FromCorners(const std::array<glm::dvec2, 4>& q);
  glm::dvec2 Map(double u, double v) const;
  // The homogeneous weight q = g u + h v + 1 at (u, v).
  double Weight(double u, double v) const { return g * u + h * v + 1.0; }
};

// Cube faces in GL's order (GL_TEXTURE_CUBE_MAP_POSITIVE_X + i).
enum CubeFace : int { kPosX, kNegX, kPosY, kNegY, kPosZ, kNegZ, kNumFaces };

// The piece of the image (normalised coordinates: 0..1 across, 0 at the
// image's top edge) that face `face` shows, as the images of the face's
// texel corners (s, t) = (0,0), (1,0), (1,1), (0,1) in GL's cube map
// convention, for the box (x0, y0, x1, y1) in the same coordinates.
std::array<glm::dvec2, 4> EnvMapFaceQuad(int face, const glm::dvec4& box);

// The fold's box: the tank and its walls projected (ideal pinhole k), grown
// by `scale` about its centre and clamped to [margin, 1 - margin] of the
// image each way (normalised coordinates as above; the box keeps at least
// 2 margins of width and height).
glm::dvec4 EnvMapBox(const Intrinsics& k, const glm::dmat4& cam_from_tank,
                     const TankGeometry& tank, double scale, double margin);

// The cube face and its (s, t) that GL's cube map lookup takes for `dir`
// (OpenGL 4.5 core, table 8.19).
int CubeFaceOf(const glm::dvec3& dir, glm::dvec2* st);

class EnvMapPass {
 public:
  struct Options {
    int face_size = 64;        // texels per face side
    double box_scale = 1.15;   // the tank's box grown about its centre
    double box_margin = 0.04;  // share of the image kept outside the box
    double rebuild_turn_rad = 1.0 * 3.14159265358979 / 180.0;
    double rebuild_box_px = 4.0;       // pixels, any edge of the box
    double rebuild_mean_levels = 3.0;  // 8-bit levels, thumbnail mean
    bool srgb_source = true;           // the source holds sRGB-encoded values
  };
  bool Create(const Options& options, std::string* error);

  // Whether the frame differs from the last rebuild's by the key above
  // (always before the first). `thumbnail`: 32 x 24 RGB bytes of the frame.
  bool NeedsRebuild(const Intrinsics& k, const glm::dmat4& cam_from_tank,
                    const TankGeometry& tank,
                    const std::vector<std::uint8_t>& thumbnail) const;

  // Folds `source` (a 2D texture of the undistorted frame, top row at t = 0,
  // decoding to linear light on fetch) into the faces for this camera and
  // tank and remembers the key. Restores the framebuffer binding to
  // `target` and the viewport to k's size.
  void Rebuild(GLuint source, const Intrinsics& k,
               const glm::dmat4& cam_from_tank, const TankGeometry& tank,
               const std::vector<std::uint8_t>& thumbnail, GLuint target);

  // The daylight sky as a second cube map in the tank frame (looked up by
  // the tank-frame ray, kUnitSky): `radiance` of each texel's direction
  // (display units), kSkyFaceSize^2 texels per face. Called once per
  // daylight; the cube stays unused otherwise.
  void SetSky(const std::function<glm::vec3(const glm::dvec3&)>& radiance);
  static constexpr int kSkyFaceSize = 16;

  GLuint texture() const { return cube_.id(); }
  GLuint sky_texture() const { return sky_.id(); }
  // Tank frame -> the cube's frame (the camera's rotation at the rebuild).
  const glm::dmat3& cube_from_tank() const { return cube_from_tank_; }
  const Options& options() const { return options_; }
  int rebuilds() const { return rebuilds_; }

 private:
  Options options_;
  Program program_;
  GLint u_source_ = -1;
  Texture cube_;
  Texture sky_;
  Framebuffer fbo_;
  VertexArray vao_;
  Buffer vbo_;
  // The last rebuild's key.
  bool built_ = false;
  glm::dmat3 cube_from_tank_{1.0};
  glm::dvec4 box_px_{0.0};
  std::vector<std::uint8_t> thumbnail_;
  int rebuilds_ = 0;
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_ENVMAP_H_

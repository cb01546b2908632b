// The shaders' output encoding (common.glsl, EncodeOutput) against the
// exact sRGB curve (IEC 61966-2-1, render/optics.h LinearToSrgb): a ramp of
// linear values drawn through it into an 8-bit target on the GPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "render/gl.h"
#include "render/gl_objects.h"
#include "render/optics.h"
#include "render/shaders.h"
#include "tests/render/render_test_util.h"

namespace ripple::render {
namespace {

constexpr int kW = 4096;  // one linear value per column

// Each column's linear value: evenly spaced in the encoded value from the
// power segment's start (0.04045) to 1, as pixels' values are.
double LinearOfColumn(int x) {
  const double e = 0.04045 + (1.0 - 0.04045) * (x + 0.5) / kW;
  return SrgbToLinear(e);
}

// Draws the ramp through EncodeOutput (sRGB output, the shoulder's knee at
// 2 so that it leaves [0, 1] unchanged); returns the 8-bit values, or an
// empty vector with `error`.
std::vector<std::uint8_t> EncodeRamp(std::string* error) {
  const std::string vs =
      "#version 330 core\n"
      "void main() {\n"
      "  vec2 p = vec2((gl_VertexID & 1) * 4.0 - 1.0,\n"
      "                (gl_VertexID & 2) * 2.0 - 1.0);\n"
      "  gl_Position = vec4(p, 0.0, 1.0);\n"
      "}\n";
  const std::string fs =
      std::string("#version 330 core\n") +
      internal::ShaderSource("common.glsl") +
      "uniform float u_width;\n"
      "out vec4 o_color;\n"
      "float SrgbToLinearExact(float e) {\n"
      "  return e <= 0.04045 ? e / 12.92 : pow((e + 0.055) / 1.055, 2.4);\n"
      "}\n"
      "void main() {\n"
      "  float e = 0.04045 + (1.0 - 0.04045) * gl_FragCoord.x / u_width;\n"
      "  o_color = vec4(EncodeOutput(vec3(SrgbToLinearExact(e))), 1.0);\n"
      "}\n";
  internal::Program p;
  if (!p.Build("output_encoding_test", vs, fs, error)) return {};
  internal::Texture tex;
  internal::AllocTexture(&tex, GL_RGBA8, kW, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                         GL_NEAREST, GL_CLAMP_TO_EDGE);
  internal::Framebuffer fbo;
  if (!internal::AttachColor(&fbo, tex)) {
    *error = "incomplete framebuffer";
    return {};
  }
  internal::VertexArray vao;
  vao.Create();
  glBindVertexArray(vao.id());
  glViewport(0, 0, kW, 1);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glClearColor(0.5f, 0.5f, 0.5f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glUseProgram(p.id());
  glUniform1f(p.Uniform("u_width"), static_cast<float>(kW));
  glUniform1f(p.Uniform("u_srgb_out"), 1.0f);
  glUniform1f(p.Uniform("u_knee"), 2.0f);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  std::vector<std::uint8_t> rgba(4 * kW);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, kW, 1, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  if (glGetError() != GL_NO_ERROR) {
    *error = "GL error";
    return {};
  }
  return rgba;
}

// The three square roots' fit is within 0.24 of a level of the curve and
// within 0.001 of one on average over the ramp (0.07-0.1 low over linear
// 0.3-0.6); with the target's rounding every pixel is within 0.75 of the
// exact value, and the mean error, rounding averaged out over 4096 values,
// within 0.03, over linear 0.3-0.6 within 0.12. (The earlier coefficients
// were 0.10 low on average and 0.15-0.2 low over 0.3-0.6.)
TEST(OutputEncodingTest, TheShadersSrgbEncodingFollowsTheCurve) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, 64, 64);
  std::string error;
  const std::vector<std::uint8_t> rgba = EncodeRamp(&error);
  ASSERT_FALSE(rgba.empty()) << error;
  double sum = 0, worst = 0, mid_sum = 0;
  int mid = 0;
  for (int x = 0; x < kW; ++x) {
    const double linear = LinearOfColumn(x);
    const double exact = 255.0 * LinearToSrgb(linear);
    const double err = rgba[4 * x + 1] - exact;
    sum += err;
    worst = std::max(worst, std::abs(err));
    if (linear > 0.3 && linear < 0.6) {
      mid_sum += err;
      ++mid;
    }
  }
  const double mean = sum / kW, mid_mean = mid_sum / mid;
  std::printf(
      "sRGB output: mean error %.3f levels, linear 0.3-0.6 %.3f, "
      "largest %.3f\n",
      mean, mid_mean, worst);
  EXPECT_LT(worst, 0.75);
  EXPECT_LT(std::abs(mean), 0.03);
  EXPECT_LT(std::abs(mid_mean), 0.12);
}

}  // namespace
}  // namespace ripple::render

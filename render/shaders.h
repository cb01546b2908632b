// Shader sources embedded at build time from render/shaders/ (see
// embed_shaders.cmake).
#ifndef RIPPLE_RENDER_SHADERS_H_
#define RIPPLE_RENDER_SHADERS_H_

namespace ripple::render::internal {

// The text of render/shaders/<name>, or nullptr if there is no such file.
const char* ShaderSource(const char* name);

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_SHADERS_H_

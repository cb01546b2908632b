// Shader sources embedded at build time from render/shaders/ (see
// embed_shaders.cmake).
#ifndef RIPPLE_RENDER_SHADERS_H_
#define RIPPLE_RENDER_SHADERS_H_

#include <string>

#include "render/gl_objects.h"

namespace ripple::render::internal {

// The text of render/shaders/<name>, or nullptr if there is no such file.
const char* ShaderSource(const char* name);

// Builds `p` from the embedded vertex shader `vs` and fragment shader `fs`,
// each prefixed by "#version 330 core", `defines` and common.glsl. False
// with the info log (tagged by `name`) in `error`.
bool BuildProgram(Program* p, const char* name, const char* vs, const char* fs,
                  const std::string& defines, std::string* error);

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_SHADERS_H_

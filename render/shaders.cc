#include "render/shaders.h"

namespace ripple::render::internal {

bool BuildProgram(Program* p, const char* name, const char* vs, const char* fs,
                  const std::string& defines, std::string* error) {
  const char* common = ShaderSource("common.glsl");
  const char* v = ShaderSource(vs);
  const char* f = ShaderSource(fs);
  if (!common || !v || !f) {
    *error = std::string("missing embedded shader for ") + name;
    return false;
  }
  const std::string header =
      std::string("#version 330 core\n") + defines + common;
  return p->Build(name, header + v, header + f, error);
}

}  // namespace ripple::render::internal

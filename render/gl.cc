#include "render/gl.h"

#include <cstdio>

#define RIPPLE_GL_DEFINE(type, name) type ripple_##name = nullptr;
extern "C" {
RIPPLE_GL_FUNCTIONS(RIPPLE_GL_DEFINE)
}
#undef RIPPLE_GL_DEFINE

namespace ripple::render {

bool LoadGl(GlProcGetter get_proc, std::string* error) {
  bool ok = true;
#define RIPPLE_GL_LOAD(type, name)                                   \
  ripple_##name = reinterpret_cast<type>(get_proc(#name));           \
  if (ripple_##name == nullptr && ok) {                              \
    ok = false;                                                      \
    if (error) *error = "GL entry point " #name " is not available"; \
  }
  RIPPLE_GL_FUNCTIONS(RIPPLE_GL_LOAD)
#undef RIPPLE_GL_LOAD
  return ok;
}

bool CheckGlError(const char* where) {
  bool ok = true;
  for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
    std::fprintf(stderr, "ripple render: GL error 0x%04x at %s\n", e, where);
    ok = false;
  }
  return ok;
}

}  // namespace ripple::render

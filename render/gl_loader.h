// Loading render/gl.h's function table. Separate from gl.h so that backend
// files, which include their own platform GL headers (osmesa.h pulls in
// GL/gl.h), can load the table without seeing gl.h's macros.
#ifndef RIPPLE_RENDER_GL_LOADER_H_
#define RIPPLE_RENDER_GL_LOADER_H_

#include <string>

namespace ripple::render {

// Resolves a GL entry point by name in the current context's library.
using GlProcGetter = void* (*)(const char* name);

// Fills the table through `get_proc`. Returns false, naming the first
// missing entry point in `error`, if any of them is unavailable.
bool LoadGl(GlProcGetter get_proc, std::string* error);

// Reports any pending GL error on stderr, tagged with `where`, and returns
// false; true when there was none. Active in every build type: the renderer
// calls it once per frame (and per read-back or present), which costs one
// glGetError.
bool CheckGlError(const char* where);

}  // namespace ripple::render

#endif  // RIPPLE_RENDER_GL_LOADER_H_

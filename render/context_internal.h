// Backend factories behind Context::TryCreate (context_*.cc). Each makes the
// context current and loads the GL table before returning it.
#ifndef RIPPLE_RENDER_CONTEXT_INTERNAL_H_
#define RIPPLE_RENDER_CONTEXT_INTERNAL_H_

#include <memory>
#include <string>

#include "render/context.h"

namespace ripple::render::internal {

std::unique_ptr<Context> CreateEglContext(int width, int height,
                                          std::string* error);
std::unique_ptr<Context> CreateOsmesaContext(int width, int height,
                                             std::string* error);
std::unique_ptr<Context> CreateGlfwContext(int width, int height, bool visible,
                                           std::string* error);

// Context's protected constructor for the backends.
class ContextBase : public Context {
 protected:
  using Context::Context;
};

// Keeps every loaded *_dri.so mapped until exit (render/context.cc says
// why); backends call it once their context exists.
void KeepDriDriversLoaded();

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_CONTEXT_INTERNAL_H_

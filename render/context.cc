#include "render/context.h"

#include <dlfcn.h>
#include <link.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "geometry/check.h"
#include "render/context_internal.h"
#include "render/gl.h"

namespace ripple::render {

const char* BackendName(Backend backend) {
  switch (backend) {
    case Backend::kEgl:
      return "egl";
    case Backend::kOsmesa:
      return "osmesa";
    case Backend::kGlfw:
      return "glfw";
  }
  return "?";
}

std::optional<Backend> ParseBackend(const std::string& name) {
  for (Backend b : {Backend::kEgl, Backend::kOsmesa, Backend::kGlfw}) {
    if (name == BackendName(b)) return b;
  }
  return std::nullopt;
}

bool SetSoftwareRasterThreads(int threads) {
  if (threads < 0 || std::getenv("LP_NUM_THREADS") != nullptr) return false;
  return setenv("LP_NUM_THREADS", std::to_string(threads).c_str(),
                /*overwrite=*/0) == 0;
}

std::vector<Backend> CompiledBackends() {
  std::vector<Backend> backends;
#ifdef RIPPLE_RENDER_HAVE_EGL
  backends.push_back(Backend::kEgl);
#endif
#ifdef RIPPLE_RENDER_HAVE_OSMESA
  backends.push_back(Backend::kOsmesa);
#endif
#ifdef RIPPLE_RENDER_HAVE_GLFW
  backends.push_back(Backend::kGlfw);
#endif
  return backends;
}

std::unique_ptr<Context> Context::TryCreate(Backend backend, int width,
                                            int height, std::string* error,
                                            bool visible) {
  std::string local_error;
  if (error == nullptr) error = &local_error;
  if (width <= 0 || height <= 0) {
    *error = "context size must be positive";
    return nullptr;
  }
  std::unique_ptr<Context> context;
  switch (backend) {
    case Backend::kEgl:
#ifdef RIPPLE_RENDER_HAVE_EGL
      context = internal::CreateEglContext(width, height, error);
#else
      *error = "built without EGL (RIPPLE_WITH_EGL=OFF)";
#endif
      break;
    case Backend::kOsmesa:
#ifdef RIPPLE_RENDER_HAVE_OSMESA
      context = internal::CreateOsmesaContext(width, height, error);
#else
      *error = "built without OSMesa (RIPPLE_WITH_OSMESA=OFF)";
#endif
      break;
    case Backend::kGlfw:
#ifdef RIPPLE_RENDER_HAVE_GLFW
      context = internal::CreateGlfwContext(width, height, visible, error);
#else
      (void)visible;
      *error = "built without GLFW (RIPPLE_WITH_GLFW=OFF)";
#endif
      break;
  }
  if (context == nullptr) return nullptr;
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 33) {
    *error = std::string(BackendName(backend)) + ": got OpenGL " +
             std::to_string(major) + "." + std::to_string(minor) + ", need 3.3";
    return nullptr;
  }
  return context;
}

std::unique_ptr<Context> Context::Create(Backend backend, int width,
                                         int height) {
  std::string error;
  auto context = TryCreate(backend, width, height, &error);
  RIPPLE_CHECK(context != nullptr,
               std::string(BackendName(backend)) + " context: " + error);
  return context;
}

std::string Context::Description() const {
  const auto* renderer =
      reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return std::string(renderer ? renderer : "?") + ", OpenGL " +
         (version ? version : "?");
}

}  // namespace ripple::render

namespace ripple::render::internal {

// Keeps the DRI driver that context creation loaded (Mesa's swrast_dri.so
// for llvmpipe, through EGL or GLX) mapped until the process exits.
// eglTerminate (or closing the X display) unloads it, and the driver's one-time
// initialisation keeps a small allocation that only the driver's own globals
// point to: each unload leaks it, and the next context loads the driver and
// allocates it again. LeakSanitizer reports that allocation at exit from an
// unloaded module, which no suppression can name (docs/reliability.md,
// "Sanitizer build"). A second reference with RTLD_NODELETE keeps the driver,
// its globals and so the allocation: no leak, and later contexts reuse the
// loaded driver.
void KeepDriDriversLoaded() {
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void*) -> int {
        const char* name = info->dlpi_name;
        if (name != nullptr && std::strstr(name, "_dri.so") != nullptr) {
          // The handle is never closed on purpose.
          dlopen(name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
        }
        return 0;
      },
      nullptr);
}

}  // namespace ripple::render::internal

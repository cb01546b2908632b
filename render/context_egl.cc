// EGL headless backend. A GPU's EGL device (the vendor driver) is preferred;
// otherwise Mesa's surfaceless platform gives llvmpipe. There is no default
// framebuffer: the Renderer draws into its own FBO.
// RIPPLE_EGL_PLATFORM=surfaceless|device overrides the choice.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "render/context_internal.h"
#include "render/gl_loader.h"

namespace ripple::render::internal {
namespace {

void* EglProc(const char* name) {
  return reinterpret_cast<void*>(eglGetProcAddress(name));
}

bool HasExtension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) {
      return true;
    }
  }
  return false;
}

class EglContext final : public ContextBase {
 public:
  EglContext(int width, int height)
      : ContextBase(Backend::kEgl, width, height) {}
  ~EglContext() override {
    if (display_ != EGL_NO_DISPLAY) {
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
      eglTerminate(display_);
    }
  }

  bool Init(std::string* error) {
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
            eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (get_platform_display == nullptr) {
      *error = "EGL: eglGetPlatformDisplayEXT missing";
      return false;
    }
    const char* want = std::getenv("RIPPLE_EGL_PLATFORM");
    const std::string platform = want ? want : "";
    if (platform != "surfaceless") display_ = TryDevice(get_platform_display);
    if (display_ == EGL_NO_DISPLAY && platform != "device") {
      display_ = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA,
                                      EGL_DEFAULT_DISPLAY, nullptr);
    }
    if (display_ == EGL_NO_DISPLAY) {
      *error = "EGL: no device or surfaceless display";
      return false;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display_, &major, &minor)) {
      *error = "EGL: eglInitialize failed";
      display_ = EGL_NO_DISPLAY;
      return false;
    }
    KeepDriDriversLoaded();
    if (!eglBindAPI(EGL_OPENGL_API)) {
      *error = "EGL: desktop OpenGL API not supported";
      return false;
    }
    const char* exts = eglQueryString(display_, EGL_EXTENSIONS);
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!HasExtension(exts, "EGL_KHR_no_config_context")) {
      const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                       EGL_NONE};
      EGLint n = 0;
      if (!eglChooseConfig(display_, config_attribs, &config, 1, &n) || n < 1) {
        *error = "EGL: no OpenGL config";
        return false;
      }
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                              3,
                              EGL_CONTEXT_MINOR_VERSION,
                              3,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK,
                              EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, attribs);
    if (context_ == EGL_NO_CONTEXT) {
      *error = "EGL: cannot create an OpenGL 3.3 core context";
      return false;
    }
    if (!MakeCurrent()) {
      *error = "EGL: eglMakeCurrent without surface failed";
      return false;
    }
    return LoadGl(&EglProc, error);
  }

  bool MakeCurrent() override {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      return false;
    }
    std::string ignored;
    return LoadGl(&EglProc, &ignored);
  }

 private:
  // The first hardware EGL device, if the device platform offers one.
  static EGLDisplay TryDevice(PFNEGLGETPLATFORMDISPLAYEXTPROC get_display) {
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(
        eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
        eglGetProcAddress("eglQueryDeviceStringEXT"));
    if (query_devices == nullptr || query_string == nullptr) {
      return EGL_NO_DISPLAY;
    }
    EGLDeviceEXT devices[8];
    EGLint n = 0;
    if (!query_devices(8, devices, &n)) return EGL_NO_DISPLAY;
    for (EGLint i = 0; i < n; ++i) {
      const char* exts = query_string(devices[i], EGL_EXTENSIONS);
      if (HasExtension(exts, "EGL_MESA_device_software")) continue;
      EGLDisplay d = get_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
      if (d != EGL_NO_DISPLAY) return d;
    }
    return EGL_NO_DISPLAY;
  }

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace

std::unique_ptr<Context> CreateEglContext(int width, int height,
                                          std::string* error) {
  auto context = std::make_unique<EglContext>(width, height);
  if (!context->Init(error)) return nullptr;
  return context;
}

}  // namespace ripple::render::internal

// GLFW window backend, for `ripple live` and friends. The window is not
// resizable: the Renderer's FBO has the camera's size and is blitted 1:1.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <string>

#include "render/context_internal.h"
#include "render/gl_loader.h"

namespace ripple::render::internal {
namespace {

void* GlfwProc(const char* name) {
  return reinterpret_cast<void*>(glfwGetProcAddress(name));
}

std::string* g_glfw_error = nullptr;
void OnGlfwError(int code, const char* message) {
  if (g_glfw_error) *g_glfw_error = std::string("GLFW: ") + message;
}

int g_glfw_users = 0;  // glfwInit/glfwTerminate reference count

class GlfwContext final : public ContextBase {
 public:
  GlfwContext(int width, int height)
      : ContextBase(Backend::kGlfw, width, height) {}
  ~GlfwContext() override {
    if (window_ != nullptr) glfwDestroyWindow(window_);
    if (initialised_ && --g_glfw_users == 0) glfwTerminate();
  }

  bool Init(bool visible, std::string* error) {
    std::string glfw_error;
    g_glfw_error = &glfw_error;
    glfwSetErrorCallback(&OnGlfwError);
    const bool ok = InitWindow(visible);
    g_glfw_error = nullptr;
    if (!ok) {
      *error = glfw_error.empty() ? "GLFW: cannot open a window" : glfw_error;
      return false;
    }
    return LoadGl(&GlfwProc, error);
  }

  bool MakeCurrent() override {
    glfwMakeContextCurrent(window_);
    std::string ignored;
    return LoadGl(&GlfwProc, &ignored);
  }
  void SwapBuffers() override {
    glfwSwapBuffers(window_);
    glfwPollEvents();
  }
  bool ShouldClose() const override { return glfwWindowShouldClose(window_); }
  int DefaultFramebuffer() const override { return 0; }

 private:
  bool InitWindow(bool visible) {
    if (!glfwInit()) return false;
    initialised_ = true;
    ++g_glfw_users;
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_DEPTH_BITS, 0);
    window_ = glfwCreateWindow(width(), height(), "Ripple", nullptr, nullptr);
    if (window_ == nullptr) return false;
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(0);
    return true;
  }

  GLFWwindow* window_ = nullptr;
  bool initialised_ = false;
};

}  // namespace

std::unique_ptr<Context> CreateGlfwContext(int width, int height, bool visible,
                                           std::string* error) {
  auto context = std::make_unique<GlfwContext>(width, height);
  if (!context->Init(visible, error)) return nullptr;
  return context;
}

}  // namespace ripple::render::internal

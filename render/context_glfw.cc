// GLFW window backend, for `ripple live` and friends. The window is
// resizable: Renderer::Present scales the camera-sized FBO into whatever
// framebuffer the window has now, letterboxed.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <string>
#include <utility>
#include <vector>

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
    KeepDriDriversLoaded();
    std::string ignored;
    return LoadGl(&GlfwProc, &ignored);
  }
  void SwapBuffers() override {
    glfwSwapBuffers(window_);
    glfwPollEvents();
  }
  void PollEvents() override { glfwPollEvents(); }
  bool ShouldClose() const override { return glfwWindowShouldClose(window_); }
  int DefaultFramebuffer() const override { return 0; }
  std::vector<int> TakeTypedKeys() override {
    return std::exchange(typed_, {});
  }
  void GetFramebufferSize(int* width, int* height) const override {
    glfwGetFramebufferSize(window_, width, height);
  }
  void SetWindowSize(int width, int height) override {
    glfwSetWindowSize(window_, width, height);
  }

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
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_DEPTH_BITS, 0);
    window_ = glfwCreateWindow(width(), height(), "Ripple", nullptr, nullptr);
    if (window_ == nullptr) return false;
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(0);
    glfwSetWindowUserPointer(window_, this);
    glfwSetCharCallback(window_, &OnChar);
    glfwSetKeyCallback(window_, &OnKey);
    return true;
  }

  static GlfwContext* Self(GLFWwindow* window) {
    return static_cast<GlfwContext*>(glfwGetWindowUserPointer(window));
  }
  // Text input: the code point after layout and Shift, so 'v' != 'V'. Space
  // comes from OnKey instead, so that it is reported once even with
  // modifiers held (which suppress character events).
  static void OnChar(GLFWwindow* window, unsigned int codepoint) {
    if (codepoint == 32) return;
    Self(window)->typed_.push_back(static_cast<int>(codepoint));
  }
  // Escape has no character; Space is taken here (see OnChar).
  static void OnKey(GLFWwindow* window, int key, int /*scancode*/, int action,
                    int /*mods*/) {
    if (action != GLFW_PRESS) return;
    if (key == GLFW_KEY_ESCAPE) Self(window)->typed_.push_back(27);
    if (key == GLFW_KEY_SPACE) Self(window)->typed_.push_back(32);
  }

  GLFWwindow* window_ = nullptr;
  bool initialised_ = false;
  std::vector<int> typed_;  // since the last TakeTypedKeys()
};

}  // namespace

std::unique_ptr<Context> CreateGlfwContext(int width, int height, bool visible,
                                           std::string* error) {
  auto context = std::make_unique<GlfwContext>(width, height);
  if (!context->Init(visible, error)) return nullptr;
  return context;
}

}  // namespace ripple::render::internal

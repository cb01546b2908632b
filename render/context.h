// OpenGL 3.3 core contexts from three interchangeable backends. Render into
// the Renderer's FBO in every case; only GLFW has a visible default
// framebuffer (the window), only OSMesa a CPU-visible one.
#ifndef RIPPLE_RENDER_CONTEXT_H_
#define RIPPLE_RENDER_CONTEXT_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ripple::render {

enum class Backend {
  kEgl,     // headless: EGL device platform (GPU) or Mesa surfaceless
  kOsmesa,  // headless: Mesa's off-screen library (gone in Mesa >= 25.1)
  kGlfw,    // a window (X11/Wayland through GLFW)
};

// "egl", "osmesa", "glfw".
const char* BackendName(Backend backend);
// Parses the `--gl` flag value; nullopt for an unknown name.
std::optional<Backend> ParseBackend(const std::string& name);
// Backends compiled into this build (RIPPLE_WITH_EGL/OSMESA/GLFW).
std::vector<Backend> CompiledBackends();

// The threads Mesa's software rasteriser (llvmpipe) rasterises on, for
// contexts created after the call: 0 rasterises on the thread that draws;
// llvmpipe's own default is one thread per core. It sets LP_NUM_THREADS
// unless the user has set it (the user's value wins) and does nothing to a
// GPU's driver. It changes the environment: call it before other threads
// start. True if it set the variable.
bool SetSoftwareRasterThreads(int threads);

// An OpenGL 3.3 core context, current on the creating thread, with the GL
// function table (render/gl.h) loaded through the backend's GetProcAddress.
// RAII and move-only (held by unique_ptr). One context at a time: creating
// or MakeCurrent()-ing one reloads the process-wide GL table.
class Context {
 public:
  virtual ~Context() = default;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Makes a context of `width` x `height` pixels (the window size for GLFW,
  // the default framebuffer size for OSMesa; EGL has none). Returns nullptr
  // and fills `error` when the backend is not compiled in or fails (no
  // display, no GL 3.3, ...). `visible` only matters for GLFW.
  static std::unique_ptr<Context> TryCreate(Backend backend, int width,
                                            int height, std::string* error,
                                            bool visible = true);
  // Like TryCreate but dies with the message on failure.
  static std::unique_ptr<Context> Create(Backend backend, int width,
                                         int height);

  Backend backend() const { return backend_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  std::string Description() const;

  virtual bool MakeCurrent() = 0;
  // GLFW: swaps the window's buffers and polls events; others: no-op.
  virtual void SwapBuffers() {}
  // GLFW: processes pending window events (keys, resize, close) without
  // drawing, e.g. while the app is paused; others: no-op.
  virtual void PollEvents() {}
  // GLFW: the user closed the window; others: false.
  virtual bool ShouldClose() const { return false; }
  // Keys typed since the last call, oldest first, as Unicode code points
  // (so 'v' and 'V' differ), plus 27 for Escape and 32 for Space on press.
  // Events arrive in SwapBuffers() (Renderer::Present) and PollEvents().
  // Headless backends: always empty.
  virtual std::vector<int> TakeTypedKeys() { return {}; }
  // Size in pixels of the visible framebuffer: GLFW's current window
  // framebuffer (it changes when the user resizes the window), otherwise
  // width() x height().
  virtual void GetFramebufferSize(int* width, int* height) const {
    *width = width_;
    *height = height_;
  }
  // GLFW: asks the window system for a new window size (screen
  // coordinates); others: no-op. The user can resize the window too.
  virtual void SetWindowSize(int /*width*/, int /*height*/) {}
  // GL name of the framebuffer that shows or holds the output (0), or -1
  // when the backend has none (EGL surfaceless).
  virtual int DefaultFramebuffer() const { return -1; }
  // OSMesa: the RGBA8 default framebuffer in CPU memory, GL row order
  // (bottom row first), valid after glFinish. nullptr for other backends.
  virtual const std::uint8_t* CpuFramebuffer() const { return nullptr; }

 protected:
  Context(Backend backend, int width, int height)
      : backend_(backend), width_(width), height_(height) {}

 private:
  Backend backend_;
  int width_, height_;
};

}  // namespace ripple::render

#endif  // RIPPLE_RENDER_CONTEXT_H_

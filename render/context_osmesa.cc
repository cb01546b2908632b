// OSMesa headless backend: Mesa renders into a buffer we own. The Renderer
// blits its FBO into this default framebuffer and reads the buffer directly
// after glFinish, which avoids a second glReadPixels copy (DESIGN.md).
#include <GL/osmesa.h>

#include <cstdint>
#include <string>
#include <vector>

#include "render/context_internal.h"
#include "render/gl_loader.h"

namespace ripple::render::internal {
namespace {

void* OsmesaProc(const char* name) {
  return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
}

class OsmesaContext final : public ContextBase {
 public:
  OsmesaContext(int width, int height)
      : ContextBase(Backend::kOsmesa, width, height),
        buffer_(static_cast<size_t>(width) * height * 4) {}
  ~OsmesaContext() override {
    if (context_ != nullptr) OSMesaDestroyContext(context_);
  }

  bool Init(std::string* error) {
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_STENCIL_BITS,
                           0,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           3,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           3,
                           0};
    context_ = OSMesaCreateContextAttribs(attribs, nullptr);
    if (context_ == nullptr) {
      *error = "OSMesa: cannot create an OpenGL 3.3 core context";
      return false;
    }
    if (!MakeCurrent()) {
      *error = "OSMesa: OSMesaMakeCurrent failed";
      return false;
    }
    return LoadGl(&OsmesaProc, error);
  }

  bool MakeCurrent() override {
    if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, width(),
                           height())) {
      return false;
    }
    std::string ignored;
    return LoadGl(&OsmesaProc, &ignored);
  }
  int DefaultFramebuffer() const override { return 0; }
  const std::uint8_t* CpuFramebuffer() const override { return buffer_.data(); }

 private:
  OSMesaContext context_ = nullptr;
  std::vector<std::uint8_t> buffer_;
};

}  // namespace

std::unique_ptr<Context> CreateOsmesaContext(int width, int height,
                                             std::string* error) {
  auto context = std::make_unique<OsmesaContext>(width, height);
  if (!context->Init(error)) return nullptr;
  return context;
}

}  // namespace ripple::render::internal

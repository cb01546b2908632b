// Move-only RAII owners of GL object names (internal to render/). Each is
// created explicitly (Create()) while a context is current and deleted in its
// destructor, which must also run while that context is current.
#ifndef RIPPLE_RENDER_GL_OBJECTS_H_
#define RIPPLE_RENDER_GL_OBJECTS_H_

#include <string>
#include <utility>

#include "render/gl.h"

namespace ripple::render::internal {

// Holds one name from a glGen*/glDelete* pair, looked up at call time so the
// function table can be (re)loaded after static initialisation.
#define RIPPLE_GL_NAME_CLASS(Class, gen, del)                   \
  class Class {                                                 \
   public:                                                      \
    Class() = default;                                          \
    ~Class() { Reset(); }                                       \
    Class(Class&& o) noexcept : id_(std::exchange(o.id_, 0)) {} \
    Class& operator=(Class&& o) noexcept {                      \
      if (this != &o) {                                         \
        Reset();                                                \
        id_ = std::exchange(o.id_, 0);                          \
      }                                                         \
      return *this;                                             \
    }                                                           \
    Class(const Class&) = delete;                               \
    Class& operator=(const Class&) = delete;                    \
    void Create() {                                             \
      Reset();                                                  \
      gen(1, &id_);                                             \
    }                                                           \
    void Reset() {                                              \
      if (id_ != 0) del(1, &id_);                               \
      id_ = 0;                                                  \
    }                                                           \
    GLuint id() const { return id_; }                           \
                                                                \
   private:                                                     \
    GLuint id_ = 0;                                             \
  };

RIPPLE_GL_NAME_CLASS(Texture, glGenTextures, glDeleteTextures)
RIPPLE_GL_NAME_CLASS(Buffer, glGenBuffers, glDeleteBuffers)
RIPPLE_GL_NAME_CLASS(Framebuffer, glGenFramebuffers, glDeleteFramebuffers)
RIPPLE_GL_NAME_CLASS(Renderbuffer, glGenRenderbuffers, glDeleteRenderbuffers)
RIPPLE_GL_NAME_CLASS(VertexArray, glGenVertexArrays, glDeleteVertexArrays)
RIPPLE_GL_NAME_CLASS(Query, glGenQueries, glDeleteQueries)
#undef RIPPLE_GL_NAME_CLASS

// A linked shader program.
class Program {
 public:
  Program() = default;
  ~Program() { Reset(); }
  Program(Program&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  Program& operator=(Program&& o) noexcept {
    if (this != &o) {
      Reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  // Compiles and links; false with the info log (tagged by `name`) in error.
  bool Build(const std::string& name, const std::string& vertex_source,
             const std::string& fragment_source, std::string* error);
  void Reset() {
    if (id_ != 0) glDeleteProgram(id_);
    id_ = 0;
  }
  GLuint id() const { return id_; }
  // A uniform's location by name (-1 if the program has none): a string
  // look-up, so passes call it once after linking and keep the result.
  GLint Uniform(const char* name) const {
    return glGetUniformLocation(id_, name);
  }

 private:
  GLuint id_ = 0;
};

// Creates `t` as a 2D texture of `w` x `h` with the given filter (min and
// mag) and wrap (s and t), filled from `data` (tightly packed rows) or left
// undefined. Leaves it bound to the active unit.
void AllocTexture(Texture* t, GLint internal_format, int w, int h,
                  GLenum format, GLenum type, GLenum filter, GLenum wrap,
                  const void* data = nullptr);

// Creates `fbo` with `t` as its colour attachment; true if complete. Leaves
// it bound.
bool AttachColor(Framebuffer* fbo, const Texture& t);

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_GL_OBJECTS_H_

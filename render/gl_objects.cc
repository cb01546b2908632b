#include "render/gl_objects.h"

namespace ripple::render::internal {
namespace {

GLuint Compile(GLenum type, const std::string& source, const std::string& name,
               std::string* error) {
  GLuint shader = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {0};
    glGetShaderInfoLog(shader, sizeof(log), nullptr, log);
    *error = name +
             (type == GL_VERTEX_SHADER ? " (vertex): " : " (fragment): ") + log;
    glDeleteShader(shader);
    return 0;
  }
  return shader;
}

}  // namespace

bool Program::Build(const std::string& name, const std::string& vertex_source,
                    const std::string& fragment_source, std::string* error) {
  Reset();
  GLuint vs = Compile(GL_VERTEX_SHADER, vertex_source, name, error);
  if (vs == 0) return false;
  GLuint fs = Compile(GL_FRAGMENT_SHADER, fragment_source, name, error);
  if (fs == 0) {
    glDeleteShader(vs);
    return false;
  }
  id_ = glCreateProgram();
  glAttachShader(id_, vs);
  glAttachShader(id_, fs);
  glLinkProgram(id_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096] = {0};
    glGetProgramInfoLog(id_, sizeof(log), nullptr, log);
    *error = name + " (link): " + log;
    Reset();
    return false;
  }
  return true;
}

void AllocTexture(Texture* t, GLint internal_format, int w, int h,
                  GLenum format, GLenum type, GLenum filter, GLenum wrap,
                  const void* data) {
  t->Create();
  glBindTexture(GL_TEXTURE_2D, t->id());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glTexImage2D(GL_TEXTURE_2D, 0, internal_format, w, h, 0, format, type, data);
}

bool AttachColor(Framebuffer* fbo, const Texture& t) {
  fbo->Create();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo->id());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                         t.id(), 0);
  return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
}

}  // namespace ripple::render::internal

// Ripple's OpenGL 3.3 core function table, loaded through the current
// backend's own GetProcAddress (eglGetProcAddress, OSMesaGetProcAddress,
// glfwGetProcAddress). libepoxy aborts on OSMesa contexts and Debian's
// glbinding resolves only through GLX (see DESIGN.md), so render/ carries this
// small hand-written table instead.
//
// Include this header instead of <GL/gl.h>; never include both in one file.
// Each `glFoo` below is a macro naming a function pointer `ripple_glFoo`, so
// code reads like plain GL. The table is process-global: LoadGl() refills it
// whenever a Context is made current, so one context at a time is current.
#ifndef RIPPLE_RENDER_GL_H_
#define RIPPLE_RENDER_GL_H_

#include <GL/glcorearb.h>

#include "render/gl_loader.h"

// X(type, name): every GL entry point render/ calls, and only those: LoadGl
// fails if any is missing, so an entry nothing calls would refuse a driver
// for no reason.
#define RIPPLE_GL_FUNCTIONS(X)                                   \
  X(PFNGLACTIVETEXTUREPROC, glActiveTexture)                     \
  X(PFNGLATTACHSHADERPROC, glAttachShader)                       \
  X(PFNGLBEGINQUERYPROC, glBeginQuery)                           \
  X(PFNGLBINDBUFFERPROC, glBindBuffer)                           \
  X(PFNGLBINDFRAMEBUFFERPROC, glBindFramebuffer)                 \
  X(PFNGLBINDRENDERBUFFERPROC, glBindRenderbuffer)               \
  X(PFNGLBINDTEXTUREPROC, glBindTexture)                         \
  X(PFNGLBINDVERTEXARRAYPROC, glBindVertexArray)                 \
  X(PFNGLBLENDFUNCPROC, glBlendFunc)                             \
  X(PFNGLBLENDFUNCSEPARATEPROC, glBlendFuncSeparate)             \
  X(PFNGLBLITFRAMEBUFFERPROC, glBlitFramebuffer)                 \
  X(PFNGLBUFFERDATAPROC, glBufferData)                           \
  X(PFNGLBUFFERSUBDATAPROC, glBufferSubData)                     \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, glCheckFramebufferStatus)   \
  X(PFNGLCLEARPROC, glClear)                                     \
  X(PFNGLCLEARCOLORPROC, glClearColor)                           \
  X(PFNGLCLEARDEPTHPROC, glClearDepth)                           \
  X(PFNGLCLEARSTENCILPROC, glClearStencil)                       \
  X(PFNGLCOLORMASKPROC, glColorMask)                             \
  X(PFNGLCOMPILESHADERPROC, glCompileShader)                     \
  X(PFNGLCREATEPROGRAMPROC, glCreateProgram)                     \
  X(PFNGLCREATESHADERPROC, glCreateShader)                       \
  X(PFNGLDELETEBUFFERSPROC, glDeleteBuffers)                     \
  X(PFNGLDELETEFRAMEBUFFERSPROC, glDeleteFramebuffers)           \
  X(PFNGLDELETEPROGRAMPROC, glDeleteProgram)                     \
  X(PFNGLDELETEQUERIESPROC, glDeleteQueries)                     \
  X(PFNGLDELETERENDERBUFFERSPROC, glDeleteRenderbuffers)         \
  X(PFNGLDELETESHADERPROC, glDeleteShader)                       \
  X(PFNGLDELETETEXTURESPROC, glDeleteTextures)                   \
  X(PFNGLDELETEVERTEXARRAYSPROC, glDeleteVertexArrays)           \
  X(PFNGLDEPTHFUNCPROC, glDepthFunc)                             \
  X(PFNGLDEPTHMASKPROC, glDepthMask)                             \
  X(PFNGLDISABLEPROC, glDisable)                                 \
  X(PFNGLDRAWARRAYSPROC, glDrawArrays)                           \
  X(PFNGLDRAWBUFFERPROC, glDrawBuffer)                           \
  X(PFNGLDRAWELEMENTSPROC, glDrawElements)                       \
  X(PFNGLENABLEPROC, glEnable)                                   \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, glEnableVertexAttribArray) \
  X(PFNGLENDQUERYPROC, glEndQuery)                               \
  X(PFNGLFINISHPROC, glFinish)                                   \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, glFramebufferRenderbuffer) \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, glFramebufferTexture2D)       \
  X(PFNGLGENBUFFERSPROC, glGenBuffers)                           \
  X(PFNGLGENFRAMEBUFFERSPROC, glGenFramebuffers)                 \
  X(PFNGLGENQUERIESPROC, glGenQueries)                           \
  X(PFNGLGENRENDERBUFFERSPROC, glGenRenderbuffers)               \
  X(PFNGLGENTEXTURESPROC, glGenTextures)                         \
  X(PFNGLGENVERTEXARRAYSPROC, glGenVertexArrays)                 \
  X(PFNGLGETERRORPROC, glGetError)                               \
  X(PFNGLGETINTEGERVPROC, glGetIntegerv)                         \
  X(PFNGLGETPROGRAMINFOLOGPROC, glGetProgramInfoLog)             \
  X(PFNGLGETPROGRAMIVPROC, glGetProgramiv)                       \
  X(PFNGLGETQUERYOBJECTUI64VPROC, glGetQueryObjectui64v)         \
  X(PFNGLGETSHADERINFOLOGPROC, glGetShaderInfoLog)               \
  X(PFNGLGETSHADERIVPROC, glGetShaderiv)                         \
  X(PFNGLGETSTRINGPROC, glGetString)                             \
  X(PFNGLGETUNIFORMLOCATIONPROC, glGetUniformLocation)           \
  X(PFNGLLINKPROGRAMPROC, glLinkProgram)                         \
  X(PFNGLMAPBUFFERRANGEPROC, glMapBufferRange)                   \
  X(PFNGLPIXELSTOREIPROC, glPixelStorei)                         \
  X(PFNGLPOLYGONOFFSETPROC, glPolygonOffset)                     \
  X(PFNGLREADBUFFERPROC, glReadBuffer)                           \
  X(PFNGLREADPIXELSPROC, glReadPixels)                           \
  X(PFNGLRENDERBUFFERSTORAGEPROC, glRenderbufferStorage)         \
  X(PFNGLSCISSORPROC, glScissor)                                 \
  X(PFNGLSHADERSOURCEPROC, glShaderSource)                       \
  X(PFNGLSTENCILFUNCPROC, glStencilFunc)                         \
  X(PFNGLSTENCILMASKPROC, glStencilMask)                         \
  X(PFNGLSTENCILOPPROC, glStencilOp)                             \
  X(PFNGLTEXIMAGE2DPROC, glTexImage2D)                           \
  X(PFNGLTEXPARAMETERIPROC, glTexParameteri)                     \
  X(PFNGLTEXSTORAGE2DPROC, glTexStorage2D)                       \
  X(PFNGLTEXSUBIMAGE2DPROC, glTexSubImage2D)                     \
  X(PFNGLTEXTUREVIEWPROC, glTextureView)                         \
  X(PFNGLUNIFORM1FPROC, glUniform1f)                             \
  X(PFNGLUNIFORM1IPROC, glUniform1i)                             \
  X(PFNGLUNIFORM2FPROC, glUniform2f)                             \
  X(PFNGLUNIFORM3FPROC, glUniform3f)                             \
  X(PFNGLUNIFORM4FPROC, glUniform4f)                             \
  X(PFNGLUNIFORM4FVPROC, glUniform4fv)                           \
  X(PFNGLUNIFORMMATRIX3FVPROC, glUniformMatrix3fv)               \
  X(PFNGLUNIFORMMATRIX4FVPROC, glUniformMatrix4fv)               \
  X(PFNGLUNMAPBUFFERPROC, glUnmapBuffer)                         \
  X(PFNGLUSEPROGRAMPROC, glUseProgram)                           \
  X(PFNGLVERTEXATTRIBPOINTERPROC, glVertexAttribPointer)         \
  X(PFNGLVIEWPORTPROC, glViewport)

#define RIPPLE_GL_DECLARE(type, name) extern type ripple_##name;
extern "C" {
RIPPLE_GL_FUNCTIONS(RIPPLE_GL_DECLARE)
}
#undef RIPPLE_GL_DECLARE

#define glActiveTexture ripple_glActiveTexture
#define glAttachShader ripple_glAttachShader
#define glBeginQuery ripple_glBeginQuery
#define glBindBuffer ripple_glBindBuffer
#define glBindFramebuffer ripple_glBindFramebuffer
#define glBindRenderbuffer ripple_glBindRenderbuffer
#define glBindTexture ripple_glBindTexture
#define glBindVertexArray ripple_glBindVertexArray
#define glBlendFunc ripple_glBlendFunc
#define glBlendFuncSeparate ripple_glBlendFuncSeparate
#define glBlitFramebuffer ripple_glBlitFramebuffer
#define glBufferData ripple_glBufferData
#define glBufferSubData ripple_glBufferSubData
#define glCheckFramebufferStatus ripple_glCheckFramebufferStatus
#define glClear ripple_glClear
#define glClearColor ripple_glClearColor
#define glClearDepth ripple_glClearDepth
#define glClearStencil ripple_glClearStencil
#define glColorMask ripple_glColorMask
#define glCompileShader ripple_glCompileShader
#define glCreateProgram ripple_glCreateProgram
#define glCreateShader ripple_glCreateShader
#define glDeleteBuffers ripple_glDeleteBuffers
#define glDeleteFramebuffers ripple_glDeleteFramebuffers
#define glDeleteProgram ripple_glDeleteProgram
#define glDeleteQueries ripple_glDeleteQueries
#define glDeleteRenderbuffers ripple_glDeleteRenderbuffers
#define glDeleteShader ripple_glDeleteShader
#define glDeleteTextures ripple_glDeleteTextures
#define glDeleteVertexArrays ripple_glDeleteVertexArrays
#define glDepthFunc ripple_glDepthFunc
#define glDepthMask ripple_glDepthMask
#define glDisable ripple_glDisable
#define glDrawArrays ripple_glDrawArrays
#define glDrawBuffer ripple_glDrawBuffer
#define glDrawElements ripple_glDrawElements
#define glEnable ripple_glEnable
#define glEnableVertexAttribArray ripple_glEnableVertexAttribArray
#define glEndQuery ripple_glEndQuery
#define glFinish ripple_glFinish
#define glFramebufferRenderbuffer ripple_glFramebufferRenderbuffer
#define glFramebufferTexture2D ripple_glFramebufferTexture2D
#define glGenBuffers ripple_glGenBuffers
#define glGenFramebuffers ripple_glGenFramebuffers
#define glGenQueries ripple_glGenQueries
#define glGenRenderbuffers ripple_glGenRenderbuffers
#define glGenTextures ripple_glGenTextures
#define glGenVertexArrays ripple_glGenVertexArrays
#define glGetError ripple_glGetError
#define glGetIntegerv ripple_glGetIntegerv
#define glGetProgramInfoLog ripple_glGetProgramInfoLog
#define glGetProgramiv ripple_glGetProgramiv
#define glGetQueryObjectui64v ripple_glGetQueryObjectui64v
#define glGetShaderInfoLog ripple_glGetShaderInfoLog
#define glGetShaderiv ripple_glGetShaderiv
#define glGetString ripple_glGetString
#define glGetUniformLocation ripple_glGetUniformLocation
#define glLinkProgram ripple_glLinkProgram
#define glMapBufferRange ripple_glMapBufferRange
#define glPixelStorei ripple_glPixelStorei
#define glPolygonOffset ripple_glPolygonOffset
#define glReadBuffer ripple_glReadBuffer
#define glReadPixels ripple_glReadPixels
#define glRenderbufferStorage ripple_glRenderbufferStorage
#define glScissor ripple_glScissor
#define glShaderSource ripple_glShaderSource
#define glStencilFunc ripple_glStencilFunc
#define glStencilMask ripple_glStencilMask
#define glStencilOp ripple_glStencilOp
#define glTexImage2D ripple_glTexImage2D
#define glTexParameteri ripple_glTexParameteri
#define glTexStorage2D ripple_glTexStorage2D
#define glTexSubImage2D ripple_glTexSubImage2D
#define glTextureView ripple_glTextureView
#define glUniform1f ripple_glUniform1f
#define glUniform1i ripple_glUniform1i
#define glUniform2f ripple_glUniform2f
#define glUniform3f ripple_glUniform3f
#define glUniform4f ripple_glUniform4f
#define glUniform4fv ripple_glUniform4fv
#define glUniformMatrix3fv ripple_glUniformMatrix3fv
#define glUniformMatrix4fv ripple_glUniformMatrix4fv
#define glUnmapBuffer ripple_glUnmapBuffer
#define glUseProgram ripple_glUseProgram
#define glVertexAttribPointer ripple_glVertexAttribPointer
#define glViewport ripple_glViewport

#endif  // RIPPLE_RENDER_GL_H_

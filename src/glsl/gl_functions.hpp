#pragma once
// The GL entry points the draw path (gl_runner.cpp) calls, as pointers loaded from the context's
// own library (OSMesaGetProcAddress, eglGetProcAddress): the worker links libOSMesa and libEGL
// side by side and neither libGL nor libOpenGL, so each path's calls reach its own dispatch and
// no symbol of one library stands in for the other's. Named as GL names them, in namespace
// heightmarch::gl, so the draw path reads as plain GL.
#include <GL/glcorearb.h>

#include <functional>

// X(pointer type, name): every GL function the draw path calls, and only those.
#define HEIGHTMARCH_GL_FUNCTIONS(X)                            \
  X(PFNGLACTIVETEXTUREPROC, glActiveTexture)                   \
  X(PFNGLATTACHSHADERPROC, glAttachShader)                     \
  X(PFNGLBEGINQUERYPROC, glBeginQuery)                         \
  X(PFNGLBINDFRAMEBUFFERPROC, glBindFramebuffer)               \
  X(PFNGLBINDTEXTUREPROC, glBindTexture)                       \
  X(PFNGLBINDVERTEXARRAYPROC, glBindVertexArray)               \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, glCheckFramebufferStatus) \
  X(PFNGLCLEARBUFFERFVPROC, glClearBufferfv)                   \
  X(PFNGLCOMPILESHADERPROC, glCompileShader)                   \
  X(PFNGLCREATEPROGRAMPROC, glCreateProgram)                   \
  X(PFNGLCREATESHADERPROC, glCreateShader)                     \
  X(PFNGLDELETEPROGRAMPROC, glDeleteProgram)                   \
  X(PFNGLDELETESHADERPROC, glDeleteShader)                     \
  X(PFNGLDRAWARRAYSPROC, glDrawArrays)                         \
  X(PFNGLDRAWBUFFERSPROC, glDrawBuffers)                       \
  X(PFNGLENDQUERYPROC, glEndQuery)                             \
  X(PFNGLFINISHPROC, glFinish)                                 \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, glFramebufferTexture2D)     \
  X(PFNGLGENFRAMEBUFFERSPROC, glGenFramebuffers)               \
  X(PFNGLGENQUERIESPROC, glGenQueries)                         \
  X(PFNGLGENTEXTURESPROC, glGenTextures)                       \
  X(PFNGLGENVERTEXARRAYSPROC, glGenVertexArrays)               \
  X(PFNGLGETERRORPROC, glGetError)                             \
  X(PFNGLGETINTEGERVPROC, glGetIntegerv)                       \
  X(PFNGLGETPROGRAMINFOLOGPROC, glGetProgramInfoLog)           \
  X(PFNGLGETPROGRAMIVPROC, glGetProgramiv)                     \
  X(PFNGLGETQUERYOBJECTUI64VPROC, glGetQueryObjectui64v)       \
  X(PFNGLGETSHADERINFOLOGPROC, glGetShaderInfoLog)             \
  X(PFNGLGETSHADERIVPROC, glGetShaderiv)                       \
  X(PFNGLGETSTRINGPROC, glGetString)                           \
  X(PFNGLGETUNIFORMLOCATIONPROC, glGetUniformLocation)         \
  X(PFNGLLINKPROGRAMPROC, glLinkProgram)                       \
  X(PFNGLREADBUFFERPROC, glReadBuffer)                         \
  X(PFNGLREADPIXELSPROC, glReadPixels)                         \
  X(PFNGLSHADERSOURCEPROC, glShaderSource)                     \
  X(PFNGLTEXIMAGE2DPROC, glTexImage2D)                         \
  X(PFNGLTEXPARAMETERIPROC, glTexParameteri)                   \
  X(PFNGLUNIFORM1FPROC, glUniform1f)                           \
  X(PFNGLUNIFORM1IPROC, glUniform1i)                           \
  X(PFNGLUNIFORM1IVPROC, glUniform1iv)                         \
  X(PFNGLUNIFORM3FPROC, glUniform3f)                           \
  X(PFNGLUSEPROGRAMPROC, glUseProgram)                         \
  X(PFNGLVIEWPORTPROC, glViewport)

namespace heightmarch::gl {

#define HEIGHTMARCH_GL_DECLARE(type, name) extern type name;
HEIGHTMARCH_GL_FUNCTIONS(HEIGHTMARCH_GL_DECLARE)
#undef HEIGHTMARCH_GL_DECLARE

// Loads every function of the list from `proc_address` (the current context's library);
// std::runtime_error naming the first it lacks.
void load_functions(const std::function<void*(const char*)>& proc_address);

}  // namespace heightmarch::gl

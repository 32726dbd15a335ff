// Internal to algorithms/render and the GPU ray caster: the OpenGL 3.3 core
// entry points the renderer uses, loaded once per context through
// eglGetProcAddress (no GLEW, no link to libGL/libOpenGL: EGL 1.5 returns
// core functions too), and those of GL 4.3's compute shaders.  Only
// egl_context.cpp, renderer.cpp and rays/gpu_ray_caster.cpp include this.
#pragma once

#include <GL/glcorearb.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "core/errors.h"

#define CGVIEW_GL_FUNCTIONS(X)                                     \
  X(PFNGLGETSTRINGPROC, glGetString)                               \
  X(PFNGLGETERRORPROC, glGetError)                                 \
  X(PFNGLGETINTEGERVPROC, glGetIntegerv)                           \
  X(PFNGLVIEWPORTPROC, glViewport)                                 \
  X(PFNGLCLEARPROC, glClear)                                       \
  X(PFNGLCLEARCOLORPROC, glClearColor)                             \
  X(PFNGLCLEARDEPTHPROC, glClearDepth)                             \
  X(PFNGLCLEARBUFFERUIVPROC, glClearBufferuiv)                     \
  X(PFNGLCLEARBUFFERFVPROC, glClearBufferfv)                       \
  X(PFNGLCLEARBUFFERFIPROC, glClearBufferfi)                       \
  X(PFNGLENABLEPROC, glEnable)                                     \
  X(PFNGLDISABLEPROC, glDisable)                                   \
  X(PFNGLDEPTHFUNCPROC, glDepthFunc)                               \
  X(PFNGLDEPTHMASKPROC, glDepthMask)                               \
  X(PFNGLBLENDEQUATIONPROC, glBlendEquation)                       \
  X(PFNGLPOLYGONMODEPROC, glPolygonMode)                           \
  X(PFNGLPOLYGONOFFSETPROC, glPolygonOffset)                       \
  X(PFNGLPOINTSIZEPROC, glPointSize)                               \
  X(PFNGLLINEWIDTHPROC, glLineWidth)                               \
  X(PFNGLREADPIXELSPROC, glReadPixels)                             \
  X(PFNGLREADBUFFERPROC, glReadBuffer)                             \
  X(PFNGLDRAWBUFFERSPROC, glDrawBuffers)                           \
  X(PFNGLPIXELSTOREIPROC, glPixelStorei)                           \
  X(PFNGLFINISHPROC, glFinish)                                     \
  X(PFNGLGENBUFFERSPROC, glGenBuffers)                             \
  X(PFNGLDELETEBUFFERSPROC, glDeleteBuffers)                       \
  X(PFNGLBINDBUFFERPROC, glBindBuffer)                             \
  X(PFNGLBUFFERDATAPROC, glBufferData)                             \
  X(PFNGLISBUFFERPROC, glIsBuffer)                                 \
  X(PFNGLGENVERTEXARRAYSPROC, glGenVertexArrays)                   \
  X(PFNGLDELETEVERTEXARRAYSPROC, glDeleteVertexArrays)             \
  X(PFNGLBINDVERTEXARRAYPROC, glBindVertexArray)                   \
  X(PFNGLISVERTEXARRAYPROC, glIsVertexArray)                       \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, glEnableVertexAttribArray)   \
  X(PFNGLDISABLEVERTEXATTRIBARRAYPROC, glDisableVertexAttribArray) \
  X(PFNGLVERTEXATTRIBPOINTERPROC, glVertexAttribPointer)           \
  X(PFNGLVERTEXATTRIB1FPROC, glVertexAttrib1f)                     \
  X(PFNGLVERTEXATTRIB3FPROC, glVertexAttrib3f)                     \
  X(PFNGLGENTEXTURESPROC, glGenTextures)                           \
  X(PFNGLDELETETEXTURESPROC, glDeleteTextures)                     \
  X(PFNGLBINDTEXTUREPROC, glBindTexture)                           \
  X(PFNGLACTIVETEXTUREPROC, glActiveTexture)                       \
  X(PFNGLTEXBUFFERPROC, glTexBuffer)                               \
  X(PFNGLISTEXTUREPROC, glIsTexture)                               \
  X(PFNGLGENFRAMEBUFFERSPROC, glGenFramebuffers)                   \
  X(PFNGLDELETEFRAMEBUFFERSPROC, glDeleteFramebuffers)             \
  X(PFNGLBINDFRAMEBUFFERPROC, glBindFramebuffer)                   \
  X(PFNGLISFRAMEBUFFERPROC, glIsFramebuffer)                       \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, glFramebufferRenderbuffer)   \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, glCheckFramebufferStatus)     \
  X(PFNGLGENRENDERBUFFERSPROC, glGenRenderbuffers)                 \
  X(PFNGLDELETERENDERBUFFERSPROC, glDeleteRenderbuffers)           \
  X(PFNGLBINDRENDERBUFFERPROC, glBindRenderbuffer)                 \
  X(PFNGLRENDERBUFFERSTORAGEPROC, glRenderbufferStorage)           \
  X(PFNGLISRENDERBUFFERPROC, glIsRenderbuffer)                     \
  X(PFNGLCREATESHADERPROC, glCreateShader)                         \
  X(PFNGLSHADERSOURCEPROC, glShaderSource)                         \
  X(PFNGLCOMPILESHADERPROC, glCompileShader)                       \
  X(PFNGLGETSHADERIVPROC, glGetShaderiv)                           \
  X(PFNGLGETSHADERINFOLOGPROC, glGetShaderInfoLog)                 \
  X(PFNGLDELETESHADERPROC, glDeleteShader)                         \
  X(PFNGLCREATEPROGRAMPROC, glCreateProgram)                       \
  X(PFNGLATTACHSHADERPROC, glAttachShader)                         \
  X(PFNGLLINKPROGRAMPROC, glLinkProgram)                           \
  X(PFNGLGETPROGRAMIVPROC, glGetProgramiv)                         \
  X(PFNGLGETPROGRAMINFOLOGPROC, glGetProgramInfoLog)               \
  X(PFNGLDELETEPROGRAMPROC, glDeleteProgram)                       \
  X(PFNGLISPROGRAMPROC, glIsProgram)                               \
  X(PFNGLUSEPROGRAMPROC, glUseProgram)                             \
  X(PFNGLGETUNIFORMLOCATIONPROC, glGetUniformLocation)             \
  X(PFNGLUNIFORMMATRIX4FVPROC, glUniformMatrix4fv)                 \
  X(PFNGLUNIFORM1IPROC, glUniform1i)                               \
  X(PFNGLUNIFORM1UIPROC, glUniform1ui)                             \
  X(PFNGLUNIFORM1FPROC, glUniform1f)                               \
  X(PFNGLUNIFORM3FPROC, glUniform3f)                               \
  X(PFNGLUNIFORM4FPROC, glUniform4f)                               \
  X(PFNGLDRAWELEMENTSPROC, glDrawElements)                         \
  X(PFNGLDRAWARRAYSPROC, glDrawArrays)

// GL 4.3's compute shaders and storage buffers (rays/gpu_ray_caster.cpp):
// loaded beside the others but not required, so that a 3.3 driver still
// renders.
#define CGVIEW_GL_COMPUTE_FUNCTIONS(X)             \
  X(PFNGLDISPATCHCOMPUTEPROC, glDispatchCompute)   \
  X(PFNGLBINDBUFFERBASEPROC, glBindBufferBase)     \
  X(PFNGLMEMORYBARRIERPROC, glMemoryBarrier)       \
  X(PFNGLBUFFERSUBDATAPROC, glBufferSubData)       \
  X(PFNGLGETBUFFERSUBDATAPROC, glGetBufferSubData) \
  X(PFNGLGETINTEGER64VPROC, glGetInteger64v)

namespace cgview::render {

struct GlComputeFunctions {
#define CGVIEW_GL_MEMBER(type, name) type name = nullptr;
  CGVIEW_GL_COMPUTE_FUNCTIONS(CGVIEW_GL_MEMBER)
#undef CGVIEW_GL_MEMBER
};

struct GlFunctions {
#define CGVIEW_GL_MEMBER(type, name) type name = nullptr;
  CGVIEW_GL_FUNCTIONS(CGVIEW_GL_MEMBER)
#undef CGVIEW_GL_MEMBER
};

struct ShaderStage {
  GLenum type;  // GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, GL_COMPUTE_SHADER
  const char* source;
};

// A program linked from the stages.  Throws Error "<what>: shader
// compilation failed: <the driver's log>" (or linking), leaving nothing behind.
inline GLuint link_program(const GlFunctions& gl, std::initializer_list<ShaderStage> stages, const char* what) {
  std::vector<GLuint> shaders;
  const auto fail = [&](const char* stage, const char* log) {
    for (GLuint s : shaders) gl.glDeleteShader(s);
    throw Error(std::string(what) + ": shader " + stage + " failed: " + log);
  };
  char log[2048] = {};
  GLint ok = 0;
  for (const ShaderStage& st : stages) {
    shaders.push_back(gl.glCreateShader(st.type));
    gl.glShaderSource(shaders.back(), 1, &st.source, nullptr);
    gl.glCompileShader(shaders.back());
    gl.glGetShaderiv(shaders.back(), GL_COMPILE_STATUS, &ok);
    if (!ok) {
      gl.glGetShaderInfoLog(shaders.back(), sizeof log, nullptr, log);
      fail("compilation", log);
    }
  }
  const GLuint p = gl.glCreateProgram();
  for (GLuint s : shaders) gl.glAttachShader(p, s);
  gl.glLinkProgram(p);
  gl.glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    gl.glGetProgramInfoLog(p, sizeof log, nullptr, log);
    gl.glDeleteProgram(p);
    fail("linking", log);
  }
  for (GLuint s : shaders) gl.glDeleteShader(s);
  return p;
}

}  // namespace cgview::render

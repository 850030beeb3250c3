#include "gpu/gl_functions.h"

#include <EGL/egl.h>

#include <stdexcept>

namespace sweepd::gpu {

std::string load_gl_functions(GlFunctions& gl) {
  std::string missing;
#define SWEEPD_GL_LOAD(type, name)                                 \
  gl.name = reinterpret_cast<type>(eglGetProcAddress("gl" #name)); \
  if (gl.name == nullptr) missing += (missing.empty() ? "gl" : " gl") + std::string(#name);
  SWEEPD_GL_FUNCTIONS(SWEEPD_GL_LOAD)
#undef SWEEPD_GL_LOAD
  return missing;
}

const char* gl_error_name(GLenum error) {
  switch (error) {
    case GL_NO_ERROR:
      return "GL_NO_ERROR";
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW:
      return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW:
      return "GL_STACK_OVERFLOW";
    default:
      return "unknown GL error";
  }
}

void throw_on_gl_error(const GlFunctions& gl, const char* what) {
  const GLenum error = gl.GetError();
  if (error != GL_NO_ERROR) {
    throw std::runtime_error(std::string(what) + ": " + gl_error_name(error));
  }
}

}  // namespace sweepd::gpu

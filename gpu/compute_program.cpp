#include "gpu/compute_program.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace sweepd::gpu {

ComputeProgram::ComputeProgram(const GlFunctions& gl, const char* label, const char* source)
    : gl_(gl) {
  const GLuint shader = gl.CreateShader(GL_COMPUTE_SHADER);
  gl.ShaderSource(shader, 1, &source, nullptr);
  gl.CompileShader(shader);
  GLint ok = GL_FALSE;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint length = 0;
    gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(length) + 1, '\0');
    gl.GetShaderInfoLog(shader, length, nullptr, log.data());
    gl.DeleteShader(shader);
    throw std::runtime_error(std::string(label) +
                             " compute shader does not compile: " + log.c_str());
  }
  program_ = gl.CreateProgram();
  gl.AttachShader(program_, shader);
  gl.LinkProgram(program_);
  gl.DeleteShader(shader);  // flagged; freed with the program
  gl.GetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint length = 0;
    gl.GetProgramiv(program_, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(length) + 1, '\0');
    gl.GetProgramInfoLog(program_, length, nullptr, log.data());
    gl.DeleteProgram(program_);
    throw std::runtime_error(std::string(label) + " compute program does not link: " + log.c_str());
  }
}

ComputeProgram::~ComputeProgram() { gl_.DeleteProgram(program_); }

}  // namespace sweepd::gpu

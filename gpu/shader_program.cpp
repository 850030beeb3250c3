#include "gpu/shader_program.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace sweepd::gpu {
namespace {

GLuint compile(const GlFunctions& gl, GLenum stage, const char* label, const char* source) {
  const GLuint shader = gl.CreateShader(stage);
  gl.ShaderSource(shader, 1, &source, nullptr);
  gl.CompileShader(shader);
  GLint ok = GL_FALSE;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok == GL_TRUE) return shader;
  GLint length = 0;
  gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(static_cast<std::size_t>(length) + 1, '\0');
  gl.GetShaderInfoLog(shader, length, nullptr, log.data());
  gl.DeleteShader(shader);
  throw std::runtime_error(std::string(label) +
                           (stage == GL_VERTEX_SHADER ? " vertex" : " fragment") +
                           " shader does not compile: " + log.data());
}

}  // namespace

ShaderProgram::ShaderProgram(const GlFunctions& gl, const char* label, const char* vertex_source,
                             const char* fragment_source)
    : gl_(gl) {
  const GLuint vertex = compile(gl, GL_VERTEX_SHADER, label, vertex_source);
  GLuint fragment = 0;
  try {
    fragment = compile(gl, GL_FRAGMENT_SHADER, label, fragment_source);
  } catch (...) {
    gl.DeleteShader(vertex);
    throw;
  }
  program_ = gl.CreateProgram();
  gl.AttachShader(program_, vertex);
  gl.AttachShader(program_, fragment);
  gl.LinkProgram(program_);
  gl.DeleteShader(vertex);  // flagged; freed with the program
  gl.DeleteShader(fragment);
  GLint ok = GL_FALSE;
  gl.GetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint length = 0;
    gl.GetProgramiv(program_, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(static_cast<std::size_t>(length) + 1, '\0');
    gl.GetProgramInfoLog(program_, length, nullptr, log.data());
    gl.DeleteProgram(program_);
    throw std::runtime_error(std::string(label) + " program does not link: " + log.data());
  }
}

ShaderProgram::~ShaderProgram() { gl_.DeleteProgram(program_); }

}  // namespace sweepd::gpu

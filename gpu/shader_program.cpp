#include "gpu/shader_program.h"

#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

namespace sweepd::gpu {
namespace {

const char* stage_name(GLenum stage) {
  switch (stage) {
    case GL_VERTEX_SHADER:
      return "vertex";
    case GL_FRAGMENT_SHADER:
      return "fragment";
    default:
      return "compute";
  }
}

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
  throw std::runtime_error(std::string(label) + " " + stage_name(stage) +
                           " shader does not compile: " + log.data());
}

// Compiles every (stage, source) and links them; deletes what it made when anything fails.
GLuint build(const GlFunctions& gl, const char* label,
             std::initializer_list<std::pair<GLenum, const char*>> stages) {
  std::vector<GLuint> shaders;
  try {
    for (const auto& [stage, source] : stages) shaders.push_back(compile(gl, stage, label, source));
  } catch (...) {
    for (GLuint shader : shaders) gl.DeleteShader(shader);
    throw;
  }
  const GLuint program = gl.CreateProgram();
  for (GLuint shader : shaders) gl.AttachShader(program, shader);
  gl.LinkProgram(program);
  for (GLuint shader : shaders) gl.DeleteShader(shader);  // flagged; freed with the program
  GLint ok = GL_FALSE;
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok == GL_TRUE) return program;
  GLint length = 0;
  gl.GetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(static_cast<std::size_t>(length) + 1, '\0');
  gl.GetProgramInfoLog(program, length, nullptr, log.data());
  gl.DeleteProgram(program);
  throw std::runtime_error(std::string(label) + " program does not link: " + log.data());
}

}  // namespace

ShaderProgram::ShaderProgram(const GlFunctions& gl, const char* label, const char* vertex_source,
                             const char* fragment_source)
    : gl_(gl),
      program_(build(gl, label,
                     {{GL_VERTEX_SHADER, vertex_source}, {GL_FRAGMENT_SHADER, fragment_source}})) {}

ShaderProgram::ShaderProgram(const GlFunctions& gl, const char* label, const char* compute_source)
    : gl_(gl), program_(build(gl, label, {{GL_COMPUTE_SHADER, compute_source}})) {}

ShaderProgram::~ShaderProgram() { gl_.DeleteProgram(program_); }

}  // namespace sweepd::gpu

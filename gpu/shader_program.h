// ShaderProgram: a linked GLSL program (vertex + fragment, or compute), deleted with the object.
//
// Inputs: GLSL 4.50 core sources. Compile or link failures throw std::runtime_error carrying
// the stage name, the label given and the driver's info log. Use on the context's thread.
#pragma once

#include "gpu/gl_functions.h"

namespace sweepd::gpu {

class ShaderProgram {
 public:
  ShaderProgram(const GlFunctions& gl, const char* label, const char* vertex_source,
                const char* fragment_source);
  // A compute program.
  ShaderProgram(const GlFunctions& gl, const char* label, const char* compute_source);
  ~ShaderProgram();
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  GLuint id() const { return program_; }
  void use() const { gl_.UseProgram(program_); }
  // Location of a uniform; -1 (ignored by glUniform*) when the compiler removed it.
  GLint uniform(const char* name) const { return gl_.GetUniformLocation(program_, name); }

 private:
  const GlFunctions& gl_;
  GLuint program_ = 0;
};

}  // namespace sweepd::gpu

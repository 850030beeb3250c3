// ComputeProgram: a linked GLSL 4.50 compute shader program, deleted with the object.
//
// Input: the compute shader's source. Compile or link failures throw std::runtime_error
// carrying the label given and the driver's info log. Use on the context's thread.
#pragma once

#include "gpu/gl_functions.h"

namespace sweepd::gpu {

class ComputeProgram {
 public:
  ComputeProgram(const GlFunctions& gl, const char* label, const char* source);
  ~ComputeProgram();
  ComputeProgram(const ComputeProgram&) = delete;
  ComputeProgram& operator=(const ComputeProgram&) = delete;

  GLuint id() const { return program_; }
  void use() const { gl_.UseProgram(program_); }
  GLint uniform(const char* name) const { return gl_.GetUniformLocation(program_, name); }

 private:
  const GlFunctions& gl_;
  GLuint program_ = 0;
};

}  // namespace sweepd::gpu

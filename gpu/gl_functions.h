// GlFunctions: the OpenGL 4.5 core entry points sweepd uses, loaded through eglGetProcAddress.
//
// No GL loader library is involved: the types come from <GL/glcorearb.h> and every pointer is
// looked up by name once, right after the context is made current (gpu::Context does it).
// Call them as gl.Clear(...), gl.DrawArrays(...) — the member name is the GL name without "gl".
// A table is valid on whichever thread its context is current on.
#pragma once

#include <GL/glcorearb.h>

#include <string>

namespace sweepd::gpu {

// X(type, name): one line per entry point; add new ones here only.
#define SWEEPD_GL_FUNCTIONS(X)                                               \
  X(PFNGLGETSTRINGPROC, GetString)                                           \
  X(PFNGLGETSTRINGIPROC, GetStringi)                                         \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                       \
  X(PFNGLGETERRORPROC, GetError)                                             \
  X(PFNGLENABLEPROC, Enable)                                                 \
  X(PFNGLDISABLEPROC, Disable)                                               \
  X(PFNGLVIEWPORTPROC, Viewport)                                             \
  X(PFNGLCLEARBUFFERFVPROC, ClearBufferfv)                                   \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                                           \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                         \
  X(PFNGLDRAWELEMENTSPROC, DrawElements)                                     \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                         \
  X(PFNGLREADBUFFERPROC, ReadBuffer)                                         \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                       \
  X(PFNGLFINISHPROC, Finish)                                                 \
  X(PFNGLCREATESHADERPROC, CreateShader)                                     \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                                     \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                                   \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                       \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                             \
  X(PFNGLDELETESHADERPROC, DeleteShader)                                     \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                   \
  X(PFNGLATTACHSHADERPROC, AttachShader)                                     \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                       \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                     \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                           \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                   \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                         \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                         \
  X(PFNGLUNIFORM1FPROC, Uniform1f)                                           \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                           \
  X(PFNGLUNIFORM1UIPROC, Uniform1ui)                                         \
  X(PFNGLUNIFORM3FVPROC, Uniform3fv)                                         \
  X(PFNGLUNIFORM4FVPROC, Uniform4fv)                                         \
  X(PFNGLUNIFORMMATRIX3FVPROC, UniformMatrix3fv)                             \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                             \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                               \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                               \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                         \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                                         \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                                         \
  X(PFNGLBUFFERDATAPROC, BufferData)                                         \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                   \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                       \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)               \
  X(PFNGLDISABLEVERTEXATTRIBARRAYPROC, DisableVertexAttribArray)             \
  X(PFNGLVERTEXATTRIB4FPROC, VertexAttrib4f)                                 \
  X(PFNGLGENTEXTURESPROC, GenTextures)                                       \
  X(PFNGLBINDTEXTUREPROC, BindTexture)                                       \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                                   \
  X(PFNGLTEXSTORAGE2DPROC, TexStorage2D)                                     \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                   \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                 \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                               \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                               \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)                     \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)               \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                 \
  X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                                       \
  X(PFNGLBLITFRAMEBUFFERPROC, BlitFramebuffer)                               \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                         \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                             \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                             \
  X(PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC, RenderbufferStorageMultisample) \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                       \
  X(PFNGLDEBUGMESSAGECALLBACKPROC, DebugMessageCallback)                     \
  X(PFNGLDEBUGMESSAGECONTROLPROC, DebugMessageControl)                       \
  X(PFNGLDISPATCHCOMPUTEPROC, DispatchCompute)                               \
  X(PFNGLDISPATCHCOMPUTEINDIRECTPROC, DispatchComputeIndirect)               \
  X(PFNGLMEMORYBARRIERPROC, MemoryBarrier)                                   \
  X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                                 \
  X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                                   \
  X(PFNGLGETBUFFERSUBDATAPROC, GetBufferSubData)

struct GlFunctions {
#define SWEEPD_GL_DECLARE(type, name) type name = nullptr;
  SWEEPD_GL_FUNCTIONS(SWEEPD_GL_DECLARE)
#undef SWEEPD_GL_DECLARE
};

// Looks every entry point up with eglGetProcAddress. Returns the names that resolved to null,
// space-separated (empty when all were found); the caller decides whether that is fatal.
std::string load_gl_functions(GlFunctions& gl);

// "GL_INVALID_OPERATION" and friends for a glGetError code.
const char* gl_error_name(GLenum error);

// Throws std::runtime_error "<what>: GL_..." when glGetError reports an error.
void throw_on_gl_error(const GlFunctions& gl, const char* what);

}  // namespace sweepd::gpu

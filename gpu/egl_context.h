// Context: a headless OpenGL 4.5 core context over EGL — no X server, no window, no surface.
//
// Display selection (first that yields a 4.5 core context wins):
//   1. EGL_EXT_platform_device: the devices of eglQueryDevicesEXT, hardware devices first,
//      those with EGL_MESA_device_software (llvmpipe) after them;
//   2. EGL_MESA_platform_surfaceless on the default display.
// The context is made current with no surface on the constructing thread; GL calls through
// gl() are valid on that thread only (gpu::Worker gives the context a thread of its own).
// With ContextOptions::debug_output, GL debug messages (KHR_debug, synchronous) go to stderr or
// to ContextOptions::debug_sink.
// Construction throws ContextError listing every attempt and why it failed, so a machine with no
// usable EGL says so; the CPU paths of sweepd do not need a Context.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

#include "gpu/gl_functions.h"

namespace sweepd::gpu {

class ContextError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ContextOptions {
#ifdef NDEBUG
  bool debug_output = false;
#else
  bool debug_output = true;  // debug builds report GL errors and warnings on stderr
#endif
  // Receives each debug message (errors, warnings, performance notes; not notifications) on
  // the context's thread; empty: they go to stderr.
  std::function<void(const std::string&)> debug_sink;
};

class Context {
 public:
  explicit Context(const ContextOptions& options = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const GlFunctions& gl() const { return gl_; }
  const std::string& renderer() const { return renderer_; }  // GL_RENDERER, e.g. "llvmpipe (...)"
  const std::string& version() const { return version_; }    // GL_VERSION
  int major_version() const { return major_; }
  int minor_version() const { return minor_; }
  bool core_profile() const { return core_profile_; }
  // "device" or "surfaceless", and whether the device is Mesa's software rasteriser.
  const std::string& platform() const { return platform_; }
  bool software() const { return software_; }

  // Makes the context current on the calling thread.
  void make_current();

 private:
  void destroy();

  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  GlFunctions gl_;
  std::function<void(const std::string&)> debug_sink_;
  std::string renderer_, version_, platform_;
  int major_ = 0, minor_ = 0;
  bool core_profile_ = false, software_ = false;
};

}  // namespace sweepd::gpu

#include "gpu/egl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>
#include <link.h>

#include <cstdio>
#include <map>
#include <mutex>
#include <string_view>
#include <vector>

namespace sweepd::gpu {
namespace {

std::string egl_error_name(EGLint error) {
  switch (error) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default:
      return "EGL error " + std::to_string(error);
  }
}

bool has_extension(const char* extensions, std::string_view name) {
  if (extensions == nullptr) return false;
  std::string_view list(extensions);
  for (std::size_t start = 0; start < list.size();) {
    std::size_t end = list.find(' ', start);
    if (end == std::string_view::npos) end = list.size();
    if (list.substr(start, end - start) == name) return true;
    start = end + 1;
  }
  return false;
}

// EGL displays are per-process singletons: eglInitialize on one twice and a single eglTerminate
// ends both users. Contexts count their displays here and the last one out terminates.
std::mutex display_users_mutex;
std::map<EGLDisplay, int> display_users;

void add_display_user(EGLDisplay display) {
  std::lock_guard lock(display_users_mutex);
  ++display_users[display];
}

void remove_display_user(EGLDisplay display) {
  std::lock_guard lock(display_users_mutex);
  if (--display_users[display] == 0) {
    display_users.erase(display);
    eglTerminate(display);
  }
}

// Mesa's driver (.../dri/*_dri.so, or libgallium-*.so since Mesa 24.1) is loaded by
// eglInitialize and unloaded by the last eglTerminate. It keeps a buffer from a one-time
// (pthread_once) initialisation in its globals, so each unload loses that buffer (128 bytes
// under llvmpipe, a leak report under LeakSanitizer) and the next Context loads and
// initialises the driver again. Once loaded, the driver stays for the process's life
// (RTLD_NODELETE on the objects already mapped; dlopen is not called inside dl_iterate_phdr,
// whose loader lock it would need).
void keep_drivers_loaded() {
  std::vector<std::string> drivers;
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* found) {
        const std::string_view path = info->dlpi_name == nullptr ? "" : info->dlpi_name;
        if ((path.find("/dri/") != std::string_view::npos && path.ends_with("_dri.so")) ||
            path.find("/libgallium") != std::string_view::npos)
          static_cast<std::vector<std::string>*>(found)->emplace_back(path);
        return 0;
      },
      &drivers);
  for (const std::string& driver : drivers) {
    // The handle is never closed: holding it is the point.
    static_cast<void>(dlopen(driver.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE));
  }
}

struct Candidate {
  EGLDisplay display;
  std::string platform;
  bool software;
  std::string label;  // for error messages
};

std::vector<Candidate> candidate_displays(std::string& failures) {
  std::vector<Candidate> candidates;
  const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr) {
    failures += "eglGetPlatformDisplayEXT is missing (no EGL_EXT_platform_base); ";
    return candidates;
  }
  auto query_devices =
      reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto query_device_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
      eglGetProcAddress("eglQueryDeviceStringEXT"));
  if (has_extension(client_extensions, "EGL_EXT_platform_device") && query_devices != nullptr &&
      query_device_string != nullptr) {
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (query_devices(16, devices, &count) == EGL_TRUE) {
      std::vector<Candidate> software_devices;
      for (EGLint i = 0; i < count; ++i) {
        const bool software = has_extension(query_device_string(devices[i], EGL_EXTENSIONS),
                                            "EGL_MESA_device_software");
        const EGLDisplay display =
            get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        const std::string label = "device " + std::to_string(i) + (software ? " (software)" : "");
        if (display == EGL_NO_DISPLAY) {
          failures += label + ": no display (" + egl_error_name(eglGetError()) + "); ";
          continue;
        }
        (software ? software_devices : candidates).push_back({display, "device", software, label});
      }
      candidates.insert(candidates.end(), software_devices.begin(), software_devices.end());
    } else {
      failures += "eglQueryDevicesEXT failed (" + egl_error_name(eglGetError()) + "); ";
    }
  } else {
    failures += "no EGL_EXT_platform_device; ";
  }
  if (has_extension(client_extensions, "EGL_MESA_platform_surfaceless")) {
    const EGLDisplay display =
        get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display != EGL_NO_DISPLAY) {
      candidates.push_back({display, "surfaceless", false, "surfaceless"});
    } else {
      failures += "surfaceless: no display (" + egl_error_name(eglGetError()) + "); ";
    }
  } else {
    failures += "no EGL_MESA_platform_surfaceless; ";
  }
  return candidates;
}

// A 4.5 core context on an initialised display, or EGL_NO_CONTEXT with the reason in failure.
EGLContext create_core_context(EGLDisplay display, bool debug, std::string& failure) {
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
    failure = "eglBindAPI(EGL_OPENGL_API) failed";
    return EGL_NO_CONTEXT;
  }
  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  if (!has_extension(extensions, "EGL_KHR_surfaceless_context")) {
    failure = "no EGL_KHR_surfaceless_context";
    return EGL_NO_CONTEXT;
  }
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!has_extension(extensions, "EGL_KHR_no_config_context")) {
    const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE,
                                        EGL_PBUFFER_BIT, EGL_NONE};
    EGLint count = 0;
    if (eglChooseConfig(display, config_attributes, &config, 1, &count) != EGL_TRUE || count == 0) {
      failure = "no OpenGL-renderable EGL config";
      return EGL_NO_CONTEXT;
    }
  }
  const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                       4,
                                       EGL_CONTEXT_MINOR_VERSION,
                                       5,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                       EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                       EGL_CONTEXT_OPENGL_DEBUG,
                                       debug ? EGL_TRUE : EGL_FALSE,
                                       EGL_NONE};
  const EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
  if (context == EGL_NO_CONTEXT) {
    failure = "no OpenGL 4.5 core context (" + egl_error_name(eglGetError()) + ")";
  }
  return context;
}

void APIENTRY forward_debug_message(GLenum /*source*/, GLenum type, GLuint id, GLenum severity,
                                    GLsizei /*length*/, const GLchar* message, const void* user) {
  if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
  const std::string text = std::string("GL ") +
                           (type == GL_DEBUG_TYPE_ERROR ? "error" : "warning") + " (id " +
                           std::to_string(id) + "): " + message;
  const auto& sink = *static_cast<const std::function<void(const std::string&)>*>(user);
  if (sink) {
    sink(text);
  } else {
    std::fprintf(stderr, "sweepd %s\n", text.c_str());
  }
}

}  // namespace

Context::Context(const ContextOptions& options) {
  std::string failures;
  for (const Candidate& candidate : candidate_displays(failures)) {
    EGLint major = 0, minor = 0;
    if (eglInitialize(candidate.display, &major, &minor) != EGL_TRUE) {
      failures +=
          candidate.label + ": eglInitialize failed (" + egl_error_name(eglGetError()) + "); ";
      continue;
    }
    add_display_user(candidate.display);
    keep_drivers_loaded();
    std::string failure;
    const EGLContext context =
        create_core_context(candidate.display, options.debug_output, failure);
    if (context != EGL_NO_CONTEXT &&
        eglMakeCurrent(candidate.display, EGL_NO_SURFACE, EGL_NO_SURFACE, context) != EGL_TRUE) {
      failure = "eglMakeCurrent without surface failed (" + egl_error_name(eglGetError()) + ")";
      eglDestroyContext(candidate.display, context);
    } else if (context != EGL_NO_CONTEXT) {
      display_ = candidate.display;
      context_ = context;
      platform_ = candidate.platform;
      software_ = candidate.software;
      break;
    }
    failures += candidate.label + ": " + failure + "; ";
    remove_display_user(candidate.display);
  }
  if (context_ == nullptr) {
    if (failures.empty()) failures = "no EGL display to try; ";
    failures.resize(failures.size() - 2);  // the last "; "
    throw ContextError("no headless OpenGL 4.5 core context through EGL: " + failures +
                       " (needs an EGL driver: Mesa's libegl-mesa0 + libgl1-mesa-dri, or a GPU's)");
  }
  const std::string missing = load_gl_functions(gl_);
  if (!missing.empty()) {
    destroy();
    throw ContextError("OpenGL entry points missing from the EGL driver: " + missing);
  }
  renderer_ = reinterpret_cast<const char*>(gl_.GetString(GL_RENDERER));
  version_ = reinterpret_cast<const char*>(gl_.GetString(GL_VERSION));
  gl_.GetIntegerv(GL_MAJOR_VERSION, &major_);
  gl_.GetIntegerv(GL_MINOR_VERSION, &minor_);
  GLint profile = 0;
  gl_.GetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  core_profile_ = (profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
  if (options.debug_output) {
    gl_.Enable(GL_DEBUG_OUTPUT);
    gl_.Enable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    debug_sink_ = options.debug_sink;
    gl_.DebugMessageCallback(forward_debug_message, &debug_sink_);
  }
}

Context::~Context() { destroy(); }

void Context::destroy() {
  if (context_ == nullptr) return;
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  remove_display_user(display_);
  eglReleaseThread();
  context_ = nullptr;
}

void Context::make_current() {
  if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE) {
    throw ContextError("eglMakeCurrent failed (" + egl_error_name(eglGetError()) + ")");
  }
}

}  // namespace sweepd::gpu

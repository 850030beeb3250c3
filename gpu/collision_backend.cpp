#include "gpu/collision_backend.h"

namespace sweepd::gpu {

bool is_software_renderer(std::string_view renderer, bool software_device) {
  return software_device || renderer.starts_with("llvmpipe") || renderer.starts_with("softpipe");
}

CollisionBackendDecision choose_collision_backend(CollisionChoice choice, const EglDevice& device) {
  const bool context = device.failure.empty();
  // "llvmpipe (software)", or the hardware renderer's full name.
  const std::string kind =
      device.software ? device.renderer.substr(0, device.renderer.find(' ')) + " (software)"
                      : device.renderer + " (hardware)";
  switch (choice) {
    case CollisionChoice::kCpu:
      return {CollisionBackend::kCpu, "--collision cpu: the CPU reference"};
    case CollisionChoice::kGpu:
      if (!context) {
        throw CollisionBackendError("--collision gpu: no usable EGL context (" + device.failure +
                                    "); use --collision auto or cpu on a machine without one");
      }
      return {CollisionBackend::kGpu, "--collision gpu on " + kind};
    case CollisionChoice::kAuto:
      break;
  }
  if (!context) {
    return {CollisionBackend::kCpu,
            "--collision auto: no usable EGL context (" + device.failure + "), the CPU"};
  }
  if (device.software) {
    return {CollisionBackend::kCpu,
            "--collision auto: " + kind + ", the CPU reference is faster than a software GPU"};
  }
  return {CollisionBackend::kGpu, "--collision auto: " + kind};
}

std::optional<CollisionChoice> parse_collision_choice(std::string_view text) {
  if (text == "auto") return CollisionChoice::kAuto;
  if (text == "gpu") return CollisionChoice::kGpu;
  if (text == "cpu") return CollisionChoice::kCpu;
  return std::nullopt;
}

const char* to_string(CollisionChoice choice) {
  switch (choice) {
    case CollisionChoice::kAuto:
      return "auto";
    case CollisionChoice::kGpu:
      return "gpu";
    case CollisionChoice::kCpu:
      return "cpu";
  }
  return "auto";
}

const char* to_string(CollisionBackend backend) {
  return backend == CollisionBackend::kGpu ? "gpu" : "cpu";
}

}  // namespace sweepd::gpu

// CollisionBackend: where folding finds its intersecting triangle pairs — the CPU reference
// (deform::SelfIntersectionDetector) or the GPU (gpu::CollisionDetector, the same pairs) —
// decided once at start-up from the user's choice (`--collision auto|gpu|cpu` of sweepd and
// sweepctl) and what EGL found.
//
// choose_collision_backend(choice, device)
//   Inputs:  choice  kAuto, kGpu or kCpu
//            device  the EGL context EGL gave (GL_RENDERER and whether it is a software
//                    rasteriser), or its failure (why no context could be made)
//   Output:  the backend and the reason, for the start-up log line:
//            cpu: the CPU; gpu: the GPU when a context exists — llvmpipe included (that is how
//            CI runs the GPU path) — else CollisionBackendError naming the EGL problem;
//            auto: the GPU on a hardware device, the CPU on a software one ("llvmpipe
//            (software)") or without EGL.
// parse_collision_choice: "auto"/"gpu"/"cpu" (nullopt otherwise); to_string: the same names.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace sweepd::gpu {

enum class CollisionChoice { kAuto, kGpu, kCpu };
enum class CollisionBackend { kCpu, kGpu };

struct EglDevice {
  std::string renderer;   // GL_RENDERER; empty when no context could be made
  bool software = false;  // Mesa's llvmpipe/softpipe
  std::string failure;    // why no context could be made; empty when one was
};

struct CollisionBackendDecision {
  CollisionBackend backend = CollisionBackend::kCpu;
  std::string reason;
};

class CollisionBackendError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

CollisionBackendDecision choose_collision_backend(CollisionChoice choice, const EglDevice& device);

// Whether a context is a software rasteriser: EGL's device flag, or a Mesa software renderer's
// GL_RENDERER (the surfaceless platform does not say).
bool is_software_renderer(std::string_view renderer, bool software_device);

std::optional<CollisionChoice> parse_collision_choice(std::string_view text);
const char* to_string(CollisionChoice choice);
const char* to_string(CollisionBackend backend);

}  // namespace sweepd::gpu

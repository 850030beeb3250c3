// ModelLookup: a held model by its protocol id (Pose.model_id), or nullptr — all that pose
// intake (handlers/pose_intake.h) needs of the models: ModelService in the daemon, one bound
// model in the fuzzer (fuzz/fuzz_inputs.cpp).
#pragma once

#include <cstdint>

#include "server/models/model_registry.h"

namespace sweepd::server {

class ModelLookup {
 public:
  virtual ~ModelLookup() = default;
  virtual ModelHandle find(std::uint32_t id) const = 0;
};

}  // namespace sweepd::server

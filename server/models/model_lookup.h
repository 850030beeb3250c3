// ModelLookup: a held model by its protocol id (Pose.model_id), or nullptr — all that pose
// intake (handlers/pose_intake.h) needs of the models: ModelService in the daemon, one bound
// model in the fuzzer (fuzz/fuzz_inputs.cpp) — and the names of the models held, so that an
// UnknownModel error can say which exist (held_models_clause).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "server/models/model_registry.h"

namespace sweepd::server {

class ModelLookup {
 public:
  virtual ~ModelLookup() = default;
  virtual ModelHandle find(std::uint32_t id) const = 0;
  // The held models, by handle.
  virtual std::vector<ModelHandle> held_models() const = 0;
};

// For an UnknownModel message: "this server holds 'body' (id 2874114816), ..." — at most 12
// models, then "and N more" (motion/name_list.h) — or "this server holds no model".
std::string held_models_clause(const ModelLookup& models);

}  // namespace sweepd::server

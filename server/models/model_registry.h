// ModelRegistry: the models a sweepd holds, by id and by name, and their on-disk store.
//
// Store layout (store_dir): <id>.sweepbind per model (io::save_sweepbind: tmp + fsync +
// rename, CRC-checked) and index.json {"version":1,"next_id":N,"models":[{"id","name",
// "file","bind_time_ns"}]}, rewritten the same durable way after each .sweepbind. A model is
// acknowledged only once both are on disk, so a restart — even after kill -9 — finds every
// acknowledged model and loads it without rebinding. Uploaded .glb bytes are kept as
// <id>.glb beside it (the source of the binding).
//
// The daemon reaches it only through ModelService (model_service.h), the one place models change.
// Thread-safe: loads bind outside the lock (seconds), lookups never wait for a bind.
// Errors a client causes throw ModelError with the protocol code to answer and a message
// naming the model and the reason.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/job/model_runtime.h"
#include "protocol/sweepd_generated.h"

namespace sweepd::server {

struct RegisteredModel {
  std::uint32_t id = 0;
  std::string name;
  deform::BoundModel bound;
  std::uint64_t bind_time_ns = 0;  // 0 when restored from the store
  // Built from `bound` once it is final, shared read-only by every worker's DeformContext.
  std::shared_ptr<const deform::ModelRuntime> runtime{};
};
using ModelHandle = std::shared_ptr<const RegisteredModel>;

class ModelError : public std::runtime_error {
 public:
  ModelError(protocol::ErrorCode code, const std::string& message)
      : std::runtime_error(message), code_(code) {}
  protocol::ErrorCode code() const { return code_; }

 private:
  protocol::ErrorCode code_;
};

struct ModelLoadRequest {
  std::string name;                    // stored name; with no gltf: a model_dir file name
  std::span<const std::uint8_t> gltf;  // uploaded .glb/.gltf bytes, or empty
  std::string rig_map_json;            // io/rig_map_json.h override, or empty: detect
  int keys_per_link = 0;               // 0: the bind default
};

struct ModelRegistryLimits {
  std::uint32_t max_models = 16;
  std::uint32_t max_model_vertices = 2'000'000;
};

class ModelRegistry {
 public:
  // Creates store_dir if needed. model_dir may be empty (no directory to load from).
  ModelRegistry(std::filesystem::path store_dir, std::filesystem::path model_dir,
                ModelRegistryLimits limits);

  // Loads index.json and every model it names. Returns one line per entry that could not be
  // restored (file and reason); those entries are dropped from the index.
  std::vector<std::string> restore();

  ModelHandle find(std::uint32_t id) const;
  ModelHandle find(std::string_view name) const;
  std::vector<ModelHandle> models() const;  // by id
  // Model files in model_dir (file names) not loaded under that name, sorted.
  std::vector<std::string> directory_entries() const;

  // Binds and stores a model; returns it once durable. An already loaded name given without
  // bytes returns that model. Throws ModelError.
  ModelHandle load(const ModelLoadRequest& request);
  // Stores an already bound model under `name` (the default mannequin). Throws ModelError.
  ModelHandle add(const std::string& name, deform::BoundModel bound, std::uint64_t bind_time_ns);
  // Replaces model `id`'s binding (an edit), stored durably before it is swapped in; connections
  // holding the old handle finish with it. ModelError{UnknownModel / Internal}.
  ModelHandle replace(std::uint32_t id, deform::BoundModel bound);

  const std::filesystem::path& store_dir() const { return store_dir_; }

 private:
  std::filesystem::path model_file_in_directory(const std::string& name) const;
  void check_room(const std::string& name) const;  // caller holds mutex_
  void write_index() const;                        // caller holds mutex_

  std::filesystem::path store_dir_, model_dir_;
  ModelRegistryLimits limits_;
  mutable std::mutex mutex_;
  std::mutex store_mutex_;  // one bind/store at a time: ids and files stay in step
  std::vector<ModelHandle> models_;
  std::uint32_t next_id_ = 1;
};

}  // namespace sweepd::server

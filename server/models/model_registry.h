// ModelRegistry: the models a sweepd holds, by id and by name, and their on-disk store.
//
// Store layout (store_dir): <id>.sweepbind per model (io::save_sweepbind: tmp + fsync +
// rename, CRC-checked) and index.json {"version":1,"next_id":N,"models":[{"id","name",
// "file","bind_time_ns"}]}, rewritten the same durable way after each .sweepbind. A model is
// acknowledged, and visible to any client, only once both are on disk, so a restart — even
// after kill -9 — finds every acknowledged model and loads it without rebinding. Uploaded .glb
// bytes are kept as <id>.glb beside it (the source of the binding), a client's rig map as
// <id>.rig.json. An edit rewrites <id>.sweepbind the same way before it is acknowledged.
//
// restore() is where a damaged store is mended, never by deleting what it cannot read:
// FILE.tmp files (a crash before a rename: never a committed state) are removed; a .sweepbind
// that does not load (checksum, truncation, any reason io::load_sweepbind gives) is moved to
// store_dir/quarantine/ with its .glb and .rig.json (store_quarantine.h) and its entry
// dropped; an entry whose file is missing is dropped; an unreadable index.json is quarantined
// and the index rebuilt from the <id>.sweepbind files (names from the files, bind times 0).
// Every other model loads; ids are never reused, a dropped one included.
//
// It knows nothing of glTF, rigs or binding: ModelService (model_service.h), the one place
// models change, loads and binds a model while it holds a StoreSlot (the next id, and the right
// to store under it), then adds the bound model. Thread-safe: a bind holds only the slot, never
// the lock lookups take, so lookups never wait for a bind; edits of a model apply one after
// the other, each to the binding the last one stored.
// Errors a client causes throw ModelError with the protocol code to answer and a message
// naming the model and the reason.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
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

// One thing restore() found in the store and did not load.
struct StoreProblem {
  std::filesystem::path file;            // the store file (for a missing one: the name listed)
  std::string reason;                    // why it was not loaded
  std::filesystem::path quarantined_to;  // where it was moved; empty: nothing to move
};

struct RestoreReport {
  std::vector<StoreProblem> problems;
  std::vector<std::filesystem::path> removed_temporaries;  // FILE.tmp left by a crash
  bool index_rebuilt = false;  // index.json was unreadable, or absent beside .sweepbind files
};

class ModelError : public std::runtime_error {
 public:
  ModelError(protocol::ErrorCode code, const std::string& message)
      : std::runtime_error(message), code_(code) {}
  protocol::ErrorCode code() const { return code_; }

 private:
  protocol::ErrorCode code_;
};

class ModelRegistry {
 public:
  // The next model's id, claimed for one load: held, it keeps every other load and store out
  // (one at a time, so ids and files stay in step); file(suffix) is store_dir/<id><suffix>,
  // where the load keeps what its binding came from (the uploaded .glb, the rig map).
  class StoreSlot {
   public:
    std::uint32_t id() const { return id_; }
    std::filesystem::path file(std::string_view suffix) const;

   private:
    friend class ModelRegistry;
    StoreSlot(std::unique_lock<std::mutex> lock, std::filesystem::path store_dir, std::uint32_t id)
        : lock_(std::move(lock)), store_dir_(std::move(store_dir)), id_(id) {}
    std::unique_lock<std::mutex> lock_;
    std::filesystem::path store_dir_;
    std::uint32_t id_;
  };

  // Creates store_dir if needed.
  ModelRegistry(std::filesystem::path store_dir, std::uint32_t max_models);

  // Loads index.json and every model it names, mending the store as the header says; the
  // index is rewritten when anything was dropped or it was rebuilt. Throws only when the store
  // directory itself cannot be read or written.
  RestoreReport restore();

  ModelHandle find(std::uint32_t id) const;
  ModelHandle find(std::string_view name) const;
  std::vector<ModelHandle> models() const;  // by id

  // Claims the next id for a model called `name`. ModelError{ModelLimit} when the registry is
  // full, {ModelLoadFailed} when a model of that name is loaded.
  StoreSlot claim(const std::string& name);
  // Stores a bound model under the slot's id and returns it once durable (.sweepbind, then the
  // index). Throws ModelError (the claim's codes again, or Internal: the store failed).
  ModelHandle add(StoreSlot slot, const std::string& name, deform::BoundModel bound,
                  std::uint64_t bind_time_ns);
  // Edits model `id`'s binding: `change` gets a copy of the current one (it may throw
  // ModelError to refuse, changing nothing); the result is stored durably, then swapped in and
  // returned. One edit at a time, so concurrent edits of a model are all kept; connections
  // holding the old handle finish with it. ModelError{UnknownModel / Internal / change's}.
  ModelHandle replace(std::uint32_t id, const std::function<void(deform::BoundModel&)>& change);

  const std::filesystem::path& store_dir() const { return store_dir_; }

 private:
  void check_room(const std::string& name) const;  // caller holds mutex_

  std::filesystem::path store_dir_;
  std::uint32_t max_models_;
  mutable std::mutex mutex_;
  std::mutex store_mutex_;  // held by the StoreSlot of the one load in progress
  std::mutex edit_mutex_;   // held by the one replace() in progress
  std::vector<ModelHandle> models_;
  std::uint32_t next_id_ = 1;
};

}  // namespace sweepd::server

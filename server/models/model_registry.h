// ModelRegistry: the models a sweepd holds, by handle, content id and name, and their on-disk
// store, which several replicas may share (a ReadWriteMany volume, NFS).
//
// Store layout (store_dir), one set of files per model, named by its content id
// (content_id.h; 64 hex digits, "<cid>" below) — there is no shared index to race on:
//   <cid>.json       {"version":2,"content_id","name","bind_time_ns"}: its label and history;
//   <cid>.sweepbind  the binding (io::save_sweepbind, CRC-checked) — written last: a model is
//                    in the store once this file is;
//   <cid>.glb        the uploaded bytes it was bound from (.fbx, .dae for an FBX or COLLADA
//                    upload); <cid>.rig.json a client's rig map;
//   <cid>.selfcheck.json  the binding's self-check verdicts, keyed by the binding's checksum
//                    (self_check_sidecar.h) — written after the .sweepbind, read instead of
//                    checking again when its key matches.
// Every file is written by io::write_file_durably (a temporary named by its writer, fsync,
// rename, directory fsync), so two replicas storing the same model at once each rename a whole
// file over the other's identical one, and no reader sees a torn file. A model is acknowledged,
// and visible to any client, only once its files are durable, so a restart — even after kill
// -9 — finds every acknowledged model and loads it without rebinding.
//
// A model's handle (the protocol's model_id) is handle_of(content id): the same on every
// replica and across restarts. A model another replica stored is found without a restart:
// adopt(cid) loads it from the store (LoadModel by content id, or an upload of the same bytes).
//
// restore() is where a damaged store is mended, never by deleting what it cannot read:
// temporaries whose writer is gone are removed (store_quarantine.h); a .sweepbind that does not
// load (checksum, truncation, any reason io::load_sweepbind gives) is moved to
// store_dir/quarantine/ with its other files; a model whose name or handle another restored
// model already has is left in the store, not loaded, and reported. A store written before
// content ids (index.json, <n>.sweepbind) is migrated: each model gets the content id of its
// .sweepbind's bytes and keeps its name.
//
// It knows nothing of glTF, rigs or binding: ModelService (model_service.h), the one place
// models change, loads and binds a model while it holds a StoreSlot (the right to store one
// content id), then adds the bound model with its self-check. The runtime it derives again
// whenever the binding is read from the store or edited; the self-check it checks again at an
// edit, and reads from the binding's sidecar when the binding is read from the store (checking
// again only when the sidecar is not this binding's). Thread-safe: a bind holds only the slot,
// never the lock lookups take, so lookups never wait for a bind; edits of a model apply one after
// the other, each to the binding the last one stored.
//
// Edits on a shared store: an edit renames a new <cid>.sweepbind over the old one (the content
// id stays: it names the upload, and a new id per edit would fork concurrent editors). It runs
// under the model's StoreEditLock (<cid>.lock, store_edit_lock.h), which every replica's edits
// of that model take, and starts from the file as it is then, so concurrent edits on several
// replicas are all kept; it is acknowledged after the rename and the directory's fsync. Each
// held model keeps the version of the file it came from open (binding_file.h); current(id),
// which every pose's worker calls before it deforms, stats the file once and, when another
// replica replaced it, loads the new version first: new requests get it, requests in flight
// finish with the copy they hold. A replaced file that does not load is quarantined and the held
// copy served on. Errors a client causes throw ModelError with the protocol code to answer and a
// message naming the model and the reason.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/job/model_runtime.h"
#include "protocol/sweepd_generated.h"
#include "server/models/binding_file.h"
#include "server/models/content_id.h"
#include "server/models/self_check.h"

namespace sweepd::server {

struct RegisteredModel {
  std::uint32_t id = 0;    // handle_of(content_id)
  std::string content_id;  // content_id.h
  std::string name;
  deform::BoundModel bound;
  std::uint64_t bind_time_ns = 0;  // as stored; 0 for a store migrated from the first layout
  // Built from `bound` once it is final, shared read-only by every worker's DeformContext.
  std::shared_ptr<const deform::ModelRuntime> runtime{};
  // The version of store_dir/<content_id>.sweepbind `bound` was read from or written as.
  std::shared_ptr<const BindingFile> file{};
  // Of `bound` as held: given at add, run again at an edit, read from the sidecar (or run
  // again when it has none for this binding) when read from the store.
  SelfCheck self_check{};
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
  std::vector<std::filesystem::path> removed_temporaries;  // left by a crashed writer
  std::size_t migrated = 0;  // models moved from a store written before content ids
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
  // The right to store one model, held for one load: it keeps every other load, adopt and store
  // of this registry out (one at a time, so a content id is bound once); file(suffix) is
  // store_dir/<content id><suffix>, where the load keeps what its binding came from (the
  // uploaded .glb, the rig map).
  class StoreSlot {
   public:
    std::uint32_t id() const { return handle_of(content_id_); }
    const std::string& content_id() const { return content_id_; }
    std::filesystem::path file(std::string_view suffix) const;
    // Kept as long as the slot (a load's working memory, ModelLoadRequest): let go of before
    // the next load may claim the store.
    void hold(std::shared_ptr<const void> held) { held_.push_back(std::move(held)); }

   private:
    friend class ModelRegistry;
    StoreSlot(std::unique_lock<std::mutex> lock, std::filesystem::path store_dir,
              std::string content_id)
        : lock_(std::move(lock)), store_dir_(std::move(store_dir)), content_id_(content_id) {}
    std::unique_lock<std::mutex> lock_;
    std::filesystem::path store_dir_;
    std::string content_id_;
    std::vector<std::shared_ptr<const void>> held_;  // after lock_: gone before it unlocks
  };

  // Creates store_dir if needed.
  ModelRegistry(std::filesystem::path store_dir, std::uint32_t max_models);

  // Loads every model of the store, mending and migrating it as the header says. Throws only
  // when the store directory itself cannot be read or written.
  RestoreReport restore();

  ModelHandle find(std::uint32_t id) const;
  // find(id), first loading the model's binding again when another replica replaced it in the
  // store (the header). A replaced file that does not load is quarantined, described in
  // `*problem` (when given), and the held model returned.
  ModelHandle current(std::uint32_t id, std::optional<StoreProblem>* problem = nullptr);
  ModelHandle find(std::string_view name) const;
  ModelHandle find_content(std::string_view content_id) const;
  std::vector<ModelHandle> models() const;  // by handle

  // The model `content_id`: held, or loaded from the store (another replica stored it, or this
  // one before it was full); nullptr when the store has no such model. ModelError{ModelLimit,
  // ModelLoadFailed (name or handle taken; a damaged file, which is quarantined)}.
  // `hold_reading_memory`, when given, is called with the stored binding's bytes before it is
  // read; what it returns is kept until the model is held (it may throw ModelError to refuse,
  // reading nothing).
  ModelHandle adopt(const std::string& content_id,
                    const std::function<std::shared_ptr<const void>(std::uint64_t binding_bytes)>&
                        hold_reading_memory = {});
  // The content id of a model named `name` in the store (stored by any replica); empty: none.
  std::string stored_content_named(std::string_view name) const;

  // Claims the right to store `content_id` as a model called `name`. ModelError{ModelLimit}
  // when the registry is full, {ModelLoadFailed} when another model of that name or handle is
  // held. A model of this content id stored while the claim waited is held: find_content.
  StoreSlot claim(const std::string& name, const std::string& content_id);
  // Stores a bound model under the slot's content id with `checked`, its self-check, and
  // returns it once durable (.json, then .sweepbind; then the self-check's sidecar, a cache
  // whose failure fails nothing). Throws ModelError (the claim's codes again, or Internal: the
  // store failed).
  ModelHandle add(StoreSlot slot, const std::string& name, deform::BoundModel bound,
                  std::uint64_t bind_time_ns, SelfCheck checked);
  // Edits model `id`'s binding: `change` gets a copy of the current one — the store's, read
  // under the model's StoreEditLock when another replica replaced it — (it may throw
  // ModelError to refuse, changing nothing); the result is stored durably, then swapped in and
  // returned. One edit at a time across every replica of the store, so concurrent edits of a
  // model are all kept; connections holding the old handle finish with it.
  // ModelError{UnknownModel / Internal: the store failed / change's}.
  ModelHandle replace(std::uint32_t id, const std::function<void(deform::BoundModel&)>& change);

  const std::filesystem::path& store_dir() const { return store_dir_; }

 private:
  // Why `name`/`content_id` cannot be held beside the held models; empty: it can. Caller
  // holds mutex_.
  std::string conflict(const std::string& name, const std::string& content_id) const;
  // ModelError{ModelLimit} when full, {ModelLoadFailed} "<what>: <conflict>" when `name` or
  // the handle is held by another model. Caller holds mutex_.
  void check_room(const std::string& name, const std::string& content_id,
                  const std::string& what) const;
  // Holds `model` in handle order, in place of one with its handle. Caller holds mutex_.
  void hold(ModelHandle model);
  // Reads <cid>.sweepbind and its label into a model (not yet held); throws what load throws.
  std::shared_ptr<RegisteredModel> read_stored(const std::string& content_id) const;
  // Holds `fresh` in place of `stale` unless another change replaced `stale` meanwhile (then
  // the held one, newer, stays and is returned).
  ModelHandle swap_in(const ModelHandle& stale, ModelHandle fresh);
  void migrate_numbered_store(RestoreReport& report);

  std::filesystem::path store_dir_;
  std::uint32_t max_models_;
  mutable std::mutex mutex_;
  std::mutex store_mutex_;   // held by the StoreSlot of the one load in progress, and by adopt
  std::mutex edit_mutex_;    // held by the one replace() in progress
  std::mutex reload_mutex_;  // held by the one current() loading a replaced binding
  std::vector<ModelHandle> models_;
};

}  // namespace sweepd::server

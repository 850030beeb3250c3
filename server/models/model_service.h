// ModelService: the one place sweepd's models change. It owns loading a model (an uploaded glTF,
// FBX or COLLADA file, or a glTF by name from the model directory), binding it, edits of a model's
// rest key ellipses, the default procedural mannequin, and the registry with its durable store
// (model_registry.h: the .sweepbind files and the index, restored at start). Connections and
// request handlers read models through it and ask it for every change; none of them touches the
// registry or a binding itself.
//
// restore(): the registry's restore() (model_registry.h: what it mends), logged: each removed
//   temporary file (store_temporary_removed), each entry not restored (restore_problem: file,
//   reason, quarantined_to when it was moved aside), a store migrated to content ids
//   (store_migrated), each restored model (model_restored) and its self-check's warnings
//   (bind_warning: stored with the binding, RegisteredModel::self_check).
//   add_default_model(): with no model_dir and no model named "mannequin", adopts the
//   procedural mannequin of config.mannequin_vertices from the store, or binds, checks and
//   stores it (model_loaded with bind_time_ns and self_check_time_ns).
// load(request): the model the request names, found before anything is bound:
//   - a content id: the held model, or the store's (adopted: another replica stored it);
//     UnknownModel when neither has it (the client uploads the bytes);
//   - bytes (an upload): named upload_name(request name) — a client's local path is cut to
//     its file's base name (issue 48: one name per model, on every client and after every
//     restart); their content id (content_id.h) held or in the store returns that
//     model — under its own name: names are labels, so an upload sent again after a reconnect
//     or to another replica costs no binding; else the bytes are kept as <cid>.glb (<cid>.fbx,
//     <cid>.dae: the format is read from the first bytes, io/assimp/assimp_load.h), loaded,
//     bound and stored;
//   - a name alone: the held model of that name, else the store's, else
//     `name`[.glb|.gltf] from config.model_dir, bound as an upload of its bytes would be.
//   Adopting holds the request's hold_adoption_memory; binding holds its hold_reading_memory
//   and hold_binding_memory, refuses more than config.max_model_vertices (MemoryLimit), maps
//   the rig
//   (detected, or the request's rig map JSON, kept as <cid>.rig.json); the model is returned
//   once durable. ModelLoadFailed names the model and the reason. A model adopted from the
//   store is logged (model_adopted).
// directory_entries(): model files in config.model_dir (file names) not loaded under that
//   name, sorted.
// edit_key_ellipse(model_id, edit): a copy of the model's binding with one rest key replaced
//   (deform::apply_rest_key_edit), stored durably, then swapped in (ModelRegistry::replace:
//   concurrent edits of a model are all kept, also across replicas sharing the store, which
//   see the edit from their next pose of the model: current()); connections holding the old
//   handle finish with it.
// Both throw ModelError: UnknownModel (no such id; its message names the models held,
// held_models_clause), InvalidArgument (an edit the binding refuses, with its reason), or the
// registry's codes. Thread-safe (the registry's lock);
// load and edit take milliseconds to seconds: call them on a worker.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "deform/edits/rest_key_edit.h"
#include "server/config.h"
#include "server/models/model_lookup.h"
#include "server/models/model_registry.h"

namespace sweepd::server {

// The name an upload is held under: `name` without a directory (anything up to its last '/'
// or '\\') and without a model file's extension (.glb, .gltf, .fbx, .dae, any case):
// "/home/me/scans/body.glb" -> "body", "body.v2" -> "body.v2".
std::string upload_name(std::string_view name);

struct ModelLoadRequest {
  std::string content_id;              // content_id.h, or empty
  std::string name;                    // stored name; with no gltf: a model_dir file name
  std::span<const std::uint8_t> gltf;  // uploaded .glb/.gltf/.fbx/.dae bytes, or empty
  std::string rig_map_json;            // io/json/rig_map_json.h override, or empty: detect
  int keys_per_link = 0;               // 0: the bind default
  int orientation = 0;                 // 0: linear Q(t), 1: smooth (BindOptions)
  // Working memory held for the load's stages once its store slot is claimed (loads that bind
  // do so one at a time): called with the model file's bytes before they are read, then with
  // the model read before it is bound; what each returns is kept until the model is stored.
  // Each throws ModelError naming what does not fit. Empty: nothing is held.
  std::function<std::shared_ptr<const void>(std::uint64_t file_bytes)> hold_reading_memory;
  std::function<std::shared_ptr<const void>(const deform::Model&)> hold_binding_memory;
  // Working memory held while a model of the store is adopted (ModelRegistry::adopt): called
  // with its .sweepbind's bytes before they are read; throws ModelError to refuse. Empty:
  // nothing is held.
  std::function<std::shared_ptr<const void>(std::uint64_t binding_bytes)> hold_adoption_memory;
};

class ModelService : public ModelLookup {
 public:
  explicit ModelService(const ServerConfig& config);

  void restore();
  void add_default_model();

  ModelHandle find(std::uint32_t id) const override { return registry_.find(id); }
  // `held` as the store now has it: its binding loaded again when another replica sharing the
  // store edited it (ModelRegistry::current: one stat(); a replaced file that does not load is
  // logged as store_binding_damaged and the held copy returned). Called by a pose's worker
  // before it deforms, so that a reload (0.4–0.6 s at 72k vertices) never stalls the I/O thread.
  ModelHandle current(const ModelHandle& held);
  std::vector<ModelHandle> models() const { return registry_.models(); }
  std::vector<ModelHandle> held_models() const override { return registry_.models(); }
  std::vector<std::string> directory_entries() const;
  // Bytes of the regular files in the store directory (models, sources, index; not the
  // quarantine): a listing, safe from any thread.
  std::uint64_t store_bytes() const;

  ModelHandle load(const ModelLoadRequest& request);
  ModelHandle edit_key_ellipse(std::uint32_t model_id, const deform::RestKeyEdit& edit);

 private:
  // The model directory's file for a client's name, or ModelError{UnknownModel}.
  std::filesystem::path model_file_in_directory(const std::string& name) const;
  // The model `content_id` held or adopted from the store (logged; holding the request's
  // hold_adoption_memory while it is read), or nullptr.
  ModelHandle held_or_stored(const std::string& content_id, const ModelLoadRequest& request);
  // Binds and stores request.gltf (an upload), or else directory_file, as request.name under
  // content_id; a model of that content id stored meanwhile by another load is returned.
  ModelHandle bind_and_store(const ModelLoadRequest& request, const std::string& content_id,
                             const std::filesystem::path& directory_file);

  const ServerConfig& config_;
  ModelRegistry registry_;
};

}  // namespace sweepd::server

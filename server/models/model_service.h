// ModelService: the one place sweepd's models change. It owns the model registry and its
// durable store (model_registry.h: loading a glTF, binding it, storing the .sweepbind and the
// index, restoring them at start), edits of a model's rest key ellipses, and the default
// procedural mannequin. Connections and request handlers read models through it and ask it for
// every change; none of them touches the registry or a binding itself.
//
// restore(): the registry's restore(), each entry that could not be restored logged
//   (restore_problem, then dropped), each restored model logged (model_restored).
//   add_default_model(): with no model_dir and no model
//   named "mannequin", binds config.mannequin_vertices of procedural mannequin and stores it.
// load(request): binds and stores a model (ModelRegistry::load), once durable.
// edit_key_ellipse(model_id, edit): a copy of the model's binding with one rest key replaced
//   (deform::apply_rest_key_edit), stored durably, then swapped in; connections holding the
//   old handle finish with it.
// Both throw ModelError: UnknownModel (no such id), InvalidArgument (an edit the binding
// refuses, with its reason), or the registry's codes. Thread-safe (the registry's lock);
// load and edit take milliseconds to seconds: call them on a worker.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "deform/edits/rest_key_edit.h"
#include "server/config.h"
#include "server/models/model_registry.h"

namespace sweepd::server {

class ModelService {
 public:
  explicit ModelService(const ServerConfig& config);

  void restore();
  void add_default_model();

  ModelHandle find(std::uint32_t id) const { return registry_.find(id); }
  std::vector<ModelHandle> models() const { return registry_.models(); }
  std::vector<std::string> directory_entries() const { return registry_.directory_entries(); }

  ModelHandle load(const ModelLoadRequest& request) { return registry_.load(request); }
  ModelHandle edit_key_ellipse(std::uint32_t model_id, const deform::RestKeyEdit& edit);

 private:
  const ServerConfig& config_;
  ModelRegistry registry_;
};

}  // namespace sweepd::server

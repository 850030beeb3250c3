#include "server/models/model_registry.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "io/files/durable_file.h"
#include "io/sweepbind/sweepbind.h"
#include "server/models/self_check_sidecar.h"
#include "server/models/store_edit_lock.h"
#include "server/models/store_quarantine.h"

namespace sweepd::server {
namespace {

using protocol::ErrorCode;
namespace fs = std::filesystem;

constexpr const char* kSourceSuffixes[] = {".glb",      ".fbx",  ".dae",
                                           ".rig.json", ".json", kSelfCheckSuffix};

std::span<const std::uint8_t> as_bytes(const std::string& text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A model's label: <cid>.json.
void write_label(const fs::path& file, const RegisteredModel& model) {
  const nlohmann::json label = {{"version", 2},
                                {"content_id", model.content_id},
                                {"name", model.name},
                                {"bind_time_ns", model.bind_time_ns}};
  io::write_file_durably(file, as_bytes(label.dump(2) + "\n"));
}

// The name and bind time <cid>.json gives; an absent or unreadable label gives none (the
// binding's own model name stands in).
struct Label {
  std::string name;
  std::uint64_t bind_time_ns = 0;
};
Label read_label(const fs::path& file) {
  try {
    const nlohmann::json label = nlohmann::json::parse(read_text(file));
    return {label.at("name").get<std::string>(), label.value("bind_time_ns", std::uint64_t{0})};
  } catch (const std::exception&) {
    return {};
  }
}

// The content ids of the store's bindings, sorted.
std::vector<std::string> stored_content_ids(const fs::path& store_dir) {
  std::vector<std::string> ids;
  for (const fs::directory_entry& file : fs::directory_iterator(store_dir)) {
    const std::string stem = file.path().stem().string();
    if (file.path().extension() == ".sweepbind" && is_content_id(stem) && file.is_regular_file())
      ids.push_back(stem);
  }
  std::sort(ids.begin(), ids.end());
  return ids;
}

// Moves what a damaged model leaves to the quarantine: its binding and its sources, which no
// binding of this content id will read again.
fs::path quarantine_model(const fs::path& store_dir, const std::string& stem) {
  const fs::path moved = quarantine(store_dir / (stem + ".sweepbind"), store_dir);
  for (const char* suffix : kSourceSuffixes) {
    const fs::path source = store_dir / (stem + suffix);
    std::error_code error;
    if (fs::exists(source, error)) quarantine(source, store_dir);
  }
  return moved;
}

// Writes `bound` durably as `file`; the checksum its sidecar is keyed by.
io::SweepbindChecksum store_binding(const deform::BoundModel& bound, const fs::path& file) {
  const std::vector<std::uint8_t> bytes = io::encode_sweepbind(bound);
  io::write_file_durably(file, bytes);
  return io::sweepbind_checksum(bytes);
}

// Stores a binding's self-check beside it. A cache of the binding, so a store that does not take
// it (read-only, full) fails nothing: the binding is stored, and the next restore checks it
// again.
void keep_self_check(const fs::path& sidecar, const SelfCheck& checked,
                     const io::SweepbindChecksum& binding) {
  try {
    save_self_check(sidecar, checked, binding);
  } catch (const std::exception&) {
    // Not kept: see above.
  }
}

}  // namespace

fs::path ModelRegistry::StoreSlot::file(std::string_view suffix) const {
  return store_dir_ / (content_id_ + std::string(suffix));
}

ModelRegistry::ModelRegistry(fs::path store_dir, std::uint32_t max_models)
    : store_dir_(std::move(store_dir)), max_models_(max_models) {
  fs::create_directories(store_dir_);
}

std::shared_ptr<RegisteredModel> ModelRegistry::read_stored(const std::string& content_id) const {
  auto model = std::make_shared<RegisteredModel>();
  model->content_id = content_id;
  model->id = handle_of(content_id);
  const fs::path file = store_dir_ / (content_id + ".sweepbind");
  model->file = BindingFile::open(file);
  const std::vector<std::uint8_t> bytes = model->file->bytes();
  model->bound = io::decode_sweepbind(bytes, file);
  const Label label = read_label(store_dir_ / (content_id + ".json"));
  model->name = label.name.empty() ? model->bound.model.name : label.name;
  if (model->name.empty()) model->name = "model-" + content_id.substr(0, 8);
  model->bind_time_ns = label.bind_time_ns;
  model->runtime = std::make_shared<const deform::ModelRuntime>(model->bound);
  const io::SweepbindChecksum checksum = io::sweepbind_checksum(bytes);
  const fs::path sidecar = store_dir_ / (content_id + kSelfCheckSuffix);
  if (std::optional<SelfCheck> stored = load_self_check(sidecar, checksum)) {
    model->self_check = std::move(*stored);
  } else {
    // A store written before the sidecars, or a binding whose sidecar is stale: checked once
    // more, and kept for the next restore.
    model->self_check = self_check(model->bound);
    keep_self_check(sidecar, model->self_check, checksum);
  }
  return model;
}

// A store of the first layout: index.json naming <n>.sweepbind (n a per-server number). Each
// model moves to its content id — the SHA-256 of its .sweepbind's bytes, since what it was
// bound from is not always kept — with its sources and name; index.json goes last.
void ModelRegistry::migrate_numbered_store(RestoreReport& report) {
  const fs::path index_file = store_dir_ / "index.json";
  std::map<std::string, std::string> names;  // "<n>" -> name, from the index when it reads
  try {
    const nlohmann::json index = nlohmann::json::parse(read_text(index_file));
    for (const nlohmann::json& entry : index.at("models"))
      names[std::to_string(entry.at("id").get<std::uint32_t>())] = entry.at("name");
  } catch (const std::exception& error) {
    report.problems.push_back({index_file, std::string("unreadable index: ") + error.what(),
                               quarantine(index_file, store_dir_)});
  }
  for (const fs::directory_entry& file : fs::directory_iterator(store_dir_)) {
    const std::string stem = file.path().stem().string();
    const bool numbered =
        !stem.empty() && stem.size() <= 9 &&
        std::all_of(stem.begin(), stem.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!numbered || file.path().extension() != ".sweepbind") continue;
    const std::string bytes = read_text(file.path());
    const std::string content_id = described_content_id("sweepbind " + bytes);
    for (const char* suffix : {".glb", ".rig.json"}) {
      const fs::path source = store_dir_ / (stem + suffix);
      if (fs::exists(source)) fs::rename(source, store_dir_ / (content_id + suffix));
    }
    if (names.contains(stem)) {
      RegisteredModel label;
      label.content_id = content_id;
      label.name = names[stem];
      write_label(store_dir_ / (content_id + ".json"), label);
    }
    fs::rename(file.path(), store_dir_ / (content_id + ".sweepbind"));
    ++report.migrated;
  }
  if (fs::exists(index_file)) fs::remove(index_file);
  io::sync_directory(store_dir_);
}

RestoreReport ModelRegistry::restore() {
  RestoreReport report;
  report.removed_temporaries = remove_temporary_files(store_dir_);
  if (fs::exists(store_dir_ / "index.json")) migrate_numbered_store(report);
  for (const std::string& content_id : stored_content_ids(store_dir_)) {
    const fs::path file = store_dir_ / (content_id + ".sweepbind");
    std::shared_ptr<RegisteredModel> model;
    try {
      model = read_stored(content_id);
    } catch (const std::exception& error) {
      report.problems.push_back({file, error.what(), quarantine_model(store_dir_, content_id)});
      continue;
    }
    std::lock_guard lock(mutex_);
    if (const std::string why = conflict(model->name, content_id); !why.empty()) {
      report.problems.push_back({file, "not loaded: " + why, {}});
      continue;
    }
    hold(std::move(model));
  }
  return report;
}

ModelHandle ModelRegistry::find(std::uint32_t id) const {
  std::lock_guard lock(mutex_);
  for (const ModelHandle& model : models_) {
    if (model->id == id) return model;
  }
  return nullptr;
}

ModelHandle ModelRegistry::current(std::uint32_t id, std::optional<StoreProblem>* problem) {
  const auto replaced = [](const ModelHandle& model) {
    return model && model->file && model->file->replaced();
  };
  ModelHandle held = find(id);
  if (!replaced(held)) return held;
  // One reload at a time: requests that see the same change wait for it, then find it held.
  std::lock_guard reload_lock(reload_mutex_);
  held = find(id);
  if (!replaced(held)) return held;
  std::shared_ptr<RegisteredModel> fresh;
  try {
    fresh = read_stored(held->content_id);
  } catch (const std::exception& error) {
    // Renames make every version whole, so this file was damaged in the store: set aside as
    // adopt() does, and the copy held serves on.
    StoreProblem found{
        held->file->path(),
        "the binding another replica stored does not load: " + std::string(error.what()),
        {}};
    try {
      found.quarantined_to = quarantine_model(store_dir_, held->content_id);
    } catch (const std::exception&) {
      // Moved already (another replica quarantined it) or not movable: the next stat decides.
    }
    if (problem != nullptr) *problem = std::move(found);
    return held;
  }
  return swap_in(held, std::move(fresh));
}

ModelHandle ModelRegistry::swap_in(const ModelHandle& stale, ModelHandle fresh) {
  std::lock_guard lock(mutex_);
  const auto held = std::find_if(models_.begin(), models_.end(),
                                 [&](const ModelHandle& m) { return m->id == stale->id; });
  if (held == models_.end() || *held != stale) return held == models_.end() ? stale : *held;
  *held = fresh;
  return fresh;
}

ModelHandle ModelRegistry::find(std::string_view name) const {
  std::lock_guard lock(mutex_);
  for (const ModelHandle& model : models_) {
    if (model->name == name) return model;
  }
  return nullptr;
}

ModelHandle ModelRegistry::find_content(std::string_view content_id) const {
  std::lock_guard lock(mutex_);
  for (const ModelHandle& model : models_) {
    if (model->content_id == content_id) return model;
  }
  return nullptr;
}

std::vector<ModelHandle> ModelRegistry::models() const {
  std::lock_guard lock(mutex_);
  return models_;
}

std::string ModelRegistry::conflict(const std::string& name, const std::string& content_id) const {
  const std::uint32_t handle = handle_of(content_id);
  for (const ModelHandle& model : models_) {
    if (model->content_id == content_id) continue;  // the same model: held, not a conflict
    if (model->name == name) {
      return "a model named '" + name + "' is loaded (content id " + model->content_id +
             "): another model needs another name";
    }
    if (model->id == handle) {
      return "its handle " + std::to_string(handle) + " is held by model '" + model->name +
             "' (content id " + model->content_id + "; two content ids whose first 8 hex " +
             "digits agree)";
    }
  }
  return {};
}

void ModelRegistry::check_room(const std::string& name, const std::string& content_id,
                               const std::string& what) const {
  if (models_.size() >= max_models_) {
    throw ModelError(ErrorCode::ModelLimit, "model '" + name +
                                                "': the server already holds its limit of " +
                                                std::to_string(max_models_) + " models");
  }
  if (const std::string why = conflict(name, content_id); !why.empty())
    throw ModelError(ErrorCode::ModelLoadFailed, what + ": " + why);
}

void ModelRegistry::hold(ModelHandle model) {
  std::erase_if(models_, [&](const ModelHandle& held) { return held->id == model->id; });
  const auto by_handle = [](const ModelHandle& a, const ModelHandle& b) { return a->id < b->id; };
  models_.insert(std::upper_bound(models_.begin(), models_.end(), model, by_handle),
                 std::move(model));
}

std::string ModelRegistry::stored_content_named(std::string_view name) const {
  for (const std::string& content_id : stored_content_ids(store_dir_)) {
    if (read_label(store_dir_ / (content_id + ".json")).name == name) return content_id;
  }
  return {};
}

ModelHandle ModelRegistry::adopt(
    const std::string& content_id,
    const std::function<std::shared_ptr<const void>(std::uint64_t binding_bytes)>&
        hold_reading_memory) {
  if (ModelHandle held = find_content(content_id)) return held;
  std::lock_guard store_lock(store_mutex_);
  if (ModelHandle held = find_content(content_id)) return held;  // adopted while we waited
  if (!is_content_id(content_id)) return nullptr;
  std::error_code missing;
  const std::uintmax_t binding_bytes =
      fs::file_size(store_dir_ / (content_id + ".sweepbind"), missing);
  if (missing) return nullptr;
  const std::shared_ptr<const void> reading_memory =
      hold_reading_memory ? hold_reading_memory(binding_bytes) : nullptr;
  std::shared_ptr<RegisteredModel> model;
  try {
    model = read_stored(content_id);
  } catch (const std::exception& error) {
    quarantine_model(store_dir_, content_id);
    throw ModelError(ErrorCode::ModelLoadFailed,
                     "stored model " + content_id +
                         " is damaged and was quarantined: " + std::string(error.what()));
  }
  std::lock_guard lock(mutex_);
  check_room(model->name, content_id, "stored model " + content_id);
  hold(model);
  return model;
}

ModelRegistry::StoreSlot ModelRegistry::claim(const std::string& name,
                                              const std::string& content_id) {
  std::unique_lock store_lock(store_mutex_);
  std::lock_guard lock(mutex_);
  check_room(name, content_id, "model '" + name + "'");
  return StoreSlot(std::move(store_lock), store_dir_, content_id);
}

ModelHandle ModelRegistry::add(StoreSlot slot, const std::string& name, deform::BoundModel bound,
                               std::uint64_t bind_time_ns, SelfCheck checked) {
  auto model = std::make_shared<RegisteredModel>();
  model->content_id = slot.content_id();
  model->id = slot.id();
  model->name = name;
  model->bound = std::move(bound);
  model->bind_time_ns = bind_time_ns;
  // The runtime (poser tables, collision regions, proxies) is built before taking the lock, so
  // lookups do not wait for it.
  model->runtime = std::make_shared<const deform::ModelRuntime>(model->bound);
  model->self_check = std::move(checked);
  // The files are durable before the model is visible, and written outside the lookups'
  // lock: no client sees a model that a crash could take back, and lookups do not wait for an
  // fsync. The label goes first: the .sweepbind is what puts the model in the store; its
  // self-check's sidecar, keyed by it, last (a cache: not kept, it fails nothing).
  try {
    write_label(slot.file(".json"), *model);
    const io::SweepbindChecksum checksum = store_binding(model->bound, slot.file(".sweepbind"));
    model->file = BindingFile::open(slot.file(".sweepbind"));
    keep_self_check(slot.file(kSelfCheckSuffix), model->self_check, checksum);
  } catch (const std::exception& error) {
    throw ModelError(ErrorCode::Internal,
                     "model '" + name + "' could not be stored: " + std::string(error.what()));
  }
  std::lock_guard lock(mutex_);
  // The slot kept every other add out, so the claim's room, name and handle still hold.
  hold(model);
  return model;
}

ModelHandle ModelRegistry::replace(std::uint32_t id,
                                   const std::function<void(deform::BoundModel&)>& change) {
  // Held from reading the current binding to swapping in the edited one: a concurrent edit
  // starts from this one's result instead of overwriting it — edit_mutex_ on this replica, the
  // store's lock file on every replica sharing the store.
  std::lock_guard edit_lock(edit_mutex_);
  const ModelHandle held = find(id);
  if (!held) throw ModelError(ErrorCode::UnknownModel, "no model with id " + std::to_string(id));
  const fs::path file = store_dir_ / (held->content_id + ".sweepbind");
  std::shared_ptr<RegisteredModel> model;
  try {
    StoreEditLock store_lock(store_dir_ / (held->content_id + ".lock"));
    // Another replica's edit since this one loaded the model is where this edit starts.
    model = held->file && held->file->replaced() ? read_stored(held->content_id)
                                                 : std::make_shared<RegisteredModel>(*held);
    change(model->bound);
    model->runtime = std::make_shared<const deform::ModelRuntime>(model->bound);
    model->self_check = self_check(model->bound);  // an edited key changes what the sweep does
    // Stored before it is swapped in, and outside the lookups' lock: poses do not wait for
    // fsync. Opened again under the lock, so the version held is this edit's.
    const io::SweepbindChecksum checksum = store_binding(model->bound, file);
    model->file = BindingFile::open(file);
    keep_self_check(store_dir_ / (held->content_id + kSelfCheckSuffix), model->self_check,
                    checksum);
  } catch (const ModelError&) {
    throw;
  } catch (const std::exception& error) {
    throw ModelError(ErrorCode::Internal, "model '" + held->name + "' could not be stored: " +
                                              std::string(error.what()));
  }
  // Unconditionally: a reload by current() that finished meanwhile holds an older version.
  std::lock_guard lock(mutex_);
  hold(model);
  return model;
}

}  // namespace sweepd::server

#include "server/models/model_registry.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/durable_file.h"
#include "io/sweepbind.h"
#include "server/models/store_quarantine.h"

namespace sweepd::server {
namespace {

using protocol::ErrorCode;
namespace fs = std::filesystem;

std::span<const std::uint8_t> as_bytes(const std::string& text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

std::string sweepbind_name(std::uint32_t id) { return std::to_string(id) + ".sweepbind"; }

// Rewrites index.json durably: `models` by id, and the next id to give.
void write_index(const fs::path& store_dir, std::span<const ModelHandle> models,
                 std::uint32_t next_id) {
  nlohmann::json entries = nlohmann::json::array();
  for (const ModelHandle& model : models) {
    entries.push_back({{"id", model->id},
                       {"name", model->name},
                       {"file", sweepbind_name(model->id)},
                       {"bind_time_ns", model->bind_time_ns}});
  }
  const nlohmann::json index = {{"version", 1}, {"next_id", next_id}, {"models", entries}};
  io::write_file_durably(store_dir / "index.json", as_bytes(index.dump(2) + "\n"));
}

// A model the store holds: from index.json, or from its file when the index is rebuilt.
struct IndexEntry {
  std::uint32_t id = 0;
  std::string name;  // empty: the name the .sweepbind holds
  std::uint64_t bind_time_ns = 0;
};

// index.json's entries, and its next_id raised into next_id; throws when anything in it is
// malformed (it is written whole, so damage anywhere means it cannot be trusted).
std::vector<IndexEntry> read_index(const fs::path& index_file, std::uint32_t& next_id) {
  std::ifstream in(index_file);
  const nlohmann::json index = nlohmann::json::parse(in);
  next_id = std::max(next_id, index.at("next_id").get<std::uint32_t>());
  std::vector<IndexEntry> entries;
  for (const nlohmann::json& entry : index.at("models")) {
    entries.push_back({entry.at("id").get<std::uint32_t>(), entry.at("name").get<std::string>(),
                       entry.value("bind_time_ns", std::uint64_t{0})});
  }
  return entries;
}

// Every <id>.sweepbind in the store, by id.
std::vector<IndexEntry> entries_from_files(const fs::path& store_dir) {
  std::vector<IndexEntry> entries;
  for (const fs::directory_entry& file : fs::directory_iterator(store_dir)) {
    const std::string stem = file.path().stem().string();
    const bool numbered =
        !stem.empty() && stem.size() <= 9 &&
        std::all_of(stem.begin(), stem.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (file.is_regular_file() && file.path().extension() == ".sweepbind" && numbered) {
      entries.push_back({static_cast<std::uint32_t>(std::stoul(stem)), "", 0});
    }
  }
  std::sort(entries.begin(), entries.end(),
            [](const IndexEntry& a, const IndexEntry& b) { return a.id < b.id; });
  return entries;
}

}  // namespace

fs::path ModelRegistry::StoreSlot::file(std::string_view suffix) const {
  return store_dir_ / (std::to_string(id_) + std::string(suffix));
}

ModelRegistry::ModelRegistry(fs::path store_dir, std::uint32_t max_models)
    : store_dir_(std::move(store_dir)), max_models_(max_models) {
  fs::create_directories(store_dir_);
}

RestoreReport ModelRegistry::restore() {
  RestoreReport report;
  report.removed_temporaries = remove_temporary_files(store_dir_);
  const fs::path index_file = store_dir_ / "index.json";
  std::vector<IndexEntry> entries;
  if (fs::exists(index_file)) {
    try {
      entries = read_index(index_file, next_id_);
    } catch (const std::exception& error) {
      report.problems.push_back({index_file, std::string("unreadable index: ") + error.what(),
                                 quarantine(index_file, store_dir_)});
      report.index_rebuilt = true;
    }
  } else {
    report.index_rebuilt = true;  // a store holding .sweepbind files but never an index
  }
  if (report.index_rebuilt) {
    entries = entries_from_files(store_dir_);
    report.index_rebuilt = !entries.empty() || !report.problems.empty();
  }
  std::lock_guard lock(mutex_);
  for (const IndexEntry& entry : entries) {
    const fs::path file = store_dir_ / sweepbind_name(entry.id);
    next_id_ = std::max(next_id_, entry.id + 1);  // ids are never reused, a dropped one included
    if (std::any_of(models_.begin(), models_.end(),
                    [&](const ModelHandle& m) { return m->id == entry.id; })) {
      report.problems.push_back({file, "listed twice in index.json", {}});
      continue;
    }
    if (!fs::exists(file)) {
      report.problems.push_back({file, "missing (listed in index.json)", {}});
      continue;
    }
    try {
      auto model = std::make_shared<RegisteredModel>();
      model->id = entry.id;
      model->bound = io::load_sweepbind(file);
      model->name = entry.name.empty() ? model->bound.model.name : entry.name;
      if (model->name.empty()) model->name = "model-" + std::to_string(entry.id);
      for (const ModelHandle& other : models_) {
        if (other->name == model->name) {
          throw std::runtime_error("a model named '" + model->name + "' is restored (id " +
                                   std::to_string(other->id) + ")");
        }
      }
      model->runtime = std::make_shared<const deform::ModelRuntime>(model->bound);
      models_.push_back(std::move(model));
    } catch (const std::exception& error) {
      report.problems.push_back({file, error.what(), quarantine(file, store_dir_)});
      // Its sources go with it: the id is not used again, so nothing else would read them.
      for (const char* suffix : {".glb", ".rig.json"}) {
        const fs::path source = store_dir_ / (std::to_string(entry.id) + suffix);
        if (fs::exists(source)) quarantine(source, store_dir_);
      }
    }
  }
  std::sort(models_.begin(), models_.end(),
            [](const ModelHandle& a, const ModelHandle& b) { return a.get()->id < b.get()->id; });
  if (!report.problems.empty() || report.index_rebuilt) write_index(store_dir_, models_, next_id_);
  return report;
}

ModelHandle ModelRegistry::find(std::uint32_t id) const {
  std::lock_guard lock(mutex_);
  for (const ModelHandle& model : models_) {
    if (model->id == id) return model;
  }
  return nullptr;
}

ModelHandle ModelRegistry::find(std::string_view name) const {
  std::lock_guard lock(mutex_);
  for (const ModelHandle& model : models_) {
    if (model->name == name) return model;
  }
  return nullptr;
}

std::vector<ModelHandle> ModelRegistry::models() const {
  std::lock_guard lock(mutex_);
  return models_;
}

void ModelRegistry::check_room(const std::string& name) const {
  if (models_.size() >= max_models_) {
    throw ModelError(ErrorCode::ModelLimit, "model '" + name +
                                                "': the server already holds its limit of " +
                                                std::to_string(max_models_) + " models");
  }
  for (const ModelHandle& model : models_) {
    if (model->name == name) {
      throw ModelError(ErrorCode::ModelLoadFailed, "model '" + name +
                                                       "': a model of that name is loaded (id " +
                                                       std::to_string(model->id) + ")");
    }
  }
}

ModelRegistry::StoreSlot ModelRegistry::claim(const std::string& name) {
  std::unique_lock store_lock(store_mutex_);
  std::lock_guard lock(mutex_);
  check_room(name);
  return StoreSlot(std::move(store_lock), store_dir_, next_id_);
}

ModelHandle ModelRegistry::add(StoreSlot slot, const std::string& name, deform::BoundModel bound,
                               std::uint64_t bind_time_ns) {
  auto model = std::make_shared<RegisteredModel>();
  model->id = slot.id();
  model->name = name;
  model->bound = std::move(bound);
  model->bind_time_ns = bind_time_ns;
  // The runtime (poser tables, collision regions, proxies) is built before taking the lock, so
  // lookups do not wait for it.
  model->runtime = std::make_shared<const deform::ModelRuntime>(model->bound);
  // Both files are durable before the model is visible, and written outside the lookups'
  // lock: no client sees a model that a crash could take back, and lookups do not wait for an
  // fsync. The slot keeps every other add out, so models() is the index's list (an edit
  // changes no entry).
  std::vector<ModelHandle> listed = models();
  listed.push_back(model);
  try {
    io::save_sweepbind(model->bound, slot.file(".sweepbind"));
    write_index(store_dir_, listed, model->id + 1);
  } catch (const std::exception& error) {
    throw ModelError(ErrorCode::Internal,
                     "model '" + name + "' could not be stored: " + std::string(error.what()));
  }
  std::lock_guard lock(mutex_);
  // The slot kept every other add out, so the claim's room and name still hold.
  next_id_ = model->id + 1;
  models_.push_back(model);
  return model;
}

ModelHandle ModelRegistry::replace(std::uint32_t id,
                                   const std::function<void(deform::BoundModel&)>& change) {
  // Held from reading the current binding to swapping in the edited one: a concurrent edit
  // starts from this one's result instead of overwriting it.
  std::lock_guard edit_lock(edit_mutex_);
  const ModelHandle old = find(id);
  if (!old) throw ModelError(ErrorCode::UnknownModel, "no model with id " + std::to_string(id));
  auto model = std::make_shared<RegisteredModel>();
  model->id = old->id;
  model->name = old->name;
  model->bind_time_ns = old->bind_time_ns;
  model->bound = old->bound;
  change(model->bound);
  model->runtime = std::make_shared<const deform::ModelRuntime>(model->bound);
  // Stored before it is swapped in, and outside the lookups' lock: poses do not wait for fsync.
  try {
    io::save_sweepbind(model->bound, store_dir_ / sweepbind_name(id));
  } catch (const std::exception& error) {
    throw ModelError(ErrorCode::Internal, "model '" + model->name + "' could not be stored: " +
                                              std::string(error.what()));
  }
  std::lock_guard lock(mutex_);
  *std::find_if(models_.begin(), models_.end(),
                [id](const ModelHandle& m) { return m->id == id; }) = model;
  return model;
}

}  // namespace sweepd::server

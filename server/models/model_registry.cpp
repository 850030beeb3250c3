#include "server/models/model_registry.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "io/durable_file.h"
#include "io/gltf_load.h"
#include "io/load_error.h"
#include "io/rig_map_json.h"
#include "io/sweepbind.h"

namespace sweepd::server {
namespace {

using protocol::ErrorCode;
namespace fs = std::filesystem;

constexpr std::size_t kMaxNameBytes = 200;

bool is_model_file(const fs::path& file) {
  const std::string extension = file.extension().string();
  return extension == ".glb" || extension == ".gltf";
}

void write_bytes(const fs::path& file, std::span<const std::uint8_t> bytes) {
  io::write_file_durably(file, bytes);
}

std::span<const std::uint8_t> as_bytes(const std::string& text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

}  // namespace

ModelRegistry::ModelRegistry(fs::path store_dir, fs::path model_dir, ModelRegistryLimits limits)
    : store_dir_(std::move(store_dir)), model_dir_(std::move(model_dir)), limits_(limits) {
  fs::create_directories(store_dir_);
}

std::vector<std::string> ModelRegistry::restore() {
  std::vector<std::string> problems;
  const fs::path index_file = store_dir_ / "index.json";
  if (!fs::exists(index_file)) return problems;
  nlohmann::json index;
  try {
    std::ifstream in(index_file);
    index = nlohmann::json::parse(in);
    next_id_ = index.at("next_id").get<std::uint32_t>();
  } catch (const std::exception& error) {
    problems.push_back(index_file.string() + ": unreadable index (" + error.what() + ")");
    return problems;
  }
  std::lock_guard lock(mutex_);
  for (const nlohmann::json& entry : index.value("models", nlohmann::json::array())) {
    try {
      auto model = std::make_shared<RegisteredModel>();
      model->id = entry.at("id").get<std::uint32_t>();
      model->name = entry.at("name").get<std::string>();
      model->bound = io::load_sweepbind(store_dir_ / entry.at("file").get<std::string>());
      model->runtime = std::make_shared<const deform::ModelRuntime>(model->bound);
      next_id_ = std::max(next_id_, model->id + 1);
      models_.push_back(std::move(model));
    } catch (const std::exception& error) {
      problems.push_back(index_file.string() + ": entry " + entry.dump() + " not restored (" +
                         error.what() + ")");
    }
  }
  std::sort(models_.begin(), models_.end(),
            [](const ModelHandle& a, const ModelHandle& b) { return a.get()->id < b.get()->id; });
  if (!problems.empty()) write_index();
  return problems;
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

std::vector<std::string> ModelRegistry::directory_entries() const {
  std::vector<std::string> names;
  std::error_code error;
  if (model_dir_.empty() || !fs::is_directory(model_dir_, error)) return names;
  for (const fs::directory_entry& entry : fs::directory_iterator(model_dir_, error)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file(error) && is_model_file(entry.path()) && !find(name)) {
      names.push_back(name);
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

fs::path ModelRegistry::model_file_in_directory(const std::string& name) const {
  if (model_dir_.empty()) {
    throw ModelError(ErrorCode::UnknownModel,
                     "model '" + name + "': this server has no model directory; upload the glTF");
  }
  if (name.empty() || name.find('/') != std::string::npos || name.starts_with(".")) {
    throw ModelError(ErrorCode::UnknownModel,
                     "model '" + name + "': not a file name in the model directory");
  }
  for (const std::string suffix : {"", ".glb", ".gltf"}) {
    const fs::path file = model_dir_ / (name + suffix);
    std::error_code error;
    if (is_model_file(file) && fs::is_regular_file(file, error)) return file;
  }
  throw ModelError(ErrorCode::UnknownModel,
                   "model '" + name + "': no such .glb/.gltf in " + model_dir_.string());
}

void ModelRegistry::check_room(const std::string& name) const {
  if (models_.size() >= limits_.max_models) {
    throw ModelError(ErrorCode::ModelLimit, "model '" + name +
                                                "': the server already holds its limit of " +
                                                std::to_string(limits_.max_models) + " models");
  }
  for (const ModelHandle& model : models_) {
    if (model->name == name) {
      throw ModelError(ErrorCode::ModelLoadFailed, "model '" + name +
                                                       "': a model of that name is loaded (id " +
                                                       std::to_string(model->id) + ")");
    }
  }
}

void ModelRegistry::write_index() const {
  nlohmann::json entries = nlohmann::json::array();
  for (const ModelHandle& model : models_) {
    entries.push_back({{"id", model->id},
                       {"name", model->name},
                       {"file", std::to_string(model->id) + ".sweepbind"},
                       {"bind_time_ns", model->bind_time_ns}});
  }
  const nlohmann::json index = {{"version", 1}, {"next_id", next_id_}, {"models", entries}};
  write_bytes(store_dir_ / "index.json", as_bytes(index.dump(2) + "\n"));
}

ModelHandle ModelRegistry::load(const ModelLoadRequest& request) {
  if (request.name.empty() || request.name.size() > kMaxNameBytes) {
    throw ModelError(ErrorCode::ModelLoadFailed,
                     "a model name must have 1 to " + std::to_string(kMaxNameBytes) + " bytes");
  }
  if (request.gltf.empty()) {
    if (ModelHandle loaded = find(request.name)) return loaded;
  }
  std::lock_guard store_lock(store_mutex_);
  std::uint32_t id = 0;
  {
    std::lock_guard lock(mutex_);
    check_room(request.name);
    id = next_id_;
  }
  const auto started = std::chrono::steady_clock::now();
  deform::BoundModel bound;
  try {
    fs::path source;
    io::GltfUriPolicy uris;
    if (request.gltf.empty()) {
      source = model_file_in_directory(request.name);
      uris = io::GltfUriPolicy::within(model_dir_);
    } else {
      source = store_dir_ / (std::to_string(id) + ".glb");
      write_bytes(source, request.gltf);
      uris = io::GltfUriPolicy::self_contained();  // an upload reads nothing but itself
    }
    deform::Model model = io::load_gltf(source, uris);
    if (model.vertex_count() > limits_.max_model_vertices) {
      throw ModelError(ErrorCode::MemoryLimit, "model '" + request.name + "' has " +
                                                   std::to_string(model.vertex_count()) +
                                                   " vertices; this server takes at most " +
                                                   std::to_string(limits_.max_model_vertices));
    }
    deform::RigMap rig;
    if (request.rig_map_json.empty()) {
      rig = deform::detect_rig_map(model.skeleton);
    } else {
      const fs::path rig_file = store_dir_ / (std::to_string(id) + ".rig.json");
      write_bytes(rig_file, as_bytes(request.rig_map_json));
      rig = io::load_rig_map_json(rig_file, model.skeleton);
    }
    deform::BindOptions options;
    if (request.keys_per_link > 0) options.intermediate_keys_per_link = request.keys_per_link;
    model.name = request.name;
    bound = deform::bind(model, rig, options);
  } catch (const ModelError&) {
    throw;
  } catch (const io::LoadError& error) {
    // An uploaded file's place in the store is the server's business: the reason alone.
    const bool uploaded = error.file().parent_path() == store_dir_;
    throw ModelError(ErrorCode::ModelLoadFailed,
                     "model '" + request.name + "' could not be loaded: " +
                         (uploaded ? "the uploaded file: " + error.reason() : error.what()));
  } catch (const std::exception& error) {
    throw ModelError(ErrorCode::ModelLoadFailed,
                     "model '" + request.name + "' could not be loaded: " + error.what());
  }
  const auto bind_time = std::chrono::duration_cast<std::chrono::nanoseconds>(
      std::chrono::steady_clock::now() - started);
  return add(request.name, std::move(bound), static_cast<std::uint64_t>(bind_time.count()));
}

ModelHandle ModelRegistry::add(const std::string& name, deform::BoundModel bound,
                               std::uint64_t bind_time_ns) {
  auto model = std::make_shared<RegisteredModel>();
  model->name = name;
  model->bound = std::move(bound);
  model->bind_time_ns = bind_time_ns;
  model->runtime = std::make_shared<const deform::ModelRuntime>(model->bound);
  std::lock_guard lock(mutex_);
  check_room(name);
  model->id = next_id_;
  try {
    io::save_sweepbind(model->bound, store_dir_ / (std::to_string(model->id) + ".sweepbind"));
    ++next_id_;
    models_.push_back(model);
    write_index();
  } catch (const std::exception& error) {
    std::erase(models_, model);
    throw ModelError(ErrorCode::Internal,
                     "model '" + name + "' could not be stored: " + std::string(error.what()));
  }
  return model;
}

ModelHandle ModelRegistry::replace(std::uint32_t id, deform::BoundModel bound) {
  // The runtime (poser tables, collision regions, proxies) is built before taking the lock, so
  // lookups do not wait for it.
  auto model = std::make_shared<RegisteredModel>();
  model->bound = std::move(bound);
  model->runtime = std::make_shared<const deform::ModelRuntime>(model->bound);
  std::lock_guard lock(mutex_);
  const auto old = std::find_if(models_.begin(), models_.end(),
                                [id](const ModelHandle& m) { return m->id == id; });
  if (old == models_.end())
    throw ModelError(ErrorCode::UnknownModel, "no model with id " + std::to_string(id));
  model->id = (*old)->id;
  model->name = (*old)->name;
  model->bind_time_ns = (*old)->bind_time_ns;
  try {
    io::save_sweepbind(model->bound, store_dir_ / (std::to_string(id) + ".sweepbind"));
  } catch (const std::exception& error) {
    throw ModelError(ErrorCode::Internal, "model '" + model->name + "' could not be stored: " +
                                              std::string(error.what()));
  }
  *old = model;
  return model;
}

}  // namespace sweepd::server

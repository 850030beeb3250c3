#include "server/models/model_registry.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/durable_file.h"
#include "io/sweepbind.h"

namespace sweepd::server {
namespace {

using protocol::ErrorCode;
namespace fs = std::filesystem;

std::span<const std::uint8_t> as_bytes(const std::string& text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

}  // namespace

fs::path ModelRegistry::StoreSlot::file(std::string_view suffix) const {
  return store_dir_ / (std::to_string(id_) + std::string(suffix));
}

ModelRegistry::ModelRegistry(fs::path store_dir, std::uint32_t max_models)
    : store_dir_(std::move(store_dir)), max_models_(max_models) {
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

void ModelRegistry::write_index() const {
  nlohmann::json entries = nlohmann::json::array();
  for (const ModelHandle& model : models_) {
    entries.push_back({{"id", model->id},
                       {"name", model->name},
                       {"file", std::to_string(model->id) + ".sweepbind"},
                       {"bind_time_ns", model->bind_time_ns}});
  }
  const nlohmann::json index = {{"version", 1}, {"next_id", next_id_}, {"models", entries}};
  io::write_file_durably(store_dir_ / "index.json", as_bytes(index.dump(2) + "\n"));
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
  try {
    io::save_sweepbind(model->bound, slot.file(".sweepbind"));
  } catch (const std::exception& error) {
    throw ModelError(ErrorCode::Internal,
                     "model '" + name + "' could not be stored: " + std::string(error.what()));
  }
  std::lock_guard lock(mutex_);
  // The slot kept every other add out, so the claim's room and name still hold.
  next_id_ = model->id + 1;
  models_.push_back(model);
  try {
    write_index();
  } catch (const std::exception& error) {
    models_.pop_back();
    throw ModelError(ErrorCode::Internal,
                     "model '" + name + "' could not be stored: " + std::string(error.what()));
  }
  return model;
}

ModelHandle ModelRegistry::replace(std::uint32_t id, deform::BoundModel bound) {
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

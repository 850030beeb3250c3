#include "server/models/model_service.h"

#include <algorithm>
#include <chrono>
#include <fstream>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "io/assimp/assimp_load.h"
#include "io/files/durable_file.h"
#include "io/gltf/gltf_load.h"
#include "io/json/rig_map_json.h"
#include "mannequin/mannequin.h"
#include "selfcheck/binding_self_check.h"
#include "server/elapsed_time.h"
#include "server/log_event.h"

namespace sweepd::server {

namespace {

using protocol::ErrorCode;
namespace fs = std::filesystem;

// The name a model is held under. The request's whole name, which may be a client's path, is
// bounded at intake (client_string_limits.h).
constexpr std::size_t kMaxNameBytes = 200;

// A model name the store can hold: 1 to kMaxNameBytes bytes.
void check_name(const std::string& name) {
  if (name.empty() || name.size() > kMaxNameBytes) {
    throw ModelError(ErrorCode::ModelLoadFailed,
                     "a model name must have 1 to " + std::to_string(kMaxNameBytes) +
                         " bytes; this one has " + std::to_string(name.size()));
  }
}

bool is_model_file(const fs::path& file) {
  const std::string extension = file.extension().string();
  return extension == ".glb" || extension == ".gltf";
}

// A store problem's log fields: file, reason, and quarantined_to when it was moved.
nlohmann::json problem_fields(const StoreProblem& problem) {
  nlohmann::json fields = {{"file", problem.file.string()}, {"reason", problem.reason}};
  if (!problem.quarantined_to.empty()) fields["quarantined_to"] = problem.quarantined_to.string();
  return fields;
}

// Each region the model's self-check found worse than skinning, for the operator.
void log_bind_warnings(const RegisteredModel& model) {
  for (const selfcheck::RegionWarning& warning : model.self_check.warnings)
    log_event("bind_warning", {{"name", model.name}, {"warning", warning.text}});
}

}  // namespace

std::string upload_name(std::string_view name) {
  const std::size_t slash = name.find_last_of("/\\");
  if (slash != std::string_view::npos) name.remove_prefix(slash + 1);
  std::string base(name);
  const std::size_t dot = base.rfind('.');
  if (dot != std::string::npos && dot > 0) {
    std::string extension = base.substr(dot);
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    for (const char* model_file : {".glb", ".gltf", ".fbx", ".dae"})
      if (extension == model_file) base.resize(dot);
  }
  return base;
}

ModelService::ModelService(const ServerConfig& config)
    : config_(config), registry_(config.store_dir, config.max_models) {}

ModelHandle ModelService::current(const ModelHandle& held) {
  std::optional<StoreProblem> problem;
  ModelHandle model = registry_.current(held->id, &problem);
  if (!model) return held;  // not a registry model (none is ever removed)
  if (problem) {
    nlohmann::json fields = problem_fields(*problem);
    fields["model"] = held->id;
    log_event("store_binding_damaged", std::move(fields));
  }
  return model;
}

std::vector<std::string> ModelService::directory_entries() const {
  std::vector<std::string> names;
  std::error_code error;
  if (config_.model_dir.empty() || !fs::is_directory(config_.model_dir, error)) return names;
  for (const fs::directory_entry& entry : fs::directory_iterator(config_.model_dir, error)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file(error) && is_model_file(entry.path()) && !registry_.find(name)) {
      names.push_back(name);
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

fs::path ModelService::model_file_in_directory(const std::string& name) const {
  if (config_.model_dir.empty()) {
    throw ModelError(ErrorCode::UnknownModel, "model '" + name +
                                                  "': this server has no model directory; upload "
                                                  "the glTF (" +
                                                  held_models_clause(*this) + ")");
  }
  if (name.empty() || name.find('/') != std::string::npos || name.starts_with(".")) {
    throw ModelError(ErrorCode::UnknownModel, "model '" + name +
                                                  "': not a file name in the model directory (" +
                                                  held_models_clause(*this) + ")");
  }
  for (const std::string suffix : {"", ".glb", ".gltf"}) {
    const fs::path file = config_.model_dir / (name + suffix);
    std::error_code error;
    if (is_model_file(file) && fs::is_regular_file(file, error)) return file;
  }
  throw ModelError(ErrorCode::UnknownModel, "model '" + name + "': no such .glb/.gltf in " +
                                                config_.model_dir.string() + " (" +
                                                held_models_clause(*this) + ")");
}

ModelHandle ModelService::held_or_stored(const std::string& content_id,
                                         const ModelLoadRequest& request) {
  if (ModelHandle held = registry_.find_content(content_id)) return held;
  ModelHandle adopted = registry_.adopt(content_id, request.hold_adoption_memory);
  if (adopted) {
    log_event("model_adopted", {{"model", adopted->id},
                                {"content_id", adopted->content_id},
                                {"name", adopted->name},
                                {"vertices", adopted->bound.model.vertex_count()}});
    log_bind_warnings(*adopted);
  }
  return adopted;
}

ModelHandle ModelService::load(const ModelLoadRequest& request) {
  if (!request.content_id.empty()) {
    if (!is_content_id(request.content_id)) {
      throw ModelError(ErrorCode::InvalidArgument,
                       "a content id has 64 lower-case hex digits (SHA-256)");
    }
    if (ModelHandle model = held_or_stored(request.content_id, request)) return model;
    throw ModelError(ErrorCode::UnknownModel, "no model with content id " + request.content_id +
                                                  " on this server or in its store; upload it (" +
                                                  held_models_clause(*this) + ")");
  }
  if (request.orientation != 0 && request.orientation != 1)
    throw ModelError(ErrorCode::ModelLoadFailed, "orientation curve " +
                                                     std::to_string(request.orientation) +
                                                     " is neither 0 (linear) nor 1 (smooth)");
  if (!request.gltf.empty()) {
    // One name per model (issue 48): an upload is named by its file's base name, never by a
    // client's local path, so every client and every restart finds it by the same name.
    ModelLoadRequest upload = request;
    upload.name = upload_name(request.name);
    check_name(upload.name);
    const std::string content_id = model_content_id(upload.gltf, upload.rig_map_json,
                                                    upload.keys_per_link, upload.orientation);
    if (ModelHandle model = held_or_stored(content_id, request)) return model;
    return bind_and_store(upload, content_id, {});
  }
  check_name(request.name);
  if (ModelHandle loaded = registry_.find(request.name)) return loaded;
  if (const std::string stored = registry_.stored_content_named(request.name); !stored.empty()) {
    if (ModelHandle model = held_or_stored(stored, request)) return model;
  }
  const fs::path file = model_file_in_directory(request.name);
  std::ifstream in(file, std::ios::binary);
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in),
                                        std::istreambuf_iterator<char>()};
  const std::string content_id =
      model_content_id(bytes, request.rig_map_json, request.keys_per_link, request.orientation);
  if (ModelHandle model = held_or_stored(content_id, request)) return model;
  return bind_and_store(request, content_id, file);
}

ModelHandle ModelService::bind_and_store(const ModelLoadRequest& request,
                                         const std::string& content_id,
                                         const fs::path& directory_file) {
  ModelRegistry::StoreSlot slot = registry_.claim(request.name, content_id);
  if (ModelHandle stored = registry_.find_content(content_id)) return stored;
  const auto started = std::chrono::steady_clock::now();
  // A load that fails leaves nothing in the store: the sources it wrote go — unless a binding of
  // this content id is there (another replica's, on a shared store: the same sources).
  struct SourcesOfAFailedLoad {
    fs::path binding, upload, rig_map;
    bool kept = false;
    ~SourcesOfAFailedLoad() {
      std::error_code ignored;
      if (kept || fs::exists(binding, ignored)) return;
      if (!upload.empty()) fs::remove(upload, ignored);
      fs::remove(rig_map, ignored);
    }
  } sources{slot.file(".sweepbind"), {}, slot.file(".rig.json")};
  deform::BoundModel bound;
  SelfCheck checked;
  try {
    // Held by the slot: until the binding is stored, and not while the next load reads.
    if (request.hold_reading_memory)
      slot.hold(request.hold_reading_memory(
          directory_file.empty() ? request.gltf.size() : fs::file_size(directory_file)));
    deform::Model model;
    if (directory_file.empty()) {
      // An upload reads nothing but itself: a glTF its GLB chunk and data: URIs, an FBX or
      // COLLADA file (io/assimp/assimp_load.h) its bytes. Kept under its format's suffix.
      const std::string_view assimp_suffix = io::assimp_model_suffix(request.gltf);
      sources.upload = slot.file(assimp_suffix.empty() ? ".glb" : assimp_suffix);
      io::write_file_durably(sources.upload, request.gltf);
      model = assimp_suffix.empty()
                  ? io::load_gltf(sources.upload, io::GltfUriPolicy::self_contained())
                  : io::load_assimp(request.gltf, sources.upload);
    } else {
      model = io::load_gltf(directory_file, io::GltfUriPolicy::within(config_.model_dir));
    }
    if (model.vertex_count() > config_.max_model_vertices) {
      throw ModelError(ErrorCode::MemoryLimit, "model '" + request.name + "' has " +
                                                   std::to_string(model.vertex_count()) +
                                                   " vertices; this server takes at most " +
                                                   std::to_string(config_.max_model_vertices));
    }
    model.name = request.name;
    if (request.hold_binding_memory) slot.hold(request.hold_binding_memory(model));
    deform::RigMap rig;
    if (request.rig_map_json.empty()) {
      rig = deform::detect_rig_map(model.skeleton);
      // A part found neither by name nor by shape is skinned, not swept: the operator hears it.
      for (const std::string& warning : rig.warnings)
        log_event("rig_warning", {{"name", request.name}, {"warning", warning}});
    } else {
      const fs::path rig_file = slot.file(".rig.json");
      io::write_file_durably(rig_file,
                             {reinterpret_cast<const std::uint8_t*>(request.rig_map_json.data()),
                              request.rig_map_json.size()});
      rig = io::load_rig_map_json(rig_file, model.skeleton);
    }
    deform::BindOptions options;
    if (request.keys_per_link > 0) options.intermediate_keys_per_link = request.keys_per_link;
    options.orientation_curve = static_cast<deform::OrientationCurveKind>(request.orientation);
    // The binding checks itself (issue 47) and adapts the sweeps that lose to skinning where a
    // refit wins (selfcheck::adapt_binding, recorded in the binding); each body region where the
    // sweep is still worse on the range of motion's peaks is said to the operator (the log)
    // and to the client (ModelInfo.bind_warnings). About 2.3x bind's own CPU time again
    // (docs/performance.md).
    selfcheck::CheckedBinding adapted = selfcheck::bind_checked(model, rig, options, true);
    bound = std::move(adapted.bound);
    checked = self_check(adapted.verdict);
  } catch (const ModelError&) {
    throw;
  } catch (const io::LoadError& error) {
    // An uploaded file's place in the store is the server's business: the reason alone.
    const bool uploaded = error.file().parent_path() == registry_.store_dir();
    throw ModelError(ErrorCode::ModelLoadFailed,
                     "model '" + request.name + "' could not be loaded: " +
                         (uploaded ? "the uploaded file: " + error.reason() : error.what()));
  } catch (const std::exception& error) {
    throw ModelError(ErrorCode::ModelLoadFailed,
                     "model '" + request.name + "' could not be loaded: " + error.what());
  }
  ModelHandle added = registry_.add(std::move(slot), request.name, std::move(bound),
                                    nanoseconds_since(started), std::move(checked));
  sources.kept = true;
  log_bind_warnings(*added);
  return added;
}

void ModelService::restore() {
  const RestoreReport report = registry_.restore();
  for (const fs::path& file : report.removed_temporaries) {
    log_event("store_temporary_removed", {{"file", file.string()}});
  }
  for (const StoreProblem& problem : report.problems)
    log_event("restore_problem", problem_fields(problem));
  if (report.migrated > 0) log_event("store_migrated", {{"models", report.migrated}});
  for (const ModelHandle& model : registry_.models()) {
    log_event("model_restored", {{"model", model->id},
                                 {"content_id", model->content_id},
                                 {"name", model->name},
                                 {"vertices", model->bound.model.vertex_count()}});
    log_bind_warnings(*model);
  }
}

void ModelService::add_default_model() {
  if (!config_.model_dir.empty() || registry_.find(std::string_view("mannequin"))) return;
  const std::string content_id = described_content_id("procedural mannequin, vertices=" +
                                                      std::to_string(config_.mannequin_vertices));
  if (held_or_stored(content_id, {})) return;  // start-up: no client's budget
  ModelRegistry::StoreSlot slot = registry_.claim("mannequin", content_id);
  const deform::Model model =
      mannequin::make_mannequin({.target_vertices = config_.mannequin_vertices});
  // Bound as an uploaded model is (and sweepctl bind binds): it checks itself and adapts where a
  // refit wins (its ModelInfo says so); the self-check and adaptation timed apart: the
  // start-up's cost.
  selfcheck::CheckedBinding adapted =
      selfcheck::bind_checked(model, deform::detect_rig_map(model.skeleton), {}, true);
  const auto bind_time_ns = static_cast<std::uint64_t>(adapted.bind_seconds * 1e9);
  const auto check_time_ns = static_cast<std::uint64_t>(adapted.check_seconds * 1e9);
  const ModelHandle added = registry_.add(std::move(slot), "mannequin", std::move(adapted.bound),
                                          bind_time_ns, self_check(adapted.verdict));
  log_event("model_loaded", {{"model", added->id},
                             {"content_id", added->content_id},
                             {"name", added->name},
                             {"vertices", added->bound.model.vertex_count()},
                             {"bind_time_ns", added->bind_time_ns},
                             {"self_check_time_ns", check_time_ns}});
  log_bind_warnings(*added);
}

ModelHandle ModelService::edit_key_ellipse(std::uint32_t model_id,
                                           const deform::RestKeyEdit& edit) {
  if (!registry_.find(model_id))
    throw ModelError(ErrorCode::UnknownModel, "no model with id " + std::to_string(model_id) +
                                                  " (" + held_models_clause(*this) + ")");
  return registry_.replace(model_id, [&edit](deform::BoundModel& bound) {
    if (const std::string problem = deform::apply_rest_key_edit(bound, edit); !problem.empty())
      throw ModelError(protocol::ErrorCode::InvalidArgument, problem);
  });
}

std::uint64_t ModelService::store_bytes() const {
  std::uint64_t bytes = 0;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(registry_.store_dir(), error)) {
    std::error_code ignored;  // a file renamed away during the listing is simply not counted
    if (entry.is_regular_file(ignored)) bytes += entry.file_size(ignored);
  }
  return bytes;
}

}  // namespace sweepd::server

#include "cli/model_loading.h"

#include "io/gltf_load.h"
#include "io/rig_map_json.h"

namespace sweepd::cli {

LoadedModel load_model_and_rig(const std::filesystem::path& model_file,
                               const std::filesystem::path& rig_file) {
  LoadedModel loaded;
  loaded.model = io::load_gltf(model_file);
  loaded.rig = rig_file.empty() ? deform::detect_rig_map(loaded.model.skeleton)
                                : io::load_rig_map_json(rig_file, loaded.model.skeleton);
  return loaded;
}

}  // namespace sweepd::cli

#include "cli/model_loading.h"

#include <cstdio>

#include "io/json/rig_map_json.h"
#include "io/model_load.h"

namespace sweepd::cli {

LoadedModel load_model_and_rig(const std::filesystem::path& model_file,
                               const std::filesystem::path& rig_file) {
  LoadedModel loaded;
  loaded.model = io::load_model(model_file);
  loaded.rig = rig_file.empty() ? deform::detect_rig_map(loaded.model.skeleton)
                                : io::load_rig_map_json(rig_file, loaded.model.skeleton);
  for (const std::string& warning : loaded.rig.warnings)
    std::fprintf(stderr, "warning: %s: %s\n", model_file.string().c_str(), warning.c_str());
  return loaded;
}

}  // namespace sweepd::cli

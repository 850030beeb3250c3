#include "io/joint_name_map_json.h"

#include "io/json_file.h"
#include "io/load_error.h"

namespace sweepd::io {

motion::JointNameMap load_joint_name_map_json(const std::filesystem::path& path) {
  const nlohmann::json document = read_json_file(path, "joint name map");
  if (!document.is_object())
    throw LoadError(path, "expected an object {\"BVH joint\": \"model joint\", ...}");
  motion::JointNameMap map{.source = path.string(), .pairs = {}};
  for (const auto& [clip_joint, model_joint] : document.items()) {
    if (model_joint.is_null()) {
      map.pairs.push_back({clip_joint, std::nullopt});
    } else if (model_joint.is_string()) {
      map.pairs.push_back({clip_joint, model_joint.get<std::string>()});
    } else {
      throw LoadError(path, "'" + clip_joint + "': expected a model joint name or null, got " +
                                model_joint.dump());
    }
  }
  return map;
}

}  // namespace sweepd::io

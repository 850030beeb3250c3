#include "io/json/joint_name_map_json.h"

#include "io/files/load_error.h"
#include "io/json/json_file.h"

namespace sweepd::io {

namespace {

motion::JointNameMap name_map_of(const nlohmann::json& document, const std::string& source) {
  if (!document.is_object())
    throw LoadError(source, "expected an object {\"BVH joint\": \"model joint\", ...}");
  motion::JointNameMap map{.source = source, .pairs = {}};
  for (const auto& [clip_joint, model_joint] : document.items()) {
    if (model_joint.is_null()) {
      map.pairs.push_back({clip_joint, std::nullopt});
    } else if (model_joint.is_string()) {
      map.pairs.push_back({clip_joint, model_joint.get<std::string>()});
    } else {
      throw LoadError(source, "'" + clip_joint + "': expected a model joint name or null, got " +
                                  model_joint.dump());
    }
  }
  return map;
}

}  // namespace

motion::JointNameMap load_joint_name_map_json(const std::filesystem::path& path) {
  return name_map_of(read_json_file(path, "joint name map"), path.string());
}

motion::JointNameMap parse_joint_name_map_json(std::string_view text, const std::string& source) {
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw LoadError(source, std::string("the joint name map is not valid JSON: ") + e.what());
  }
  return name_map_of(document, source);
}

}  // namespace sweepd::io

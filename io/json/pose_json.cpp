#include "io/json/pose_json.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "io/files/load_error.h"
#include "io/files/write_whole_file.h"
#include "io/json/json_file.h"

namespace sweepd::io {

namespace {

using nlohmann::json;

class PoseReader {
 public:
  PoseReader(const std::filesystem::path& path, const deform::Skeleton& skeleton)
      : path_(path), skeleton_(skeleton) {}

  [[noreturn]] void fail(const std::string& reason) const { throw LoadError(path_, reason); }

  // An array of exactly N finite numbers.
  template <int N>
  glm::vec<N, float> numbers(const json& value, const std::string& where) const {
    if (!value.is_array() || value.size() != N)
      fail(where + ": expected an array of " + std::to_string(N) + " numbers, got " + value.dump());
    glm::vec<N, float> result(0.0f);
    for (int i = 0; i < N; ++i) {
      if (!value[i].is_number())
        fail(where + ": element " + std::to_string(i) + " is not a number: " + value[i].dump());
      result[i] = value[i].get<float>();
      if (!std::isfinite(result[i]))
        fail(where + ": element " + std::to_string(i) + " is NaN or infinite");
    }
    return result;
  }

  glm::quat rotation(const json& value, const std::string& where) const {
    if (value.is_array()) {
      const glm::vec4 wxyz = numbers<4>(value, where);
      const glm::quat q(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
      if (!(glm::length(q) > 0.0f)) fail(where + ": the quaternion has zero length");
      return q;  // normalize_and_validate normalises it (and leaves unit ones bit for bit)
    }
    if (!value.is_object())
      fail(where + ": expected [w, x, y, z] or {\"axis\": [x, y, z], \"degrees\": angle}, got " +
           value.dump());
    for (const auto& [key, unused] : value.items())
      if (key != "axis" && key != "degrees")
        fail(where + ": unknown key \"" + key + "\" (expected \"axis\" and \"degrees\")");
    if (!value.contains("axis") || !value.contains("degrees"))
      fail(where + ": an axis-angle rotation needs both \"axis\" and \"degrees\"");
    const glm::vec3 axis = numbers<3>(value["axis"], where + ".axis");
    if (!(glm::length(axis) > 0.0f)) fail(where + ".axis has zero length");
    const json& degrees = value["degrees"];
    if (!degrees.is_number() || !std::isfinite(degrees.get<float>()))
      fail(where + ".degrees: expected a finite number, got " + degrees.dump());
    return glm::angleAxis(glm::radians(degrees.get<float>()), glm::normalize(axis));
  }

  deform::Pose read(const json& document) const {
    if (!document.is_object())
      fail("expected a JSON object with \"root_translation\" and/or \"rotations\"");
    for (const auto& [key, unused] : document.items())
      if (key != "root_translation" && key != "rotations")
        fail("unknown key \"" + key + "\" (expected \"root_translation\" and \"rotations\")");
    deform::Pose pose = deform::rest_pose(skeleton_);
    if (document.contains("root_translation"))
      pose.root_translation = numbers<3>(document["root_translation"], "root_translation");
    if (!document.contains("rotations")) return pose;
    const json& rotations = document["rotations"];
    if (!rotations.is_object())
      fail("\"rotations\" must be an object {\"joint name\": rotation, ...}");
    for (const auto& [name, value] : rotations.items()) {
      const int j = skeleton_.find(name);
      if (j < 0) fail("rotations: no joint named '" + name + "' in the skeleton");
      pose.local_rotations[j] = rotation(value, "rotations." + name);
    }
    return pose;
  }

 private:
  std::filesystem::path path_;
  const deform::Skeleton& skeleton_;
};

}  // namespace

deform::Pose load_pose_json(const std::filesystem::path& path, const deform::Skeleton& skeleton) {
  const PoseReader reader(path, skeleton);
  deform::Pose pose = reader.read(read_json_file(path, "pose file"));
  if (std::string why = deform::normalize_and_validate(pose, skeleton); !why.empty())
    reader.fail(why);
  return pose;
}

void save_pose_json(const deform::Pose& pose, const deform::Skeleton& skeleton,
                    const std::filesystem::path& path) {
  deform::Pose checked = pose;
  if (std::string why = deform::normalize_and_validate(checked, skeleton); !why.empty())
    throw std::invalid_argument("refusing to write " + path.string() + ": " + why);
  nlohmann::ordered_json document;
  const glm::vec3& t = pose.root_translation;
  document["root_translation"] = {t.x, t.y, t.z};
  document["rotations"] = nlohmann::ordered_json::object();
  for (int j = 0; j < skeleton.size(); ++j) {
    const glm::quat& q = checked.local_rotations[j];
    if (q != skeleton.joints[j].rest_rotation)
      document["rotations"][skeleton.joints[j].name] = {q.w, q.x, q.y, q.z};
  }
  write_whole_file(path, document.dump(2) + "\n", "save_pose_json");
}

}  // namespace sweepd::io

#include "io/json/rig_map_json.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "io/files/load_error.h"
#include "io/files/write_whole_file.h"

namespace sweepd::io {

namespace {

using nlohmann::ordered_json;

// The roles of a limb, root first, as written in the file; the pointers target the map.
struct RoleSlot {
  const char* key;
  int* joint;
  bool required;
};

std::array<RoleSlot, 4> slots(deform::ArmJoints& arm) {
  return {{{"clavicle", &arm.clavicle, false},
           {"upper", &arm.upper, true},
           {"lower", &arm.lower, true},
           {"hand", &arm.hand, true}}};
}

std::array<RoleSlot, 5> slots(deform::LegJoints& leg) {
  return {{{"hip", &leg.hip, false},
           {"upper", &leg.upper, true},
           {"lower", &leg.lower, true},
           {"foot", &leg.foot, true},
           {"toe", &leg.toe, false}}};
}

class RigMapReader {
 public:
  RigMapReader(const std::filesystem::path& path, const deform::Skeleton& skeleton)
      : path_(path), skeleton_(skeleton) {}

  [[noreturn]] void fail(const std::string& reason) const { throw LoadError(path_, reason); }

  int joint(const ordered_json& value, const std::string& where) const {
    if (!value.is_string()) fail(where + ": expected a joint name (a string), got " + value.dump());
    const std::string name = value.get<std::string>();
    const int j = skeleton_.find(name);
    if (j < 0) fail(where + ": no joint named '" + name + "' in the skeleton");
    return j;
  }

  std::vector<int> chain(const ordered_json& value, const std::string& part) const {
    if (!value.is_array() || value.empty())
      fail(part + ": expected a non-empty array of joint names");
    std::vector<int> joints;
    for (std::size_t i = 0; i < value.size(); ++i)
      joints.push_back(joint(value[i], part + "[" + std::to_string(i) + "]"));
    return joints;
  }

  // Fills the slots from a keyed object, or from an array naming either the required roles
  // only or every role, in chain order; null leaves the limb absent (every slot -1).
  template <std::size_t N>
  void limb(const ordered_json& value, const std::string& part,
            const std::array<RoleSlot, N>& roles) const {
    if (value.is_null()) return;
    if (value.is_array()) {
      std::size_t first = 0, count = 0;
      for (const RoleSlot& role : roles) count += role.required;
      if (value.size() == N) {
        count = N;
      } else if (value.size() == count) {
        while (!roles[first].required) ++first;
      } else {
        fail(part + ": an array must list " + std::to_string(count) + " or " + std::to_string(N) +
             " joint names, has " + std::to_string(value.size()) + " (or use keys like \"upper\")");
      }
      for (std::size_t i = 0; i < count; ++i)
        *roles[first + i].joint = joint(value[i], part + "[" + std::to_string(i) + "]");
      return;
    }
    if (!value.is_object()) fail(part + ": expected an object of roles or an array of joint names");
    for (const auto& [key, name] : value.items()) {
      const RoleSlot* role = nullptr;
      for (const RoleSlot& r : roles)
        if (key == r.key) role = &r;
      if (!role) fail(part + ": unknown role \"" + key + "\"" + role_list(roles));
      *role->joint = name.is_null() ? -1 : joint(name, part + "." + key);
    }
    for (const RoleSlot& role : roles)
      if (role.required && *role.joint < 0) fail(part + ": missing role \"" + role.key + "\"");
  }

 private:
  template <std::size_t N>
  static std::string role_list(const std::array<RoleSlot, N>& roles) {
    std::string text = " (roles: ";
    for (const RoleSlot& role : roles) text += std::string(role.key) + (role.required ? " " : "? ");
    return text.substr(0, text.size() - 1) + ")";
  }

  std::filesystem::path path_;
  const deform::Skeleton& skeleton_;
};

constexpr const char* kParts[] = {"torso",     "neck",     "left_arm",
                                  "right_arm", "left_leg", "right_leg"};

}  // namespace

deform::RigMap load_rig_map_json(const std::filesystem::path& path,
                                 const deform::Skeleton& skeleton) {
  const RigMapReader reader(path, skeleton);
  std::ifstream file(path);
  if (!file) reader.fail("cannot open the rig map file");
  ordered_json document;
  try {
    document = ordered_json::parse(file);
  } catch (const ordered_json::parse_error& e) {
    reader.fail(std::string("not valid JSON: ") + e.what());
  }
  if (!document.is_object()) reader.fail("expected a JSON object with the parts as keys");
  for (const auto& [key, value] : document.items()) {
    const bool known = key == "convention" ||
                       std::find(std::begin(kParts), std::end(kParts), key) != std::end(kParts);
    if (!known)
      reader.fail("unknown key \"" + key +
                  "\" (expected torso, neck, left_arm, right_arm, left_leg, right_leg)");
  }
  for (const char* part : kParts)
    if (!document.contains(part))
      reader.fail(std::string("missing part \"") + part +
                  "\" (every part is required: torso, neck, left_arm, right_arm, left_leg, "
                  "right_leg)");

  deform::RigMap map;
  map.convention = "json";
  map.torso.chain = reader.chain(document["torso"], "torso");
  if (!document["neck"].is_null()) {  // null: no head (the neck and head are skinned)
    map.neck.chain = reader.chain(document["neck"], "neck");
    map.neck.head = map.neck.chain.back();
  }
  reader.limb(document["left_arm"], "left_arm", slots(map.left_arm));
  reader.limb(document["right_arm"], "right_arm", slots(map.right_arm));
  reader.limb(document["left_leg"], "left_leg", slots(map.left_leg));
  reader.limb(document["right_leg"], "right_leg", slots(map.right_leg));
  if (std::string why = deform::validate_rig_map(map, skeleton); !why.empty())
    reader.fail("the rig map does not fit the skeleton: " + why);
  return map;
}

void save_rig_map_json(const deform::RigMap& map, const deform::Skeleton& skeleton,
                       const std::filesystem::path& path) {
  if (std::string why = deform::validate_rig_map(map, skeleton); !why.empty())
    throw std::invalid_argument("refusing to write " + path.string() +
                                ": the rig map does not fit the skeleton: " + why);
  auto names = [&](const std::vector<int>& chain) {
    ordered_json list = ordered_json::array();
    for (int j : chain) list.push_back(skeleton.joints[j].name);
    return list;
  };
  auto roles = [&](const auto& role_slots) {
    const bool absent = std::all_of(role_slots.begin(), role_slots.end(),
                                    [](const RoleSlot& role) { return *role.joint < 0; });
    if (absent) return ordered_json(nullptr);
    ordered_json object = ordered_json::object();
    for (const RoleSlot& role : role_slots)
      if (*role.joint >= 0) object[role.key] = skeleton.joints[*role.joint].name;
    return object;
  };
  deform::RigMap copy = map;  // slots() point into a mutable map
  ordered_json document;
  document["convention"] = map.convention;
  document["torso"] = names(map.torso.chain);
  document["neck"] = map.has_head() ? names(map.neck.chain) : ordered_json(nullptr);
  document["left_arm"] = roles(slots(copy.left_arm));
  document["right_arm"] = roles(slots(copy.right_arm));
  document["left_leg"] = roles(slots(copy.left_leg));
  document["right_leg"] = roles(slots(copy.right_leg));
  write_whole_file(path, document.dump(2) + "\n", "save_rig_map_json");
}

}  // namespace sweepd::io

#include "io/json/key_ellipse_edits_json.h"

#include <nlohmann/json.hpp>
#include <string>

#include "io/files/load_error.h"
#include "io/files/write_whole_file.h"
#include "io/json/json_file.h"

namespace sweepd::io {

namespace {

using nlohmann::json;

class EditsReader {
 public:
  EditsReader(const std::filesystem::path& path, const deform::BoundModel& bound)
      : path_(path), bound_(bound) {}

  [[noreturn]] void fail(const std::string& reason) const { throw LoadError(path_, reason); }

  const json& field(const json& object, const char* key, const std::string& where) const {
    if (!object.is_object() || !object.contains(key)) fail(where + ": missing \"" + key + "\"");
    return object.at(key);
  }

  float number(const json& value, const std::string& where) const {
    if (!value.is_number()) fail(where + ": expected a number, got " + value.dump());
    return value.get<float>();
  }

  // A fixed-size array of numbers, or `fallback` when the key is absent.
  template <int N>
  std::array<float, N> numbers(const json& object, const char* key, const std::string& where,
                               float fallback) const {
    std::array<float, N> out;
    out.fill(fallback);
    if (!object.contains(key)) return out;
    const json& value = object.at(key);
    if (!value.is_array() || value.size() != N)
      fail(where + "." + key + ": expected " + std::to_string(N) + " numbers, got " + value.dump());
    for (int i = 0; i < N; ++i) out[i] = number(value[i], where + "." + key);
    return out;
  }

  int sweep(const json& value, const std::string& where) const {
    if (!value.is_string()) fail(where + ": expected a body part name, got " + value.dump());
    const std::string name = value.get<std::string>();
    for (std::size_t s = 0; s < bound_.sweeps.size(); ++s)
      if (name == deform::to_string(bound_.sweeps[s].part)) return static_cast<int>(s);
    std::string known;
    for (const deform::BoundSweep& s : bound_.sweeps)
      known += (known.empty() ? "" : ", ") + std::string(deform::to_string(s.part));
    fail(where + ": no sweep for part '" + name + "' (the model has: " + known + ")");
  }

  deform::KeyEllipseEdit edit(const json& value, const std::string& where) const {
    deform::KeyEllipseEdit edit;
    edit.sweep = sweep(field(value, "part", where), where + ".part");
    const json& key = field(value, "key", where);
    if (!key.is_number_integer()) fail(where + ".key: expected an integer, got " + key.dump());
    edit.key = key.get<int>();
    const json& joint = field(value, "joint", where);
    if (!joint.is_string()) fail(where + ".joint: expected a joint name, got " + joint.dump());
    edit.joint = bound_.model.skeleton.find(joint.get<std::string>());
    if (edit.joint < 0)
      fail(where + ".joint: no joint named '" + joint.get<std::string>() + "' in the skeleton");
    const json& samples = field(value, "samples", where);
    if (!samples.is_array()) fail(where + ".samples: expected an array");
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const std::string at = where + ".samples[" + std::to_string(i) + "]";
      deform::KeyEllipseEditSample sample;
      sample.angle_degrees = number(field(samples[i], "angle", at), at + ".angle");
      const auto offset = numbers<3>(samples[i], "offset", at, 0.0f);
      const auto rotation = numbers<3>(samples[i], "rotation", at, 0.0f);
      const auto scale = numbers<2>(samples[i], "scale", at, 1.0f);
      sample.correction = {{offset[0], offset[1], offset[2]},
                           {rotation[0], rotation[1], rotation[2]},
                           scale[0],
                           scale[1]};
      edit.samples.push_back(sample);
    }
    return edit;
  }

 private:
  const std::filesystem::path& path_;
  const deform::BoundModel& bound_;
};

}  // namespace

deform::KeyEllipseEdits load_key_ellipse_edits_json(const std::filesystem::path& path,
                                                    const deform::BoundModel& bound) {
  const json document = read_json_file(path, "key ellipse edits");
  const EditsReader reader(path, bound);
  const json& list = reader.field(document, "edits", "the file");
  if (!list.is_array()) reader.fail("\"edits\": expected an array");
  deform::KeyEllipseEdits edits;
  for (std::size_t e = 0; e < list.size(); ++e)
    edits.edits.push_back(reader.edit(list[e], "edits[" + std::to_string(e) + "]"));
  if (std::string why = deform::validate(edits, bound); !why.empty()) reader.fail(why);
  return edits;
}

void save_key_ellipse_edits_json(const deform::KeyEllipseEdits& edits,
                                 const deform::BoundModel& bound,
                                 const std::filesystem::path& path) {
  json list = json::array();
  for (const deform::KeyEllipseEdit& edit : edits.edits) {
    json samples = json::array();
    for (const deform::KeyEllipseEditSample& s : edit.samples) {
      const deform::KeyEllipseCorrection& c = s.correction;
      samples.push_back({{"angle", s.angle_degrees},
                         {"offset", {c.offset.x, c.offset.y, c.offset.z}},
                         {"rotation", {c.rotation.x, c.rotation.y, c.rotation.z}},
                         {"scale", {c.scale_a, c.scale_b}}});
    }
    list.push_back({{"part", deform::to_string(bound.sweeps.at(edit.sweep).part)},
                    {"key", edit.key},
                    {"joint", bound.model.skeleton.joints.at(edit.joint).name},
                    {"samples", samples}});
  }
  write_whole_file(path, json{{"edits", list}}.dump(2) + "\n", "save_key_ellipse_edits_json");
}

}  // namespace sweepd::io

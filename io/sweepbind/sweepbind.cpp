#include "io/sweepbind/sweepbind.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "io/files/durable_file.h"
#include "io/files/file_bytes.h"
#include "io/sweepbind/byte_stream.h"

namespace sweepd::io {

namespace {

constexpr char kMagic[8] = {'S', 'W', 'E', 'E', 'P', 'B', 'N', 'D'};
constexpr std::size_t kHeaderSize = 32;  // magic 8, version 4, flags 4, size 8, CRC 4, model 4
constexpr std::uint64_t kMaxVertices = 1u << 26;
constexpr std::uint64_t kMaxJoints = 1u << 12;
constexpr std::uint64_t kMaxKeys = 1u << 10;
constexpr std::uint64_t kMaxEdits = 1u << 12;
constexpr std::uint64_t kMaxEditSamples = 1u << 10;
constexpr std::uint64_t kMaxMeshParts = 1u << 16;

// Records stored as raw bytes: their layout is the file format (io/sweepbind/SWEEPBIND.md). No padding.
static_assert(sizeof(deform::KeyAnchor) == 12);
static_assert(sizeof(deform::KeyEllipse) == 44);
static_assert(sizeof(deform::BindOptions) == 28);
// Version 6's bind options are version 7's without the orientation curve, their last field.
constexpr std::size_t kVersion6BindOptionsSize = 24;
static_assert(offsetof(deform::BindOptions, orientation_curve) == kVersion6BindOptionsSize);
constexpr std::uint32_t kOldestReadableVersion = 6;
static_assert(sizeof(deform::VertexBinding) == 84);

using deform::BodyPart;
using deform::BoundModel;

// --- writing ---------------------------------------------------------------------------------

void put_chain(ByteWriter& out, const std::vector<int>& chain) {
  out.put_array(std::span<const int>(chain));
}

void put_model(ByteWriter& out, const deform::Model& model) {
  out.put_string(model.name);
  out.put_array(std::span<const glm::vec3>(model.positions));
  out.put_array(std::span<const glm::vec3>(model.normals));
  out.put_array(std::span<const glm::vec2>(model.uvs));
  out.put_array(std::span<const std::uint32_t>(model.indices));
  out.put<std::uint64_t>(model.skeleton.joints.size());
  for (const deform::Joint& joint : model.skeleton.joints) {
    out.put_string(joint.name);
    out.put<std::int32_t>(joint.parent);
    out.put(joint.rest_translation);
    out.put(joint.rest_rotation);
    out.put(joint.rest_scale);
  }
  out.put_array(std::span<const std::array<std::uint16_t, deform::kInfluences>>(model.skin_joints));
  out.put_array(std::span<const std::array<float, deform::kInfluences>>(model.skin_weights));
}

void put_rig(ByteWriter& out, const deform::RigMap& rig) {
  out.put_string(rig.convention);
  put_chain(out, rig.torso.chain);
  put_chain(out, rig.neck.chain);
  out.put<std::int32_t>(rig.neck.head);
  for (const deform::ArmJoints* arm : {&rig.left_arm, &rig.right_arm})
    for (int j : {arm->clavicle, arm->upper, arm->lower, arm->hand}) out.put<std::int32_t>(j);
  for (const deform::LegJoints* leg : {&rig.left_leg, &rig.right_leg})
    for (int j : {leg->hip, leg->upper, leg->lower, leg->foot, leg->toe}) out.put<std::int32_t>(j);
}

void put_sweep(ByteWriter& out, const deform::BoundSweep& sweep) {
  out.put<std::uint8_t>(static_cast<std::uint8_t>(sweep.part));
  put_chain(out, sweep.chain);
  out.put_array(std::span<const deform::KeyAnchor>(sweep.anchors));
  out.put_array(std::span<const deform::KeyEllipse>(sweep.rest_keys));
  out.put_array(std::span<const float>(sweep.key_fit_errors));
  out.put_array(std::span<const float>(sweep.key_area_ratios));
  out.put_array(std::span<const std::uint8_t>(sweep.key_fallback));
  out.put(sweep.rest_volume);
}

// Version 8 on: the model's mesh parts (deform/model/mesh_part.h), after the edits.
void put_mesh_parts(ByteWriter& out, const std::vector<deform::MeshPart>& parts) {
  out.put<std::uint64_t>(parts.size());
  for (const deform::MeshPart& part : parts) {
    out.put_string(part.name);
    out.put_string(part.material);
    for (std::uint32_t value :
         {part.mesh, part.first_vertex, part.vertex_count, part.first_index, part.index_count})
      out.put<std::uint32_t>(value);
    out.put<std::int32_t>(part.rigid_joint);
  }
}

// Version 9 on: what each sweep was bound with (deform::SweepChoice), after the mesh parts.
void put_sweep_choices(ByteWriter& out, const std::vector<deform::BoundSweep>& sweeps) {
  out.put<std::uint64_t>(sweeps.size());
  for (const deform::BoundSweep& sweep : sweeps) {
    out.put<std::int32_t>(static_cast<std::int32_t>(sweep.choice.orientation_curve));
    out.put<std::int32_t>(sweep.choice.keys_per_link);
    out.put<std::uint8_t>(static_cast<std::uint8_t>(sweep.choice.origin));
    out.put<std::uint32_t>(sweep.choice.worse_before);
    out.put<std::uint32_t>(sweep.choice.worse_after);
  }
}

// --- reading ---------------------------------------------------------------------------------

std::vector<int> get_chain(ByteReader& in, const char* what) {
  return in.get_array<int>(what, kMaxJoints);
}

deform::Model get_model(ByteReader& in) {
  deform::Model model;
  model.name = in.get_string("model name");
  model.positions = in.get_array<glm::vec3>("positions", kMaxVertices);
  model.normals = in.get_array<glm::vec3>("normals", kMaxVertices);
  model.uvs = in.get_array<glm::vec2>("UVs", kMaxVertices);
  model.indices = in.get_array<std::uint32_t>("indices", 3 * 2 * kMaxVertices);
  const auto joints = in.get<std::uint64_t>("joint count");
  if (joints > kMaxJoints) in.fail("joint count " + std::to_string(joints) + " is out of range");
  model.skeleton.joints.resize(joints);
  for (deform::Joint& joint : model.skeleton.joints) {
    joint.name = in.get_string("joint name");
    joint.parent = in.get<std::int32_t>("joint parent");
    joint.rest_translation = in.get<glm::vec3>("joint translation");
    joint.rest_rotation = in.get<glm::quat>("joint rotation");
    joint.rest_scale = in.get<glm::vec3>("joint scale");
  }
  model.skin_joints =
      in.get_array<std::array<std::uint16_t, deform::kInfluences>>("skin joints", kMaxVertices);
  model.skin_weights =
      in.get_array<std::array<float, deform::kInfluences>>("skin weights", kMaxVertices);
  return model;
}

deform::RigMap get_rig(ByteReader& in) {
  deform::RigMap rig;
  rig.convention = in.get_string("rig convention");
  rig.torso.chain = get_chain(in, "torso chain");
  rig.neck.chain = get_chain(in, "neck chain");
  rig.neck.head = in.get<std::int32_t>("head joint");
  for (deform::ArmJoints* arm : {&rig.left_arm, &rig.right_arm})
    for (int* j : {&arm->clavicle, &arm->upper, &arm->lower, &arm->hand})
      *j = in.get<std::int32_t>("arm joint");
  for (deform::LegJoints* leg : {&rig.left_leg, &rig.right_leg})
    for (int* j : {&leg->hip, &leg->upper, &leg->lower, &leg->foot, &leg->toe})
      *j = in.get<std::int32_t>("leg joint");
  return rig;
}

deform::BoundSweep get_sweep(ByteReader& in) {
  deform::BoundSweep sweep;
  const auto part = in.get<std::uint8_t>("sweep part");
  if (part > static_cast<std::uint8_t>(BodyPart::kRightFoot))
    in.fail("unknown body part " + std::to_string(part));
  sweep.part = static_cast<BodyPart>(part);
  sweep.chain = get_chain(in, "sweep chain");
  sweep.anchors = in.get_array<deform::KeyAnchor>("key anchors", kMaxKeys);
  sweep.rest_keys = in.get_array<deform::KeyEllipse>("key ellipses", kMaxKeys);
  sweep.key_fit_errors = in.get_array<float>("key fit errors", kMaxKeys);
  sweep.key_area_ratios = in.get_array<float>("key area ratios", kMaxKeys);
  sweep.key_fallback = in.get_array<std::uint8_t>("key fallbacks", kMaxKeys);
  sweep.rest_volume = in.get<double>("sweep volume");
  return sweep;
}

std::vector<deform::MeshPart> get_mesh_parts(ByteReader& in) {
  const auto count = in.get<std::uint64_t>("mesh part count");
  if (count > kMaxMeshParts)
    in.fail("mesh part count " + std::to_string(count) + " is out of range");
  std::vector<deform::MeshPart> parts(count);
  for (deform::MeshPart& part : parts) {
    part.name = in.get_string("mesh part name");
    part.material = in.get_string("mesh part material");
    for (std::uint32_t* value :
         {&part.mesh, &part.first_vertex, &part.vertex_count, &part.first_index, &part.index_count})
      *value = in.get<std::uint32_t>("mesh part range");
    part.rigid_joint = in.get<std::int32_t>("mesh part joint");
  }
  return parts;
}

void get_sweep_choices(ByteReader& in, std::vector<deform::BoundSweep>& sweeps) {
  const auto count = in.get<std::uint64_t>("sweep choice count");
  if (count != sweeps.size())
    in.fail("sweep choice count " + std::to_string(count) + " differs from the sweep count " +
            std::to_string(sweeps.size()));
  for (deform::BoundSweep& sweep : sweeps) {
    const auto curve = in.get<std::int32_t>("sweep orientation curve");
    if (curve != 0 && curve != 1)
      in.fail("sweep orientation curve " + std::to_string(curve) +
              " is neither 0 (linear) nor 1 (smooth)");
    sweep.choice.orientation_curve = static_cast<deform::OrientationCurveKind>(curve);
    sweep.choice.keys_per_link = in.get<std::int32_t>("sweep keys per link");
    if (sweep.choice.keys_per_link < 0 ||
        sweep.choice.keys_per_link > static_cast<std::int32_t>(kMaxKeys))
      in.fail("sweep keys per link " + std::to_string(sweep.choice.keys_per_link) +
              " is out of range");
    const auto origin = in.get<std::uint8_t>("sweep choice origin");
    if (origin > 1)
      in.fail("sweep choice origin " + std::to_string(origin) +
              " is neither 0 (bind options) nor 1 (self-check)");
    sweep.choice.origin = static_cast<deform::SweepChoiceOrigin>(origin);
    sweep.choice.worse_before = in.get<std::uint32_t>("sweep choice worse before");
    sweep.choice.worse_after = in.get<std::uint32_t>("sweep choice worse after");
  }
}

bool finite(float x) { return std::isfinite(x); }

// Everything the poser will index or trust, checked once here.
std::string validate(const BoundModel& bound) {
  if (std::string why = bound.model.validate(); !why.empty()) return "model: " + why;
  if (std::string why = deform::validate_rig_map(bound.rig, bound.model.skeleton); !why.empty())
    return "rig map: " + why;
  if (const auto kind = bound.options.orientation_curve;
      kind != deform::OrientationCurveKind::kLinear &&
      kind != deform::OrientationCurveKind::kSmooth)
    return "bind options: orientation curve " + std::to_string(static_cast<int>(kind)) +
           " is neither 0 (linear) nor 1 (smooth)";
  const int joints = bound.model.skeleton.size();
  for (std::size_t s = 0; s < bound.sweeps.size(); ++s) {
    const deform::BoundSweep& sweep = bound.sweeps[s];
    const std::string name = "sweep " + std::to_string(s);
    const std::size_t keys = sweep.rest_keys.size();
    if (keys < 2 || sweep.anchors.size() != keys || sweep.key_fit_errors.size() != keys ||
        sweep.key_area_ratios.size() != keys || sweep.key_fallback.size() != keys)
      return name + ": key arrays disagree in size or hold fewer than 2 keys";
    for (int j : sweep.chain)
      if (j < 0 || j >= joints)
        return name + ": chain joint " + std::to_string(j) + " out of range";
    for (const deform::KeyAnchor& anchor : sweep.anchors)
      if (anchor.joint < 0 || anchor.joint >= joints || anchor.next_joint < -1 ||
          anchor.next_joint >= joints || !(anchor.fraction >= 0.0f && anchor.fraction <= 1.0f) ||
          (anchor.fraction == 1.0f && anchor.next_joint >= 0))  // 1: a carried end's own key
        return name + ": a key anchor is out of range";
    for (const deform::KeyEllipse& key : sweep.rest_keys)
      if (!finite(key.centre.x) || !finite(key.centre.y) || !finite(key.centre.z) ||
          !finite(key.orientation.w) || !(key.a > 0.0f) || !(key.b > 0.0f) ||
          !std::isfinite(key.a * key.b) || !finite(key.offset.x) || !finite(key.offset.y))
        return name + ": a key ellipse is not finite or has a non-positive half-axis";
  }
  const std::size_t n = bound.model.vertex_count();
  if (bound.vertices.size() != n)
    return "binding count " + std::to_string(bound.vertices.size()) + " != vertex count " +
           std::to_string(bound.model.vertex_count());
  const auto sweeps = static_cast<int>(bound.sweeps.size());
  for (std::size_t v = 0; v < bound.vertices.size(); ++v) {
    const deform::VertexBinding& b = bound.vertices[v];
    float sum = b.skin_weight;
    for (int k = 0; k < deform::kSweepsPerVertex; ++k) {
      const deform::SweepCoordinate& c = b.coordinate[k];
      if (b.sweep[k] < -1 || b.sweep[k] >= sweeps || !finite(b.weight[k]) || !finite(c.t) ||
          !finite(c.theta) || !finite(c.da) || !finite(c.db) || !finite(c.c))
        return "vertex " + std::to_string(v) + " has an invalid sweep binding";
      sum += b.weight[k];
    }
    if (!(std::abs(sum - 1.0f) < 1e-3f))
      return "vertex " + std::to_string(v) + " has binding weights summing to " +
             std::to_string(sum);
  }
  const std::size_t shares = bound.skinned_share_joints.size();
  if (bound.skinned_share_weights.size() != shares || (shares != 0 && shares != n))
    return "skinned share influences: " + std::to_string(shares) + " joint and " +
           std::to_string(bound.skinned_share_weights.size()) + " weight sets for " +
           std::to_string(n) + " vertices";
  for (std::size_t v = 0; v < shares; ++v) {
    float sum = 0.0f;
    for (int k = 0; k < deform::kInfluences; ++k) {
      const float w = bound.skinned_share_weights[v][k];
      if (bound.skinned_share_joints[v][k] >= joints || !(w >= 0.0f) || !finite(w))
        return "vertex " + std::to_string(v) + " has an invalid skinned share influence";
      sum += w;
    }
    if (!(std::abs(sum - 1.0f) < 1e-3f))
      return "vertex " + std::to_string(v) + " has skinned share weights summing to " +
             std::to_string(sum);
  }
  return {};
}

}  // namespace

std::uint32_t model_fingerprint(const deform::Model& model) {
  std::vector<std::uint8_t> bytes(model.positions.size() * sizeof(glm::vec3) +
                                  model.indices.size() * sizeof(std::uint32_t));
  std::memcpy(bytes.data(), model.positions.data(), model.positions.size() * sizeof(glm::vec3));
  std::memcpy(bytes.data() + model.positions.size() * sizeof(glm::vec3), model.indices.data(),
              model.indices.size() * sizeof(std::uint32_t));
  return crc32(bytes);
}

std::vector<std::uint8_t> encode_sweepbind(const BoundModel& bound) {
  ByteWriter payload;
  put_model(payload, bound.model);
  put_rig(payload, bound.rig);
  payload.put(bound.options);
  payload.put<std::uint64_t>(bound.sweeps.size());
  for (const deform::BoundSweep& sweep : bound.sweeps) put_sweep(payload, sweep);
  payload.put_array(std::span<const deform::VertexBinding>(bound.vertices));
  payload.put_array(
      std::span<const std::array<std::uint16_t, deform::kInfluences>>(bound.skinned_share_joints));
  payload.put_array(
      std::span<const std::array<float, deform::kInfluences>>(bound.skinned_share_weights));
  payload.put<std::uint64_t>(bound.edits.edits.size());
  for (const deform::KeyEllipseEdit& edit : bound.edits.edits) {
    for (int value : {edit.sweep, edit.key, edit.joint}) payload.put<std::int32_t>(value);
    payload.put_array(std::span<const deform::KeyEllipseEditSample>(edit.samples));
  }
  put_mesh_parts(payload, bound.model.parts);
  put_sweep_choices(payload, bound.sweeps);

  ByteWriter file;
  for (char c : kMagic) file.put(c);
  file.put<std::uint32_t>(kSweepbindVersion);
  file.put<std::uint32_t>(0);  // flags, none defined
  file.put<std::uint64_t>(payload.bytes().size());
  file.put<std::uint32_t>(crc32(payload.bytes()));
  file.put<std::uint32_t>(model_fingerprint(bound.model));
  file.bytes().insert(file.bytes().end(), payload.bytes().begin(), payload.bytes().end());
  return std::move(file.bytes());
}

SweepbindChecksum sweepbind_checksum(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kHeaderSize)
    throw std::invalid_argument("a .sweepbind header is " + std::to_string(kHeaderSize) +
                                " bytes; got " + std::to_string(bytes.size()));
  SweepbindChecksum checksum;
  std::memcpy(&checksum.payload_size, bytes.data() + 16, sizeof checksum.payload_size);
  std::memcpy(&checksum.crc32, bytes.data() + 24, sizeof checksum.crc32);
  return checksum;
}

BoundModel decode_sweepbind(std::span<const std::uint8_t> bytes,
                            const std::filesystem::path& source,
                            const deform::Model* expected_model) {
  ByteReader header(bytes.first(std::min(bytes.size(), kHeaderSize)), source);
  if (std::memcmp(bytes.data(), kMagic, std::min(bytes.size(), sizeof(kMagic))) != 0)
    header.fail("not a .sweepbind file (wrong magic)");
  for (std::size_t i = 0; i < sizeof(kMagic); ++i) header.get<char>("magic");
  const auto version = header.get<std::uint32_t>("version");
  if (version < kOldestReadableVersion || version > kSweepbindVersion)
    header.fail("unsupported .sweepbind version " + std::to_string(version) +
                " (this sweepd reads " + std::to_string(kOldestReadableVersion) + " to " +
                std::to_string(kSweepbindVersion) + "; bind the model again to rebuild it)");
  header.get<std::uint32_t>("flags");
  const auto payload_size = header.get<std::uint64_t>("payload size");
  const auto payload_crc = header.get<std::uint32_t>("payload checksum");
  const auto fingerprint = header.get<std::uint32_t>("model fingerprint");
  const std::span<const std::uint8_t> payload = bytes.subspan(kHeaderSize);
  if (payload.size() != payload_size)
    header.fail(payload.size() < payload_size
                    ? "truncated: the header announces " + std::to_string(payload_size) +
                          " payload bytes, the file has " + std::to_string(payload.size())
                    : "trailing bytes after the payload");
  if (crc32(payload) != payload_crc) header.fail("checksum mismatch: the file is corrupt");
  if (expected_model && model_fingerprint(*expected_model) != fingerprint)
    header.fail("this binding was made for another model (fingerprint mismatch)");

  ByteReader in(payload, source, kHeaderSize);
  BoundModel bound;
  bound.model = get_model(in);
  bound.rig = get_rig(in);
  if (version >= 7) {
    bound.options = in.get<deform::BindOptions>("bind options");
  } else {  // version 6: the paper's linear orientation curve
    const auto old = in.get<std::array<std::uint8_t, kVersion6BindOptionsSize>>("bind options");
    std::memcpy(static_cast<void*>(&bound.options), old.data(), old.size());
    bound.options.orientation_curve = deform::OrientationCurveKind::kLinear;
  }
  const auto sweeps = in.get<std::uint64_t>("sweep count");
  if (sweeps > 64) in.fail("sweep count " + std::to_string(sweeps) + " is out of range");
  for (std::uint64_t s = 0; s < sweeps; ++s) bound.sweeps.push_back(get_sweep(in));
  bound.vertices = in.get_array<deform::VertexBinding>("vertex bindings", kMaxVertices);
  bound.skinned_share_joints = in.get_array<std::array<std::uint16_t, deform::kInfluences>>(
      "skinned share joints", kMaxVertices);
  bound.skinned_share_weights =
      in.get_array<std::array<float, deform::kInfluences>>("skinned share weights", kMaxVertices);
  const auto edits = in.get<std::uint64_t>("edit count");
  if (edits > kMaxEdits) in.fail("edit count " + std::to_string(edits) + " is out of range");
  for (std::uint64_t e = 0; e < edits; ++e) {
    deform::KeyEllipseEdit edit;
    edit.sweep = in.get<std::int32_t>("edit sweep");
    edit.key = in.get<std::int32_t>("edit key");
    edit.joint = in.get<std::int32_t>("edit joint");
    edit.samples = in.get_array<deform::KeyEllipseEditSample>("edit samples", kMaxEditSamples);
    bound.edits.edits.push_back(std::move(edit));
  }
  if (version >= 8) bound.model.parts = get_mesh_parts(in);
  if (version >= 9) {
    get_sweep_choices(in, bound.sweeps);
  } else {  // every sweep as the bind options say
    for (deform::BoundSweep& sweep : bound.sweeps)
      sweep.choice = {.orientation_curve = bound.options.orientation_curve,
                      .keys_per_link = bound.options.intermediate_keys_per_link};
  }
  if (in.remaining() != 0) in.fail("trailing bytes inside the payload");
  if (std::string why = validate(bound); !why.empty()) in.fail("invalid binding: " + why);
  if (std::string why = deform::validate(bound.edits, bound); !why.empty())
    in.fail("invalid key ellipse edits: " + why);
  return bound;
}

void save_sweepbind(const BoundModel& bound, const std::filesystem::path& file) {
  write_file_durably(file, encode_sweepbind(bound));
}

BoundModel load_sweepbind(const std::filesystem::path& file, const deform::Model* expected_model) {
  return decode_sweepbind(read_file_bytes(file), file, expected_model);
}

}  // namespace sweepd::io

// .sweepbind files: bit-exact round trips, and every kind of damage refused with its reason.
#include "io/sweepbind/sweepbind.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "io/files/durable_file.h"
#include "io/sweepbind/byte_stream.h"
#include "mannequin/mannequin.h"
#include "tests/deform/shared_male.h"

namespace sweepd::io {
namespace {

namespace fs = std::filesystem;

const deform::BoundModel& bound_mannequin() {
  static const deform::BoundModel bound = [] {
    mannequin::MannequinOptions options;
    options.target_vertices = 3000;
    const deform::Model model = mannequin::make_mannequin(options);
    return deform::bind(model, deform::detect_rig_map(model.skeleton));
  }();
  return bound;
}

std::string decode_error(const std::vector<std::uint8_t>& bytes,
                         const deform::Model* expected = nullptr) {
  try {
    decode_sweepbind(bytes, "damaged.sweepbind", expected);
  } catch (const LoadError& e) {
    return e.what();
  }
  return "no error";
}

// Version 9's last section: a count, then 17 bytes per sweep.
std::size_t sweep_choices_size(const deform::BoundModel& bound) {
  return 8 + 17 * bound.sweeps.size();
}

// The header's size and checksum made to fit the payload again.
void reseal(std::vector<std::uint8_t>& bytes) {
  const std::uint64_t payload_size = bytes.size() - 32;
  std::memcpy(bytes.data() + 16, &payload_size, sizeof(payload_size));
  const std::uint32_t crc = crc32(std::span<const std::uint8_t>(bytes).subspan(32));
  std::memcpy(bytes.data() + 24, &crc, sizeof(crc));
}

TEST(Sweepbind, RoundTripsBitExactlyThroughAFile) {
  const fs::path file =
      fs::temp_directory_path() / ("roundtrip_" + std::to_string(getpid()) + ".sweepbind");
  save_sweepbind(bound_mannequin(), file);
  EXPECT_FALSE(fs::exists(file.string() + "." + std::to_string(getpid()) + "@" + this_host() +
                          ".tmp"));  // renamed into place
  const deform::BoundModel loaded = load_sweepbind(file, &bound_mannequin().model);
  // Re-encoding what was read gives the same bytes: every field came back bit for bit.
  EXPECT_EQ(encode_sweepbind(loaded), encode_sweepbind(bound_mannequin()));
  EXPECT_EQ(loaded.model.positions.size(), bound_mannequin().model.positions.size());
  EXPECT_EQ(0, std::memcmp(loaded.vertices.data(), bound_mannequin().vertices.data(),
                           loaded.vertices.size() * sizeof(deform::VertexBinding)));
  // The key ellipses too, offsets included; the binding has joint keys with non-zero ones, so
  // the offsets are really carried (a reader that dropped them would fail here).
  int offset_keys = 0;
  ASSERT_EQ(loaded.sweeps.size(), bound_mannequin().sweeps.size());
  for (std::size_t s = 0; s < loaded.sweeps.size(); ++s) {
    const auto& keys = bound_mannequin().sweeps[s].rest_keys;
    ASSERT_EQ(loaded.sweeps[s].rest_keys.size(), keys.size());
    EXPECT_EQ(0, std::memcmp(loaded.sweeps[s].rest_keys.data(), keys.data(),
                             keys.size() * sizeof(deform::KeyEllipse)));
    for (const deform::KeyEllipse& key : keys) offset_keys += key.offset != glm::vec2(0.0f);
  }
  EXPECT_GT(offset_keys, 0);
  // The skinned share's own influences come back too; they differ from the model's at the
  // shoulders, so a reader that fell back on the model's weights would fail here.
  EXPECT_EQ(loaded.skinned_share_joints, bound_mannequin().skinned_share_joints);
  EXPECT_EQ(loaded.skinned_share_weights, bound_mannequin().skinned_share_weights);
  EXPECT_NE(loaded.skinned_share_weights, loaded.model.skin_weights);
  fs::remove(file);
}

TEST(Sweepbind, RefusesAVersion5FileAskingForARebind) {
  // Version 5 had no skinned-share influences: its armpits followed the painted weights.
  std::vector<std::uint8_t> bytes = encode_sweepbind(bound_mannequin());
  bytes[8] = 5;
  const std::string error = decode_error(bytes);
  EXPECT_NE(error.find("unsupported .sweepbind version 5 (this sweepd reads 6 to 9; bind the "
                       "model again to rebuild it)"),
            std::string::npos)
      << error;
}

TEST(Sweepbind, CarriesTheOrientationCurveAndReadsVersion6AsLinear) {
  deform::BoundModel smooth = bound_mannequin();
  smooth.options.orientation_curve = deform::OrientationCurveKind::kSmooth;
  std::vector<std::uint8_t> bytes = encode_sweepbind(smooth);
  EXPECT_EQ(decode_sweepbind(bytes, "smooth.sweepbind").options.orientation_curve,
            deform::OrientationCurveKind::kSmooth);
  // The same file as version 6 wrote it: bind options without their last 4 bytes.
  const auto* options = reinterpret_cast<const std::uint8_t*>(&smooth.options);
  const auto at =
      std::search(bytes.begin() + 32, bytes.end(), options, options + sizeof(deform::BindOptions));
  ASSERT_NE(at, bytes.end());
  bytes.erase(at + 24, at + 28);
  // Nor version 8's mesh parts (a count of 0) and version 9's sweep choices.
  bytes.resize(bytes.size() - 8 - sweep_choices_size(smooth));
  bytes[8] = 6;
  const std::uint64_t payload_size = bytes.size() - 32;
  std::memcpy(bytes.data() + 16, &payload_size, sizeof(payload_size));
  const std::uint32_t crc = crc32(std::span<const std::uint8_t>(bytes).subspan(32));
  std::memcpy(bytes.data() + 24, &crc, sizeof(crc));
  const deform::BoundModel old = decode_sweepbind(bytes, "old.sweepbind");
  EXPECT_EQ(old.options.orientation_curve, deform::OrientationCurveKind::kLinear);
  EXPECT_EQ(old.options.plane_samples_per_span, smooth.options.plane_samples_per_span);
  EXPECT_EQ(encode_sweepbind(old), encode_sweepbind(bound_mannequin()));  // all else as written
  // An orientation curve this reader does not know is refused.
  smooth.options.orientation_curve = static_cast<deform::OrientationCurveKind>(2);
  EXPECT_NE(decode_error(encode_sweepbind(smooth)).find("orientation curve 2"), std::string::npos);
}

TEST(Sweepbind, CarriesEachSweepsChoiceAndReadsVersion8AsTheBindOptions) {
  deform::BoundModel chosen = bound_mannequin();
  ASSERT_GE(chosen.sweeps.size(), 3u);
  chosen.sweeps[2].choice = {.orientation_curve = deform::OrientationCurveKind::kSmooth,
                             .keys_per_link = 1,
                             .origin = deform::SweepChoiceOrigin::kSelfCheck,
                             .worse_before = 7,
                             .worse_after = 2};
  std::vector<std::uint8_t> bytes = encode_sweepbind(chosen);
  const deform::BoundModel read = decode_sweepbind(bytes, "chosen.sweepbind");
  for (std::size_t s = 0; s < read.sweeps.size(); ++s) {
    const deform::SweepChoice& c = read.sweeps[s].choice;
    const deform::SweepChoice& expected = chosen.sweeps[s].choice;
    EXPECT_EQ(c.orientation_curve, expected.orientation_curve) << s;
    EXPECT_EQ(c.keys_per_link, expected.keys_per_link) << s;
    EXPECT_EQ(c.origin, expected.origin) << s;
    EXPECT_EQ(c.worse_before, expected.worse_before) << s;
    EXPECT_EQ(c.worse_after, expected.worse_after) << s;
  }
  EXPECT_EQ(read.sweeps[2].choice.worse_before, 7u);  // not the defaults
  EXPECT_EQ(encode_sweepbind(read), bytes);
  // As version 8 wrote it (no choices): every sweep as the bind options say.
  std::vector<std::uint8_t> old = bytes;
  old.resize(old.size() - sweep_choices_size(chosen));
  old[8] = 8;
  reseal(old);
  const deform::BoundModel v8 = decode_sweepbind(old, "v8.sweepbind");
  for (const deform::BoundSweep& sweep : v8.sweeps) {
    EXPECT_EQ(sweep.choice.orientation_curve, chosen.options.orientation_curve);
    EXPECT_EQ(sweep.choice.keys_per_link, chosen.options.intermediate_keys_per_link);
    EXPECT_EQ(sweep.choice.origin, deform::SweepChoiceOrigin::kBindOptions);
  }
  // Values this reader does not know are refused, each with its reason. The choices are the
  // payload's last bytes: sweep 2's record starts 17 * (count - 2) bytes from the end.
  const std::size_t record = bytes.size() - 17 * (chosen.sweeps.size() - 2);
  std::vector<std::uint8_t> bad = bytes;
  bad[record] = 2;  // orientation curve 2
  reseal(bad);
  EXPECT_NE(decode_error(bad).find("sweep orientation curve 2 is neither"), std::string::npos)
      << decode_error(bad);
  bad = bytes;
  bad[record + 8] = 3;  // origin 3
  reseal(bad);
  EXPECT_NE(decode_error(bad).find("sweep choice origin 3 is neither"), std::string::npos)
      << decode_error(bad);
  bad = bytes;
  bad[record + 7] = 0x80;  // keys per link negative
  reseal(bad);
  EXPECT_NE(decode_error(bad).find("sweep keys per link -2147483647 is out of range"),
            std::string::npos)
      << decode_error(bad);
}

// Bind's default is one link key per link since stop 65; a file bound with two (the default
// before, or --keys-per-link 2) keeps its keys, because each sweep's key count is stored with it
// (SweepChoice::keys_per_link) and its keys are read, not fitted again: it deforms as it did.
TEST(Sweepbind, AFileBoundWithTwoLinkKeysKeepsThemAndDeformsAsBound) {
  const deform::Model model = mannequin::make_mannequin({.target_vertices = 3000});
  deform::BindOptions two_keys;
  two_keys.intermediate_keys_per_link = 2;
  const deform::BoundModel bound =
      deform::bind(model, deform::detect_rig_map(model.skeleton), two_keys);
  ASSERT_NE(deform::BindOptions{}.intermediate_keys_per_link, 2);  // else this proves nothing
  const deform::BoundModel read = decode_sweepbind(encode_sweepbind(bound), "two_keys.sweepbind");
  ASSERT_EQ(read.sweeps.size(), bound.sweeps.size());
  for (const deform::BoundSweep& sweep : read.sweeps) {
    EXPECT_EQ(sweep.choice.keys_per_link, 2) << deform::to_string(sweep.part);
    EXPECT_EQ(sweep.rest_keys.size(), sweep.chain.size() + 2 * (sweep.chain.size() - 1))
        << deform::to_string(sweep.part);
  }
  // Every joint turned 25° about one axis: the same positions to the bit (same keys, same
  // bindings, same arithmetic).
  deform::Pose pose = deform::rest_pose(model.skeleton);
  for (std::size_t j = 1; j < pose.local_rotations.size(); ++j)
    pose.local_rotations[j] =
        pose.local_rotations[j] * glm::angleAxis(glm::radians(25.0f), glm::vec3(1, 0, 0));
  deform::test::Posing as_bound(bound), as_read(read);
  const std::vector<glm::vec3> expected =
      deform::test::deformed(as_bound, pose, deform::DeformMethod::kSweep);
  const std::vector<glm::vec3> got =
      deform::test::deformed(as_read, pose, deform::DeformMethod::kSweep);
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t v = 0; v < got.size(); ++v) ASSERT_EQ(got[v], expected[v]) << "vertex " << v;
}

TEST(Sweepbind, CarriesTheMeshPartsAndRefusesOnesThatDoNotFitTheModel) {
  deform::BoundModel bound = bound_mannequin();
  const auto n = static_cast<std::uint32_t>(bound.model.vertex_count());
  const auto corners = static_cast<std::uint32_t>(bound.model.indices.size());
  bound.model.parts = {
      {.name = "body", .material = "skin", .vertex_count = n, .index_count = corners}};
  EXPECT_EQ(decode_sweepbind(encode_sweepbind(bound), "parts.sweepbind").model.parts,
            bound.model.parts);
  bound.model.parts[0].vertex_count = n - 1;
  EXPECT_NE(decode_error(encode_sweepbind(bound)).find("mesh part 0 ('body')"), std::string::npos);
}

TEST(Sweepbind, RefusesSkinnedShareInfluencesThatDoNotFitTheModel) {
  deform::BoundModel bound = bound_mannequin();
  bound.skinned_share_joints[7][0] = 60000;  // no such joint
  EXPECT_NE(decode_error(encode_sweepbind(bound)).find("vertex 7 has an invalid skinned share"),
            std::string::npos);
  bound = bound_mannequin();
  bound.skinned_share_weights[9][0] += 0.5f;
  EXPECT_NE(decode_error(encode_sweepbind(bound)).find("vertex 9 has skinned share weights"),
            std::string::npos);
  bound = bound_mannequin();
  bound.skinned_share_weights.pop_back();
  EXPECT_NE(decode_error(encode_sweepbind(bound)).find("skinned share influences:"),
            std::string::npos);
}

TEST(Sweepbind, RefusesDamagedFilesWithTheReason) {
  const std::vector<std::uint8_t> good = encode_sweepbind(bound_mannequin());

  std::vector<std::uint8_t> bytes = good;
  bytes[0] = 'X';
  EXPECT_NE(decode_error(bytes).find("wrong magic"), std::string::npos);

  bytes = good;
  bytes[8] = 10;  // version
  EXPECT_NE(decode_error(bytes).find("unsupported .sweepbind version 10"), std::string::npos);

  for (std::size_t keep : {std::size_t{5}, std::size_t{20}, good.size() / 2, good.size() - 1}) {
    bytes.assign(good.begin(), good.begin() + keep);
    EXPECT_NE(decode_error(bytes).find("truncated"), std::string::npos) << keep;
  }

  bytes = good;
  bytes[good.size() / 2] ^= 0x40;
  EXPECT_NE(decode_error(bytes).find("checksum mismatch"), std::string::npos);

  bytes = good;
  bytes.push_back(0);
  EXPECT_NE(decode_error(bytes).find("trailing bytes"), std::string::npos);

  deform::Model other = bound_mannequin().model;
  other.positions[0].x += 0.001f;
  EXPECT_NE(decode_error(good, &other).find("another model"), std::string::npos);

  EXPECT_NE(decode_error(good).find("no error"), std::string::npos);
}

TEST(Sweepbind, RefusesWellFormedFilesWithInvalidContent) {
  // A valid checksum over bad values (a buggy or hostile writer) is still refused.
  deform::BoundModel bad = bound_mannequin();
  bad.vertices[7].coordinate[0].t = std::nanf("");
  bad.vertices[7].sweep[0] = 0;
  EXPECT_NE(decode_error(encode_sweepbind(bad)).find("vertex 7 has an invalid sweep binding"),
            std::string::npos);
  bad = bound_mannequin();
  bad.sweeps[1].rest_keys[0].a = -1.0f;
  EXPECT_NE(decode_error(encode_sweepbind(bad)).find("non-positive half-axis"), std::string::npos);
  bad = bound_mannequin();
  bad.vertices.pop_back();
  EXPECT_NE(decode_error(encode_sweepbind(bad)).find("binding count"), std::string::npos);
}

// The checksum a server keys a binding's derived data by (server/models/self_check_sidecar.h):
// the header's payload CRC-32 and size, so one key names one binding's bytes.
TEST(Sweepbind, ItsChecksumIsTheHeadersPayloadCrcAndSize) {
  const std::vector<std::uint8_t> bytes = encode_sweepbind(bound_mannequin());
  const SweepbindChecksum checksum = sweepbind_checksum(bytes);
  EXPECT_EQ(checksum.payload_size, bytes.size() - 32);
  EXPECT_EQ(checksum.crc32, crc32(std::span<const std::uint8_t>(bytes).subspan(32)));
  deform::BoundModel edited = bound_mannequin();
  edited.sweeps[0].rest_keys[0].a *= 1.5f;  // one half-axis: another binding, another key
  EXPECT_NE(sweepbind_checksum(encode_sweepbind(edited)), checksum);
  EXPECT_THROW(sweepbind_checksum(std::span(bytes).first(31)), std::invalid_argument);
}

TEST(Sweepbind, MissingFileNamesIt) {
  try {
    load_sweepbind("/nonexistent/dir/model.sweepbind");
    FAIL() << "no error";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("model.sweepbind"), std::string::npos);
  }
}

}  // namespace
}  // namespace sweepd::io

// Key-ellipse edits as JSON and inside .sweepbind files, on the shared male: a written file
// reads back to the same edits, bad files are refused with the file and the reason, and a
// .sweepbind keeps its edits through encode/decode.
#include "io/json/key_ellipse_edits_json.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "io/files/load_error.h"
#include "io/sweepbind/sweepbind.h"
#include "tests/deform/shared_male.h"
#include "tests/scratch_directory.h"

namespace sweepd::io {
namespace {

namespace fs = std::filesystem;
using deform::BodyPart;

fs::path write_temp(const std::string& name, const std::string& text) {
  const fs::path file = sweepd::test::process_scratch("key_ellipse_edits") / name;
  std::ofstream(file) << text;
  return file;
}

std::string load_error(const deform::BoundModel& bound, const std::string& text) {
  const fs::path file = write_temp("bad_edits.json", text);
  try {
    load_key_ellipse_edits_json(file, bound);
  } catch (const LoadError& e) {
    return e.what();
  }
  return "";
}

TEST(KeyEllipseEditsJson, ReadsTheDocumentedFormatAndWritesItBack) {
  using namespace sweepd::deform;
  REQUIRE_SHARED_MALE();
  const fs::path file = write_temp("edits.json", R"({"edits": [
      {"part": "left arm", "key": 1, "joint": "LeftArm",
       "samples": [{"angle": 120, "rotation": [0, 0, 30]},
                   {"angle": 60, "offset": [0, 0.01, 0], "scale": [1.0, 1.1]}]}]})");
  const KeyEllipseEdits edits = load_key_ellipse_edits_json(file, male);
  ASSERT_EQ(edits.edits.size(), 1u);
  const KeyEllipseEdit& e = edits.edits[0];
  EXPECT_EQ(e.sweep, deform::test::sweep_of(male, BodyPart::kLeftArm));
  EXPECT_EQ(e.key, 1);
  EXPECT_EQ(e.joint, male.model.skeleton.find("LeftArm"));
  ASSERT_EQ(e.samples.size(), 2u);
  EXPECT_EQ(e.samples[0].angle_degrees, 60.0f);  // sorted
  EXPECT_EQ(e.samples[0].correction.offset.y, 0.01f);
  EXPECT_EQ(e.samples[0].correction.scale_b, 1.1f);
  EXPECT_EQ(e.samples[1].correction.rotation.z, 30.0f);
  EXPECT_EQ(e.samples[1].correction.scale_a, 1.0f);  // left out: 1

  const fs::path copy = sweepd::test::process_scratch("key_ellipse_edits") / "copy.json";
  save_key_ellipse_edits_json(edits, male, copy);
  const KeyEllipseEdits again = load_key_ellipse_edits_json(copy, male);
  ASSERT_EQ(again.edits.size(), 1u);
  ASSERT_EQ(again.edits[0].samples.size(), 2u);
  for (int s = 0; s < 2; ++s)
    EXPECT_EQ(0, std::memcmp(&again.edits[0].samples[s], &e.samples[s], sizeof e.samples[s]));
}

TEST(KeyEllipseEditsJson, RefusesBadFilesNamingTheProblem) {
  REQUIRE_SHARED_MALE();
  using deform::BoundModel;
  auto expect = [&](const std::string& text, const std::string& reason) {
    const std::string message = load_error(male, text);
    EXPECT_NE(message.find("bad_edits.json"), std::string::npos) << message;
    EXPECT_NE(message.find(reason), std::string::npos) << message;
  };
  expect("not json", "bad_edits.json");
  expect(R"({})", "missing \"edits\"");
  expect(R"({"edits": [{"part": "tail", "key": 0, "joint": "LeftArm", "samples": []}]})",
         "no sweep for part 'tail'");
  expect(R"({"edits": [{"part": "left arm", "key": 0, "joint": "Nope", "samples": []}]})",
         "no joint named 'Nope'");
  expect(R"({"edits": [{"part": "left arm", "key": 99, "joint": "LeftArm",
                        "samples": [{"angle": 10}]}]})",
         "key 99 out of range");
  expect(R"({"edits": [{"part": "left arm", "key": 0, "joint": "LeftArm",
                        "samples": [{"angle": 10, "scale": [1]}]}]})",
         "expected 2 numbers");
}

TEST(KeyEllipseEditsJson, SweepbindFilesKeepTheirEdits) {
  using namespace sweepd::deform;
  REQUIRE_SHARED_MALE();
  BoundModel bound = male;
  KeyEllipseEdit edit;
  edit.sweep = deform::test::sweep_of(male, BodyPart::kRightLeg);
  edit.key = 2;
  edit.joint = male.rig.right_leg.lower;
  edit.samples.push_back({90.0f, {{0.0f, 0.0f, 0.01f}, {5.0f, 0.0f, 0.0f}, 1.05f, 0.95f}});
  bound.edits.edits.push_back(edit);
  const BoundModel back = decode_sweepbind(encode_sweepbind(bound), "memory.sweepbind");
  ASSERT_EQ(back.edits.edits.size(), 1u);
  EXPECT_EQ(back.edits.edits[0].sweep, edit.sweep);
  EXPECT_EQ(back.edits.edits[0].key, edit.key);
  EXPECT_EQ(back.edits.edits[0].joint, edit.joint);
  ASSERT_EQ(back.edits.edits[0].samples.size(), 1u);
  EXPECT_EQ(0,
            std::memcmp(&back.edits.edits[0].samples[0], &edit.samples[0], sizeof edit.samples[0]));
  // An edit that does not fit is refused on reading, with the reason.
  bound.edits.edits[0].samples[0].correction.scale_a = -1.0f;
  try {
    decode_sweepbind(encode_sweepbind(bound), "memory.sweepbind");
    ADD_FAILURE() << "a negative scale was accepted";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("scales must be positive"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sweepd::io

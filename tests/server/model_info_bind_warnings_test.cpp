// ModelInfo carries the binding's self-check (protocol 1.14, issue 47 item 3): the regions where
// the sweep is still worse than skinning on the model's range of motion, with their figures and
// in words. The words are the very lines `sweepctl bind` prints: both run
// selfcheck::check_binding on the same binding (the daemon's bind options are sweepctl's
// defaults, and the check is deterministic), so the texts are compared for equality, not
// approximately. A stored model's ModelInfo after a restart carries them too (the daemon reads
// the verdicts stored beside the binding: server/models/self_check_sidecar.h), and so does the
// default mannequin's.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "mannequin/mannequin.h"
#include "selfcheck/binding_self_check.h"
#include "server/replies/model_info.h"
#include "tests/scratch_directory.h"
#include "tests/server/daemon_process.h"
#include "tests/server/sweepctl_remote.h"

// Its own namespace: the file is compiled in a batch with others (tests/CMakeLists.txt), whose
// anonymous names would otherwise meet these.
namespace sweepd::test::model_info_bind_warnings {
namespace {

namespace pb = sweepd::protocol;

const pb::ModelInfo* load_model(FrameClient& client, const std::string& name,
                                const std::vector<std::uint8_t>& bytes) {
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(pb::finish_message(
      builder, pb::CreateLoadModelDirect(builder, name.c_str(), bytes.empty() ? nullptr : &bytes),
      31));
  return client.receive_as<pb::ModelInfo>();
}

// One warning as read off the wire (the ModelInfo is gone after the next receive).
struct Warning {
  std::string region, baseline, pose, flipped_pose, text;
  unsigned worse_poses = 0, extra_flipped = 0;
  float sweep = 0.0f, baseline_stretch = 0.0f;
  bool operator==(const Warning&) const = default;
};

struct Checked {
  unsigned poses = 0;
  std::vector<Warning> warnings;
};

Checked read_check(const pb::ModelInfo& info) {
  Checked checked{info.self_check_poses(), {}};
  if (!info.bind_warnings()) return checked;
  const auto text = [](const flatbuffers::String* s) { return s ? s->str() : std::string(); };
  for (const pb::BindWarning* w : *info.bind_warnings())
    checked.warnings.push_back({text(w->region()), text(w->baseline()), text(w->pose()),
                                text(w->flipped_pose()), text(w->text()), w->worse_poses(),
                                w->extra_flipped(), w->sweep_stretch(), w->baseline_stretch()});
  return checked;
}

std::vector<std::string> texts(const Checked& checked) {
  std::vector<std::string> lines;
  for (const Warning& w : checked.warnings) lines.push_back(w.text);
  return lines;
}

// The warning lines `sweepctl bind` prints ("  warning: TEXT"), TEXT alone.
std::vector<std::string> printed_warnings(const std::string& output) {
  std::vector<std::string> lines;
  std::size_t at = 0;
  const std::string mark = "  warning: ";
  while ((at = output.find(mark, at)) != std::string::npos) {
    const std::size_t end = output.find('\n', at);
    lines.push_back(output.substr(at + mark.size(), end - at - mark.size()));
    at = end;
  }
  return lines;
}

// The structured fields say what the text says, and the sweep really is worse there.
void expect_consistent(const Checked& checked) {
  for (const Warning& w : checked.warnings) {
    EXPECT_TRUE(w.text.starts_with(w.region + ": worse than skinning in " +
                                   std::to_string(w.worse_poses) + " of " +
                                   std::to_string(checked.poses) + " poses"))
        << w.text;
    EXPECT_GT(w.worse_poses, 0u) << w.text;
    EXPECT_LE(w.worse_poses, checked.poses) << w.text;
    if (w.sweep > 0.0f) {
      // Worse means above 1.02 times the better baseline (the self-check's tolerance); the
      // text rounds both ratios to 2 decimals, as printed here.
      EXPECT_GT(w.sweep, 1.02f * w.baseline_stretch) << w.text;
      EXPECT_TRUE(w.baseline == "LBS" || w.baseline == "DQS") << w.baseline;
      char figures[160];
      std::snprintf(figures, sizeof figures, "stretches an edge %.2fx where %s stretches it %.2fx (%s)",
                    w.sweep, w.baseline.c_str(), w.baseline_stretch, w.pose.c_str());
      EXPECT_NE(w.text.find(figures), std::string::npos) << w.text << " / " << figures;
    } else {
      EXPECT_TRUE(w.baseline.empty() && w.pose.empty()) << w.text;
    }
    if (w.extra_flipped > 0) {
      EXPECT_NE(w.text.find(w.flipped_pose), std::string::npos) << w.text;
    }
  }
}

// The shared male uploaded to a daemon on `directory` (whose store stays there), which then
// stops: his ModelInfo's self-check; none (0 poses) when the daemon did not answer.
Checked upload_male(const fs::path& directory) {
  DaemonProcess daemon(directory, {"--mannequin-vertices", "1000"});
  if (!daemon.running()) {
    ADD_FAILURE() << daemon.log();
    return {};
  }
  FrameClient client(daemon.port());
  EXPECT_NE(client.hello(""), nullptr);
  const pb::ModelInfo* info = load_model(client, "male", read_bytes(kSharedMale));
  if (info == nullptr) ADD_FAILURE() << daemon.log();
  return info ? read_check(*info) : Checked{};
}

bool has_region(const Checked& checked, const std::string& region) {
  for (const Warning& w : checked.warnings)
    if (w.region == region) return true;
  return false;
}

TEST(ModelInfoBindWarnings, AnUploadedMaleCarriesTheWarningsSweepctlBindPrints) {
  if (!fs::exists(kSharedMale)) GTEST_SKIP() << "shared data absent: " << kSharedMale;
  const ScratchDirectory directory("model_info_bind_warnings");
  const ClientRun bind =
      run_sweepctl("bind " + kSharedMale.string() + " -o " + (directory / "male.sweepbind").string());
  ASSERT_EQ(bind.exit_code, 0) << bind.output;
  const std::vector<std::string> printed = printed_warnings(bind.output);
  ASSERT_FALSE(printed.empty()) << bind.output;

  const Checked checked = upload_male(directory);
  EXPECT_EQ(checked.poses, 48u);  // the male's rig map has every role: 48 moves
  EXPECT_EQ(texts(checked), printed);
  // The male loses at the arms (elbow flexion 150°) and the neck (docs/quality/).
  for (const char* region : {"left arm", "right arm", "neck"})
    EXPECT_TRUE(has_region(checked, region)) << region;
  expect_consistent(checked);
}

TEST(ModelInfoBindWarnings, ARestartedDaemonsStoredModelCarriesThemToo) {
  if (!fs::exists(kSharedMale)) GTEST_SKIP() << "shared data absent: " << kSharedMale;
  const ScratchDirectory directory("model_info_bind_warnings_restart");
  const Checked uploaded = upload_male(directory);
  ASSERT_FALSE(uploaded.warnings.empty());
  DaemonProcess restarted(directory, {"--mannequin-vertices", "1000"});
  ASSERT_TRUE(restarted.running()) << restarted.log();
  FrameClient client(restarted.port());
  ASSERT_NE(client.hello(""), nullptr);
  const pb::ModelInfo* info = load_model(client, "male", {});  // by name: the store's
  ASSERT_NE(info, nullptr) << restarted.log();
  // Read from the store beside the binding, which is the uploaded one bit for bit: the same
  // verdicts, figures included, exactly.
  EXPECT_EQ(read_check(*info).poses, uploaded.poses);
  EXPECT_EQ(read_check(*info).warnings, uploaded.warnings);
  // And the operator hears each at the restore (the log's keys are in alphabetical order).
  const std::string log = restarted.log();
  const std::size_t restored = log.find("\"event\":\"model_restored\"");
  ASSERT_NE(restored, std::string::npos) << log;
  for (const Warning& w : uploaded.warnings) {
    const std::size_t at = log.find("\"warning\":\"" + w.text + "\"", restored);
    ASSERT_NE(at, std::string::npos) << w.text << "\n" << log;
    const std::size_t line = log.rfind('\n', at) + 1;  // npos + 1: the first line
    EXPECT_TRUE(log.compare(line, 37, "{\"event\":\"bind_warning\",\"name\":\"male\"") == 0)
        << log.substr(line, at - line);
  }
}

// The default mannequin checks itself at start-up too, bound as an upload is (adapted): its
// ModelInfo says it was checked, with the warnings the library gives for the same mannequin
// bound so.
TEST(ModelInfoBindWarnings, TheDefaultMannequinIsCheckedToo) {
  const ScratchDirectory directory("model_info_bind_warnings_mannequin");
  DaemonProcess daemon(directory, {"--mannequin-vertices", "1000"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  FrameClient client(daemon.port());
  ASSERT_NE(client.hello(""), nullptr);
  const pb::ModelInfo* info = load_model(client, "mannequin", {});
  ASSERT_NE(info, nullptr) << daemon.log();
  const Checked checked = read_check(*info);
  const deform::Model model = mannequin::make_mannequin({.target_vertices = 1000});
  const selfcheck::BindingVerdict verdict =
      selfcheck::bind_checked(model, deform::detect_rig_map(model.skeleton), {}, true).verdict;
  EXPECT_EQ(checked.poses, verdict.pose_names.size());
  EXPECT_GT(checked.poses, 0u);
  EXPECT_EQ(texts(checked), selfcheck::self_check_warnings(verdict));
  expect_consistent(checked);
  EXPECT_NE(daemon.log().find("\"self_check_time_ns\":"), std::string::npos) << daemon.log();
}

// build_model_info writes the model's SelfCheck field for field; a model not checked says 0
// poses and no warnings (what a client also reads from a server before 1.14).
TEST(ModelInfoBindWarnings, BuildModelInfoWritesTheSelfCheckFieldForField) {
  server::RegisteredModel registered{
      .id = 7, .content_id = std::string(64, 'a'), .name = "body", .bound = {}, .bind_time_ns = 0};
  const auto built = [&registered] {
    flatbuffers::FlatBufferBuilder builder;
    server::build_model_info(builder, registered, 1);
    return read_check(*pb::GetSizePrefixedMessage(builder.GetBufferPointer())->body_as_ModelInfo());
  };
  const Checked unchecked = built();
  EXPECT_EQ(unchecked.poses, 0u);
  EXPECT_TRUE(unchecked.warnings.empty());

  selfcheck::RegionWarning arm;
  arm.region = "left arm", arm.worse_poses = 7, arm.pose_count = 48, arm.sweep = 5.03,
  arm.baseline = 3.58, arm.baseline_name = "LBS", arm.pose = "elbow flexion 150°",
  arm.extra_flipped = 2, arm.flipped_pose = "shoulder flexion 180°", arm.text = "left arm: ...";
  registered.self_check = {.poses = 48, .warnings = {arm}};
  const Checked checked = built();
  EXPECT_EQ(checked.poses, 48u);
  ASSERT_EQ(checked.warnings.size(), 1u);
  EXPECT_EQ(checked.warnings[0],
            (Warning{"left arm", "LBS", "elbow flexion 150°", "shoulder flexion 180°",
                     "left arm: ...", 7, 2, 5.03f, 3.58f}));
}

}  // namespace
}  // namespace sweepd::test::model_info_bind_warnings

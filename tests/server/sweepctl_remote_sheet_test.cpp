// Contact sheets drawn by the daemon (ContactSheetRequest, protocol 1.11): `sweepctl --server
// sheet` of the uploaded shared male writes the same PNG, byte for byte, as `sweepctl sheet` here
// (the same code and renderer), with sweep+features' pairs from the daemon's backend, a close-up
// with the stretch heat map and a turned camera; the daemon refuses a bad request with the field
// named and keeps serving; --video with --server is a usage error.
#include <gtest/gtest.h>

#include <algorithm>

#include "client/clip_upload.h"
#include "client/connection.h"
#include "io/files/file_bytes.h"
#include "protocol/messages.h"
#include "tests/server/sweepctl_remote.h"

namespace sweepd::test {
namespace {

namespace pb = sweepd::protocol;

// The printed table of each cell's shortest and longest edge: from its header to the collision
// line (which says where the pairs were found) or the time taken.
std::string stretch_table(const std::string& output) {
  const std::size_t start = output.find("shortest and longest edge");
  const std::size_t end = std::min(output.find("\ncollision", start), output.find("took ", start));
  return start == std::string::npos ? "" : output.substr(start, end - start);
}

class SweepctlRemoteSheet : public SweepctlRemote {
 protected:
  static void expect_the_local_sheet(const std::string& sheet_arguments, const std::string& name);
};

void SweepctlRemoteSheet::expect_the_local_sheet(const std::string& sheet_arguments,
                                                 const std::string& name) {
  const ClientRun local =
      run_sweepctl(sheet_arguments + " -o " + path(name + "_local.png").string());
  ASSERT_EQ(local.exit_code, 0) << local.output;
  const ClientRun remote =
      run_sweepctl(server() + " " + sheet_arguments + " -o " + path(name + "_remote.png").string());
  ASSERT_EQ(remote.exit_code, 0) << remote.output << log();
  EXPECT_NE(remote.output.find("sweepd at 127.0.0.1:"), std::string::npos) << remote.output;

  // The same bound model, clip frames, deformations, cameras and rasteriser (llvmpipe on both
  // sides here), encoded by the same PNG writer: identical files, not merely similar ones.
  const std::vector<char> local_png = file_bytes(path(name + "_local.png"));
  EXPECT_GT(local_png.size(), 5'000u) << "a picture of several shaded cells";
  EXPECT_TRUE(local_png == file_bytes(path(name + "_remote.png")))
      << "the daemon's sheet differs from the local one";
  EXPECT_EQ(stretch_table(remote.output), stretch_table(local.output)) << remote.output;
  EXPECT_FALSE(stretch_table(remote.output).empty()) << remote.output;
}

TEST_F(SweepctlRemoteSheet, DaemonSheetEqualsTheLocalSheetByteForByte) {
  // 197: a deep crouch, 600: standing; sweep+features runs folding on the daemon's backend.
  expect_the_local_sheet(
      "sheet " + kSharedMale.string() + " --bvh " + kClip.string() +
          " --frames 197,600 --methods sweep,lbs,dqs,sweep+features --cell 96x128",
      "body");
}

TEST_F(SweepctlRemoteSheet, DaemonCloseUpWithHeatEqualsTheLocalOne) {
  expect_the_local_sheet("sheet " + kSharedMale.string() + " --bvh " + kClip.string() +
                             " --frames 1257 --methods sweep,lbs --cell 80x96 --focus elbow_l"
                             " --heat stretch --heat-scale 50 --azimuth 30 --elevation 10",
                         "elbow");
}

TEST_F(SweepctlRemoteSheet, SheetVideoIsDrawnHereOnly) {
  const ClientRun run =
      run_sweepctl(server() + " sheet " + kSharedMale.string() + " --bvh " + kClip.string() +
                   " --frames 1 --video " + path("sheet.mp4").string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--video is drawn here, not on a server"), std::string::npos)
      << run.output;
}

// A ContactSheetRequest on the mannequin the daemon holds; `edit` changes the valid request.
struct SheetFields {
  std::uint32_t model_id = 0;
  std::string clip_id;
  std::vector<std::uint32_t> frames = {10};
  std::vector<std::string> methods = {"sweep"};
  std::uint16_t cell_width = 64, cell_height = 64;
  std::string focus;
  float heat_full_scale = 1.0f, azimuth = 0.0f, elevation = 0.0f;
};

void send_sheet_request(client::Connection& connection, const SheetFields& f) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  const auto request = pb::CreateContactSheetRequest(
      builder, f.model_id, builder.CreateString(f.clip_id), builder.CreateVector(f.frames),
      builder.CreateVectorOfStrings(f.methods), f.cell_width, f.cell_height,
      builder.CreateString(f.focus), false, f.heat_full_scale, f.azimuth, f.elevation);
  connection.send(pb::finish_message(builder, request));
}

TEST_F(SweepctlRemoteSheet, DaemonRefusesABadSheetRequestNamingTheFieldAndKeepsServing) {
  client::Connection connection("127.0.0.1", std::to_string(port()));
  const pb::Welcome& welcome = connection.hello(kRemoteTestToken, "sheet refusals");
  std::vector<std::string> capabilities;
  for (const auto* c : *welcome.capabilities()) capabilities.push_back(c->str());
  EXPECT_NE(std::find(capabilities.begin(), capabilities.end(), "contact_sheet"),
            capabilities.end());
  SheetFields valid;
  valid.model_id = mannequin_id();
  valid.clip_id = client::upload_clip(connection, "cmu_01_01", io::read_file_text(kClip), 0.056444f)
                      .clip_id()
                      ->str();

  struct Refusal {
    const char* what;
    std::function<void(SheetFields&)> edit;
    pb::ErrorCode code;
    const char* message;
  };
  const std::vector<Refusal> refusals = {
      {"unknown model", [](SheetFields& f) { f.model_id = 12345; }, pb::ErrorCode::UnknownModel,
       "no model with id 12345"},
      {"unknown clip", [](SheetFields& f) { f.clip_id = "feed"; }, pb::ErrorCode::UnknownClip,
       "no clip with id 'feed'"},
      {"no frames", [](SheetFields& f) { f.frames.clear(); }, pb::ErrorCode::InvalidArgument,
       "0 frames: a sheet has 1 to 32 rows"},
      {"33 frames", [](SheetFields& f) { f.frames.assign(33, 1); }, pb::ErrorCode::InvalidArgument,
       "33 frames: a sheet has 1 to 32 rows"},
      {"frame past the end",
       [](SheetFields& f) {
         f.frames = {1, 999999};
       },
       pb::ErrorCode::InvalidArgument, "frame 999999 is past the end of clip 'cmu_01_01'"},
      {"unknown method",
       [](SheetFields& f) {
         f.methods = {"sweep", "blend"};
       },
       pb::ErrorCode::InvalidArgument, "unknown method 'blend' (methods: dqs, lbs, sweep"},
      {"small cell", [](SheetFields& f) { f.cell_width = 63; }, pb::ErrorCode::InvalidArgument,
       "a cell of 63 x 64 pixels: each side must be 64 to 2048"},
      {"too many pixels",
       [](SheetFields& f) {
         f.cell_width = f.cell_height = 2048;
         f.frames.assign(8, 1);
       },
       pb::ErrorCode::InvalidArgument, "pixels (8 rows x 1 columns of cells): a sheet has at most"},
      {"unknown focus", [](SheetFields& f) { f.focus = "elbow"; }, pb::ErrorCode::InvalidArgument,
       "unknown focus 'elbow' (focus: ankle_l"},
      {"NaN heat scale", [](SheetFields& f) { f.heat_full_scale = std::nanf(""); },
       pb::ErrorCode::InvalidArgument, "heat_full_scale nan must be a positive number"},
      {"elevation", [](SheetFields& f) { f.elevation = 90.0f; }, pb::ErrorCode::InvalidArgument,
       "elevation 90.000000 degrees: it must be -80 to 80"},
  };
  for (const Refusal& refusal : refusals) {
    SheetFields fields = valid;
    refusal.edit(fields);
    send_sheet_request(connection, fields);
    try {
      connection.expect<pb::ContactSheet>();
      ADD_FAILURE() << refusal.what << ": answered with a sheet";
    } catch (const client::ServerError& error) {
      EXPECT_EQ(error.code(), refusal.code) << refusal.what << ": " << error.what();
      EXPECT_NE(std::string(error.what()).find(refusal.message), std::string::npos)
          << refusal.what << ": " << error.what();
    }
  }
  // Still serving on the same connection: the valid request gets its picture.
  send_sheet_request(connection, valid);
  const pb::ContactSheet& sheet = connection.expect<pb::ContactSheet>();
  EXPECT_EQ(sheet.model_id(), mannequin_id());
  EXPECT_EQ(sheet.width(), 64u);
  EXPECT_EQ(sheet.height(), 64u);
  ASSERT_NE(sheet.png(), nullptr);
  const std::array<std::uint8_t, 8> signature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  ASSERT_GE(sheet.png()->size(), signature.size());
  EXPECT_TRUE(std::equal(signature.begin(), signature.end(), sheet.png()->begin()));
  ASSERT_NE(sheet.shortest_edge_ratio(), nullptr);
  ASSERT_NE(sheet.longest_edge_ratio(), nullptr);
  ASSERT_EQ(sheet.shortest_edge_ratio()->size(), 1u);
  ASSERT_EQ(sheet.longest_edge_ratio()->size(), 1u);
  // Length ratios l / l_rest, as the local sheet measures them: the shortest edge not collapsed
  // to a point and the longest within the quality tests' 3x bound for every frame, and
  // 1.11-1.15's worst_stretch the larger of their changes (float rounding: 1e-6).
  const float shortest = sheet.shortest_edge_ratio()->Get(0);
  const float longest = sheet.longest_edge_ratio()->Get(0);
  EXPECT_GT(shortest, 0.0f);
  EXPECT_LE(shortest, 1.0f);
  EXPECT_GE(longest, 1.0f);
  EXPECT_LE(longest, 3.0f);
  ASSERT_NE(sheet.worst_stretch(), nullptr);
  ASSERT_EQ(sheet.worst_stretch()->size(), 1u);
  EXPECT_NEAR(sheet.worst_stretch()->Get(0), std::max(longest - 1.0f, 1.0f - shortest), 1e-6f);
}

// A sheet's working memory counts against the server's work budget for all clients (issue 16's
// bounded memory, issue 49's work budget): on a daemon with 64 MiB of it (the clip's 2 MB upload
// and its decoding fit), a sheet of one 1024 x 1024 cell (work_size.h: 8 bytes a pixel, the PNG's
// bound of 4.2 MB five times, 40 bytes a cell pixel: 73.9 MB) is refused as ResourceExhausted
// before any work, and a small one is still drawn.
TEST_F(SweepctlRemoteSheet, APictureOverTheWorkBudgetIsRefusedAndASmallOneIsDrawn) {
  const fs::path directory = path("budget");
  fs::create_directories(directory);
  DaemonProcess daemon(directory, {"--work-budget-bytes", "67108864"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  client::Connection connection("127.0.0.1", std::to_string(daemon.port()));
  connection.hello("", "sheet budget");
  SheetFields fields;
  fields.model_id = daemon.model_id();
  fields.clip_id =
      client::upload_clip(connection, "cmu_01_01", io::read_file_text(kClip)).clip_id()->str();
  fields.cell_width = fields.cell_height = 1024;  // 4 MiB of RGBA
  send_sheet_request(connection, fields);
  try {
    connection.expect<pb::ContactSheet>();
    ADD_FAILURE() << "a picture over the budget was drawn";
  } catch (const client::ServerError& error) {
    EXPECT_EQ(error.code(), pb::ErrorCode::ResourceExhausted) << error.what();
    EXPECT_NE(std::string(error.what()).find("contact sheet: needs 73,9"), std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("--work-budget-bytes 67,108,864"), std::string::npos)
        << error.what();
  }
  fields.cell_width = fields.cell_height = 64;
  send_sheet_request(connection, fields);
  EXPECT_EQ(connection.expect<pb::ContactSheet>().width(), 64u) << daemon.log();
}

}  // namespace
}  // namespace sweepd::test

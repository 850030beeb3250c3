// Issue 49 item 2: requests' working memory in one budget. A daemon with a 512 MiB work budget
// and 8 workers (as on an 8-core host), eight clients at once asking for the largest work a
// 64 MiB frame lets through: six ask for two position maps in a row of 1536 x 1536 with
// positions, float32 normals and coverage (66 MB of EXR; work_size.h estimates 446 MB each),
// two for a contact sheet of one 2048 x 2048 cell (296 MB each); each then a pose with normals.
// Every request is answered or refused by name (ResourceExhausted naming the bytes and the
// budget), none is lost, and the daemon's peak resident size (VmHWM) stays within the budget
// plus a base of 300 MB (the target: the mannequin, threads, libraries and Mesa's
// llvmpipe); /metrics counts the refusals and ends with every reservation given back. Before
// the budget, main's daemon (cc4c762) answered all 22 at a peak of 1,512 MB.
#include <gtest/gtest.h>

#include <barrier>
#include <chrono>
#include <fstream>
#include <mutex>
#include <thread>

#include "io/files/file_bytes.h"
#include "io/gltf/gltf_save.h"
#include "mannequin/mannequin.h"
#include "tests/scratch_directory.h"
#include "tests/server/daemon_process.h"
#include "tests/server/http_probe.h"
#include "tests/server/pose_frames.h"

namespace sweepd::test {
namespace {

constexpr std::uint64_t kBudgetBytes = 512ull << 20;
constexpr std::uint64_t kBaseBytes = 300ull << 20;
constexpr std::uint32_t kMapSide = 1536;   // 28 bytes a texel: 66.1 MB, within 64 MiB frames
constexpr std::uint16_t kSheetCell = 2048;  // the largest cell

// A field of /proc/PID/status in bytes ("VmHWM:  123 kB").
std::uint64_t status_bytes(pid_t pid, const std::string& field) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line))
    if (line.starts_with(field + ":")) return std::stoull(line.substr(field.size() + 1)) * 1024;
  ADD_FAILURE() << field << " not in /proc/" << pid << "/status";
  return 0;
}

struct Outcomes {
  std::mutex mutex;
  int answered = 0, refused = 0;
  std::vector<std::string> unexpected;
  std::vector<std::string> refusals;
};

// The next reply: the `Expected` body (answered), or a ResourceExhausted naming the work budget
// (refused); anything else is recorded as unexpected.
template <typename Expected>
void read_outcome(FrameClient& client, const std::string& what, Outcomes& outcomes) {
  const protocol::Message* message = client.receive();
  std::lock_guard lock(outcomes.mutex);
  if (message == nullptr) {
    outcomes.unexpected.push_back(what + ": no reply");
  } else if (message->body_as<Expected>() != nullptr) {
    ++outcomes.answered;
  } else if (const protocol::Error* error = message->body_as_Error();
             error != nullptr && error->code() == protocol::ErrorCode::ResourceExhausted &&
             error->message()->str().find("bytes of working memory, over") != std::string::npos) {
    ++outcomes.refused;
    outcomes.refusals.push_back(error->message()->str());
  } else {
    outcomes.unexpected.push_back(what + ": " + protocol::EnumNameBody(message->body_type()) +
                                  (message->body_as_Error() ? " " + message->body_as_Error()->message()->str() : ""));
  }
}

// The /metrics page once every reservation is given back (the last one a moment after its
// reply goes out), or after 10 s.
std::string metrics_once_work_is_given_back(int http_port) {
  std::string page = curl_get(http_port, "/metrics").body;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (metric(page, "sweepd_work_bytes") != 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    page = curl_get(http_port, "/metrics").body;
  }
  return page;
}

TEST(DaemonWorkBudget, TheLargestValidWorkFromManyClientsStaysWithinTheBudgetOrIsRefusedByName) {
  const fs::path directory = fresh_directory("work_budget");
  const fs::path http_port_file = directory / "http_port";
  DaemonProcess daemon(directory, {"--work-budget-bytes", std::to_string(kBudgetBytes),
                                   "--work-budget-client-bytes", std::to_string(kBudgetBytes),
                                   "--worker-threads", "8", "--http-listen", "127.0.0.1:0",
                                   "--http-port-file", http_port_file.string()});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  const int http_port = std::stoi(read_text(http_port_file));
  const std::string clip = io::read_file_text(fs::path(SWEEPD_SHARED_DATA) / "motion" / "cmu_01_01.bvh");
  const std::vector<protocol::Quat> rotations = to_wire(bent_rotations(31));
  const std::uint64_t resident_at_rest = status_bytes(daemon.pid(), "VmRSS");

  constexpr int kClients = 8;
  const auto asks_for_a_sheet = [](int client) { return client % 4 == 1; };
  std::vector<std::unique_ptr<FrameClient>> clients;
  std::vector<std::string> clip_ids(kClients);
  for (int c = 0; c < kClients; ++c) {
    clients.push_back(std::make_unique<FrameClient>(daemon.port()));
    ASSERT_NE(clients.back()->hello(""), nullptr);
    if (asks_for_a_sheet(c)) {  // the sheets' clients upload the clip first
      flatbuffers::FlatBufferBuilder builder;
      clients.back()->send_bytes(protocol::finish_message(
          builder, protocol::CreateUploadClipDirect(builder, "cmu_01_01.bvh", clip.c_str()), 1));
      const protocol::ClipInfo* info = clients.back()->receive_as<protocol::ClipInfo>();
      ASSERT_NE(info, nullptr);
      clip_ids[c] = info->clip_id()->str();
    }
  }

  Outcomes outcomes;
  std::barrier start(kClients);
  std::vector<std::thread> threads;
  for (int c = 0; c < kClients; ++c) {
    threads.emplace_back([&, c] {
      FrameClient& client = *clients[c];
      flatbuffers::FlatBufferBuilder builder;
      protocol::PoseFields fields = pose_fields(daemon.model_id(), 100 * c, rotations);
      start.arrive_and_wait();
      if (!asks_for_a_sheet(c)) {  // two maps in a row, then a pose with normals
        for (int m = 0; m < 2; ++m) {
          builder.Clear();
          fields.sequence = 100 * c + m;
          const auto pose = protocol::add_pose(builder, fields);
          client.send_bytes(protocol::finish_message(
              builder,
              protocol::CreatePositionMapRequest(
                  builder, pose, kMapSide, kMapSide, protocol::ExrCompression::Zip,
                  protocol::MapLayers::Position | protocol::MapLayers::Normal |
                      protocol::MapLayers::Coverage),
              10 + m));
        }
        fields.sequence = 100 * c + 2;
        fields.normals = true;
        send_pose(client, fields);
        read_outcome<protocol::PositionMap>(client, "map 1 of client " + std::to_string(c), outcomes);
        read_outcome<protocol::PositionMap>(client, "map 2 of client " + std::to_string(c), outcomes);
        read_outcome<protocol::PosedVertices>(client, "pose of client " + std::to_string(c), outcomes);
      } else {  // a sheet of the largest cell, then a pose with normals
        const std::vector<std::uint32_t> frames = {10};
        const std::vector<std::string> methods = {"sweep"};
        client.send_bytes(protocol::finish_message(
            builder,
            protocol::CreateContactSheetRequest(builder, daemon.model_id(),
                                                builder.CreateString(clip_ids[c]),
                                                builder.CreateVector(frames),
                                                builder.CreateVectorOfStrings(methods), kSheetCell,
                                                kSheetCell),
            20));
        read_outcome<protocol::ContactSheet>(client, "sheet of client " + std::to_string(c), outcomes);
        fields.sequence = 100 * c + 1;
        fields.normals = true;
        send_pose(client, fields);
        read_outcome<protocol::PosedVertices>(client, "pose of client " + std::to_string(c), outcomes);
      }
    });
  }
  for (std::thread& thread : threads) thread.join();

  const std::uint64_t peak = status_bytes(daemon.pid(), "VmHWM");
  std::cout << "resident at rest " << resident_at_rest / 1000000 << " MB, peak (VmHWM) "
            << peak / 1000000 << " MB; " << outcomes.answered << " answered, " << outcomes.refused
            << " refused\n";
  for (const std::string& refusal : outcomes.refusals) std::cout << "  refused: " << refusal << "\n";
  EXPECT_TRUE(outcomes.unexpected.empty()) << ::testing::PrintToString(outcomes.unexpected)
                                           << daemon.log();
  EXPECT_EQ(outcomes.answered + outcomes.refused, 6 * 3 + 2 * 2);  // nothing lost
  // A connection's second map comes while its first, or another client's, holds 446 MB of
  // the 512 MiB: refused.
  EXPECT_GE(outcomes.refused, 6);
  EXPECT_GE(outcomes.answered, 8 + 1);  // the eight poses and at least one map or sheet
  EXPECT_LE(peak, kBudgetBytes + kBaseBytes);

  // /metrics tells the same: every refusal counted, the budget as configured, and every
  // reservation given back once its reply is out (the last one a moment after its reply).
  const std::string page = metrics_once_work_is_given_back(http_port);
  EXPECT_EQ(metric(page, "sweepd_work_refusals_total"), outcomes.refused) << page;
  EXPECT_EQ(metric(page, "sweepd_work_budget_bytes"), static_cast<double>(kBudgetBytes));
  EXPECT_EQ(metric(page, "sweepd_work_bytes"), 0) << page;
  clients.clear();
  fs::remove_all(directory);
}

// Model uploads (LoadModel with bytes): eight clients upload at once, four a model of the largest
// size the daemon takes (--max-frame-bytes just above it: an 80k-vertex mannequin, 6.0 MB of
// .glb), four a 20k-vertex one (1.45 MB), each with other bind options (another content id: each
// is read and bound). Loads bind one at a time (the store's slot); each upload's copy is
// reserved at intake, its reading (5 bytes a byte) when its turn comes, its binding once read
// (work_size.h: 900 bytes a vertex and 256 a triangle, less the reading: 20.6 MB for the 20k,
// 81 MB for the 80k), from a budget of 64 MiB: every 20k model fits beside every other
// upload's copy (at most 58 MB held), no 80k binding fits (88 MB with its own copy and
// reading). So four are answered and four refused by name when read, nothing is lost, the
// peak resident size (VmHWM) stays within the budget plus the 300 MB base, and /metrics counts
// every refusal and ends with every reservation given back.
TEST(DaemonWorkBudget,
     ConcurrentModelUploadsOfTheLargestAcceptedSizeStayWithinTheBudgetOrAreRefusedByName) {
  constexpr std::uint64_t kUploadBudgetBytes = 64ull << 20;
  const fs::path directory = fresh_directory("work_budget_uploads");
  std::vector<std::vector<std::uint8_t>> glbs;  // the largest, then the smaller
  for (const int vertices : {80000, 20000}) {
    const fs::path file = directory / ("upload_" + std::to_string(vertices) + ".glb");
    io::save_gltf(mannequin::make_mannequin({.target_vertices = vertices}), file);
    glbs.push_back(read_bytes(file));
  }
  const fs::path http_port_file = directory / "http_port";
  DaemonProcess daemon(
      directory,
      {"--work-budget-bytes", std::to_string(kUploadBudgetBytes), "--work-budget-client-bytes",
       std::to_string(kUploadBudgetBytes), "--worker-threads", "8", "--max-models", "16",
       "--max-frame-bytes", std::to_string(glbs[0].size() + 4096), "--http-listen", "127.0.0.1:0",
       "--http-port-file", http_port_file.string()});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  const int http_port = std::stoi(read_text(http_port_file));

  constexpr int kClients = 8;
  std::vector<std::unique_ptr<FrameClient>> clients;
  for (int c = 0; c < kClients; ++c) {
    clients.push_back(std::make_unique<FrameClient>(daemon.port()));
    ASSERT_NE(clients.back()->hello(""), nullptr);
  }
  Outcomes outcomes;
  std::barrier start(kClients);
  std::vector<std::thread> threads;
  for (int c = 0; c < kClients; ++c) {
    threads.emplace_back([&, c] {
      flatbuffers::FlatBufferBuilder builder;
      // 1 to 4 keys a link, either orientation curve: eight content ids.
      const auto options = protocol::CreateBindOptions(
          builder, 0, static_cast<std::uint8_t>(1 + c % 4), static_cast<std::uint8_t>(c / 4));
      const std::string name = "upload_" + std::to_string(c);
      const std::vector<std::uint8_t>& glb = glbs[c % 2];
      const auto frame = protocol::finish_message(
          builder, protocol::CreateLoadModelDirect(builder, name.c_str(), &glb, options), 30);
      start.arrive_and_wait();
      clients[c]->send_bytes(frame);
      read_outcome<protocol::ModelInfo>(*clients[c], "upload of client " + std::to_string(c),
                                        outcomes);
    });
  }
  for (std::thread& thread : threads) thread.join();

  const std::uint64_t peak = status_bytes(daemon.pid(), "VmHWM");
  std::cout << "uploads of " << glbs[0].size() << " and " << glbs[1].size()
            << " bytes; peak (VmHWM) " << peak / 1000000 << " MB; " << outcomes.answered
            << " answered, " << outcomes.refused << " refused\n";
  for (const std::string& refusal : outcomes.refusals)
    std::cout << "  refused: " << refusal << "\n";
  EXPECT_TRUE(outcomes.unexpected.empty())
      << ::testing::PrintToString(outcomes.unexpected) << daemon.log();
  EXPECT_EQ(outcomes.answered + outcomes.refused, kClients);  // nothing lost
  EXPECT_EQ(outcomes.answered, 4);                            // the 20k models
  EXPECT_EQ(outcomes.refused, 4);                             // the 80k models, once read
  for (const std::string& refusal : outcomes.refusals) {
    // What was asked, its bytes, the limit and what is held of it, and what fits.
    EXPECT_TRUE(refusal.starts_with("binding model 'upload_")) << refusal;
    EXPECT_NE(refusal.find("vertices, "), std::string::npos) << refusal;
    EXPECT_NE(refusal.find(" bytes of working memory, over "), std::string::npos) << refusal;
    EXPECT_NE(refusal.find("bytes 67,108,864, "), std::string::npos) << refusal;  // the limit
    EXPECT_NE(refusal.find(" fit); upload a smaller model"), std::string::npos) << refusal;
  }
  EXPECT_LE(peak, kUploadBudgetBytes + kBaseBytes);

  const std::string page = metrics_once_work_is_given_back(http_port);
  EXPECT_EQ(metric(page, "sweepd_work_refusals_total"), outcomes.refused) << page;
  EXPECT_EQ(metric(page, "sweepd_work_bytes"), 0) << page;
  clients.clear();
  fs::remove_all(directory);
}

}  // namespace
}  // namespace sweepd::test

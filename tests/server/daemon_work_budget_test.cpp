// Issue 49 item 2: requests' working memory in one budget. A daemon with a 512 MiB work budget
// and 8 workers (as on an 8-core host), eight clients at once asking for the largest work a
// 64 MiB frame lets through: six ask for two position maps in a row of 1536 x 1536 with
// positions, float32 normals and coverage (66 MB of EXR; work_size.h estimates 446 MB each),
// two for a contact sheet of one 2048 x 2048 cell (296 MB each); each then a pose with normals.
// Every request is answered or refused by name (ResourceExhausted naming the bytes and the
// budget), none is lost, and the daemon's peak resident size (VmHWM) stays within the budget
// plus a base of 300 MB (the issue's target: the mannequin, threads, libraries and Mesa's
// llvmpipe); /metrics counts the refusals and ends with every reservation given back. Before
// the budget, main's daemon (cc4c762) answered all 22 at a peak of 1,512 MB.
#include <gtest/gtest.h>

#include <barrier>
#include <chrono>
#include <fstream>
#include <mutex>
#include <regex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "console/text_format.h"
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
constexpr std::uint32_t kMapSide = 1536;    // 28 bytes a texel: 66.1 MB, within 64 MiB frames
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
    outcomes.unexpected.push_back(
        what + ": " + protocol::EnumNameBody(message->body_type()) +
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

// The next reply's Error as "<code> <message>", or what came instead.
std::string next_error(FrameClient& client) {
  const protocol::Message* message = client.receive();
  if (message == nullptr) return "no reply";
  const protocol::Error* error = message->body_as_Error();
  if (error == nullptr)
    return std::string("not an Error: ") + protocol::EnumNameBody(message->body_type());
  return std::string(protocol::EnumNameErrorCode(error->code())) + " " + error->message()->str();
}

// A refusal by a 1 MiB --work-budget-bytes: the limit, what all clients hold of it and what
// fits, which add up to the limit (held: a pose's reply a moment after it went out, or
// nothing), then what to ask instead.
bool names_the_small_budget(const std::string& refusal, const std::string& instead) {
  static const std::regex budget(
      "over what the server's work budget has free now \\(--work-budget-bytes 1,048,576, "
      "([0-9,]+) held by all clients: ([0-9,]+) fit\\); (.*), or retry when");
  std::smatch match;
  if (!std::regex_search(refusal, match, budget)) return false;
  const auto number = [](std::string text) {
    std::erase(text, ',');
    return std::stoull(text);
  };
  return number(match[1]) + number(match[2]) == (1u << 20) && match[3] == instead;
}

// "name content_id" of each model the daemon holds (ListModels).
std::vector<std::string> held_models(FrameClient& client) {
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(protocol::finish_message(builder, protocol::CreateListModels(builder), 40));
  std::vector<std::string> held;
  if (const protocol::ModelList* list = client.receive_as<protocol::ModelList>())
    for (const protocol::ModelSummary* model : *list->models())
      held.push_back(model->name()->str() + " " + model->content_id()->str());
  return held;
}

// The positions of model `model_id` bent (bent_rotations) by the daemon.
std::vector<float> bent_positions(FrameClient& client, std::uint32_t model_id,
                                  std::uint64_t sequence) {
  const std::vector<protocol::Quat> rotations = to_wire(bent_rotations(31));
  send_pose(client, pose_fields(model_id, sequence, rotations));
  const protocol::PosedVertices* posed = client.receive_as<protocol::PosedVertices>();
  return posed == nullptr ? std::vector<float>() : copy_floats(posed->positions_f32());
}

// Sets a process's peak resident size (VmHWM) to its resident size now (/proc/PID/clear_refs,
// 5), so that the next VmHWM read is the peak of what it did since.
void reset_peak(pid_t pid) { std::ofstream("/proc/" + std::to_string(pid) + "/clear_refs") << "5"; }

TEST(DaemonWorkBudget, TheLargestValidWorkFromManyClientsStaysWithinTheBudgetOrIsRefusedByName) {
  const fs::path directory = fresh_directory("work_budget");
  const fs::path http_port_file = directory / "http_port";
  DaemonProcess daemon(
      directory, {"--work-budget-bytes", std::to_string(kBudgetBytes), "--work-budget-client-bytes",
                  std::to_string(kBudgetBytes), "--worker-threads", "8", "--http-listen",
                  "127.0.0.1:0", "--http-port-file", http_port_file.string()});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  const int http_port = std::stoi(read_text(http_port_file));
  const std::string clip =
      io::read_file_text(fs::path(SWEEPD_SHARED_DATA) / "motion" / "cmu_01_01.bvh");
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
        read_outcome<protocol::PositionMap>(client, "map 1 of client " + std::to_string(c),
                                            outcomes);
        read_outcome<protocol::PositionMap>(client, "map 2 of client " + std::to_string(c),
                                            outcomes);
        read_outcome<protocol::PosedVertices>(client, "pose of client " + std::to_string(c),
                                              outcomes);
      } else {  // a sheet of the largest cell, then a pose with normals
        const std::vector<std::uint32_t> frames = {10};
        const std::vector<std::string> methods = {"sweep"};
        client.send_bytes(protocol::finish_message(
            builder,
            protocol::CreateContactSheetRequest(
                builder, daemon.model_id(), builder.CreateString(clip_ids[c]),
                builder.CreateVector(frames), builder.CreateVectorOfStrings(methods), kSheetCell,
                kSheetCell),
            20));
        read_outcome<protocol::ContactSheet>(client, "sheet of client " + std::to_string(c),
                                             outcomes);
        fields.sequence = 100 * c + 1;
        fields.normals = true;
        send_pose(client, fields);
        read_outcome<protocol::PosedVertices>(client, "pose of client " + std::to_string(c),
                                              outcomes);
      }
    });
  }
  for (std::thread& thread : threads) thread.join();

  const std::uint64_t peak = status_bytes(daemon.pid(), "VmHWM");
  std::cout << "resident at rest " << resident_at_rest / 1000000 << " MB, peak (VmHWM) "
            << peak / 1000000 << " MB; " << outcomes.answered << " answered, " << outcomes.refused
            << " refused\n";
  for (const std::string& refusal : outcomes.refusals)
    std::cout << "  refused: " << refusal << "\n";
  EXPECT_TRUE(outcomes.unexpected.empty())
      << ::testing::PrintToString(outcomes.unexpected) << daemon.log();
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

// Flags for a daemon's HTTP side port, its port written to directory/http_port.
std::vector<std::string> side_port_flags(const fs::path& directory) {
  return {"--http-listen", "127.0.0.1:0", "--http-port-file", (directory / "http_port").string()};
}

// The /metrics of the daemon of side_port_flags(directory) once its work is given back: its
// refusals counted and nothing reserved.
void expect_budget_whole(const fs::path& directory, double refusals) {
  const std::string page =
      metrics_once_work_is_given_back(std::stoi(read_text(directory / "http_port")));
  EXPECT_EQ(metric(page, "sweepd_work_refusals_total"), refusals) << page;
  EXPECT_EQ(metric(page, "sweepd_work_bytes"), 0) << page;
}

// Adopting a model another replica stored (LoadModel by content id or by name, issue 49 item
// 2): its reading is charged to the work budget (work_size.h: 10 bytes a byte of its
// .sweepbind), reserved before it is read. Three daemons share one store; all start before the
// model is stored (a daemon started after it would read it at restore, not adopt it). Through
// the first, a 20k-vertex mannequin is uploaded as "body" (a 3.6 MB .sweepbind: 36 MB of
// work). The second, with a 1 MiB budget, refuses to adopt it by content id and by name —
// ResourceExhausted naming the model, its bytes, the limit, what is held and what fits —
// counts both refusals, holds what it held (its mannequin, posed to the same bits) and ends
// with nothing reserved. The third, with the default budget, adopts it (the same handle as on
// the first) and ends with its budget whole; its peak over its resident size while adopting
// is printed beside the reservation.
TEST(DaemonWorkBudget, AdoptingAStoredModelIsRefusedByNameWhenItDoesNotFitAndAnsweredWhenItDoes) {
  constexpr std::uint64_t kSmallBudgetBytes = 1ull << 20;  // the least --work-budget-bytes
  const fs::path directory = fresh_directory("work_budget_adoption");
  const fs::path store = directory / "shared_store";
  const std::string shared = store.string();
  for (const char* replica : {"uploader", "small", "fitting"})
    fs::create_directories(directory / replica);
  DaemonProcess small(directory / "small", with(side_port_flags(directory / "small"),
                                                {"--store-dir", shared, "--work-budget-bytes",
                                                 std::to_string(kSmallBudgetBytes)}));
  DaemonProcess fitting(directory / "fitting",
                        with(side_port_flags(directory / "fitting"), {"--store-dir", shared}));
  DaemonProcess uploader(directory / "uploader", {"--store-dir", shared});
  ASSERT_TRUE(small.running() && fitting.running() && uploader.running())
      << small.log() << fitting.log() << uploader.log();

  const fs::path glb = directory / "body.glb";
  io::save_gltf(mannequin::make_mannequin({.target_vertices = 20000}), glb);
  const std::vector<std::uint8_t> upload = read_bytes(glb);
  FrameClient via_uploader(uploader.port());
  ASSERT_NE(via_uploader.hello(""), nullptr);
  flatbuffers::FlatBufferBuilder builder;
  via_uploader.send_bytes(protocol::finish_message(
      builder, protocol::CreateLoadModelDirect(builder, "body", &upload), 1));
  const protocol::ModelInfo* uploaded = via_uploader.receive_as<protocol::ModelInfo>();
  ASSERT_NE(uploaded, nullptr);
  const std::uint32_t body_id = uploaded->model_id();
  const std::string content_id = uploaded->content_id()->str();
  const std::uint64_t binding_bytes = fs::file_size(store / (content_id + ".sweepbind"));
  const auto load_by_content_id = [&](FrameClient& client) {
    builder.Clear();
    client.send_bytes(protocol::finish_message(
        builder, protocol::CreateLoadModelDirect(builder, nullptr, nullptr, 0, content_id.c_str()),
        2));
  };

  FrameClient via_small(small.port());
  ASSERT_NE(via_small.hello(""), nullptr);
  const std::vector<std::string> held_before = held_models(via_small);
  const std::vector<float> posed_before = bent_positions(via_small, small.model_id(), 1);
  ASSERT_FALSE(posed_before.empty());
  load_by_content_id(via_small);
  const std::string by_content_id = next_error(via_small);
  builder.Clear();
  via_small.send_bytes(
      protocol::finish_message(builder, protocol::CreateLoadModelDirect(builder, "body"), 3));
  const std::string by_name = next_error(via_small);
  const std::string bytes_clause =
      " (" + console::with_thousands(static_cast<std::int64_t>(binding_bytes)) +
      " bytes of binding): needs " +
      console::with_thousands(static_cast<std::int64_t>(10 * binding_bytes)) +
      " bytes of working memory, over ";
  const std::vector<std::pair<std::string, std::string>> refusals = {{by_content_id, content_id},
                                                                     {by_name, "'body'"}};
  for (const auto& [refusal, what] : refusals) {
    EXPECT_TRUE(
        refusal.starts_with("ResourceExhausted adopting stored model " + what + bytes_clause))
        << refusal;
    EXPECT_TRUE(names_the_small_budget(refusal, "a stored model is read whole")) << refusal;
  }
  EXPECT_EQ(held_models(via_small), held_before) << "nothing adopted, nothing let go";
  EXPECT_TRUE(same_bits(bent_positions(via_small, small.model_id(), 4), posed_before));
  expect_budget_whole(directory / "small", 2);

  FrameClient via_fitting(fitting.port());
  ASSERT_NE(via_fitting.hello(""), nullptr);
  const std::uint64_t resident = status_bytes(fitting.pid(), "VmRSS");
  reset_peak(fitting.pid());
  load_by_content_id(via_fitting);
  const protocol::ModelInfo* adopted = via_fitting.receive_as<protocol::ModelInfo>();
  ASSERT_NE(adopted, nullptr);
  EXPECT_EQ(adopted->model_id(), body_id) << "one content id, one handle on every replica";
  const std::uint64_t peak = status_bytes(fitting.pid(), "VmHWM");
  std::cout << "adopting " << binding_bytes << " bytes of binding: peak over the resident size "
            << (peak - std::min(peak, resident)) / 1000000 << " MB, reserved "
            << 10 * binding_bytes / 1000000 << " MB\n";
  // The reservation is an upper bound: here the self-check's sidecar is read, not the check
  // run again (measured 17 MB of 36 MB at 20k vertices).
  EXPECT_LE(peak - std::min(peak, resident), 10 * binding_bytes);
  EXPECT_NE(fitting.log().find("\"event\":\"model_adopted\""), std::string::npos) << fitting.log();
  expect_budget_whole(directory / "fitting", 0);
  fs::remove_all(directory);
}

// EditKeyEllipse's copy of the binding (issue 49 item 2): charged to the work budget at intake
// (work_size.h: 12 bytes a byte of the held .sweepbind). A daemon with a 1 MiB budget refuses
// an edit of its 2,000-vertex mannequin — ResourceExhausted naming the model, its vertices and
// binding bytes, the limit, what is held and what fits — counts it, and keeps the model as it
// was: posed to the same bits, its stored .sweepbind unchanged. A daemon with the default
// budget and a 20k-vertex mannequin answers the same edit (the model then poses otherwise) and
// ends with its budget whole; its peak over its resident size during the edit is printed
// beside the reservation.
TEST(DaemonWorkBudget, AKeyEllipseEditIsRefusedByNameWhenItDoesNotFitAndAnsweredWhenItDoes) {
  const fs::path directory = fresh_directory("work_budget_edit");
  fs::create_directories(directory / "small");
  fs::create_directories(directory / "fitting");
  DaemonProcess small(directory / "small", with(side_port_flags(directory / "small"),
                                                {"--work-budget-bytes", std::to_string(1 << 20)}));
  DaemonProcess fitting(directory / "fitting", with(side_port_flags(directory / "fitting"),
                                                    {"--mannequin-vertices", "20000"}));
  ASSERT_TRUE(small.running() && fitting.running()) << small.log() << fitting.log();
  const auto send_edit = [](FrameClient& client, std::uint32_t model_id) {
    flatbuffers::FlatBufferBuilder builder;
    const protocol::Vec3 offset(0.0f, 0.0f, 0.01f);
    client.send_bytes(
        protocol::finish_message(builder,
                                 protocol::CreateEditKeyEllipseDirect(
                                     builder, model_id, "left_arm", 2, &offset, 0.07f, 0.0f, 0.3f),
                                 5));
  };
  // The held mannequin's .sweepbind (its content id from ListModels).
  const auto binding_file = [](const fs::path& replica, FrameClient& client) {
    const std::string held = held_models(client).at(0);
    return replica / "store" / (held.substr(held.find(' ') + 1) + ".sweepbind");
  };

  FrameClient via_small(small.port());
  ASSERT_NE(via_small.hello(""), nullptr);
  const fs::path small_binding = binding_file(directory / "small", via_small);
  const std::vector<std::uint8_t> stored_before = read_bytes(small_binding);
  const std::vector<float> posed_before = bent_positions(via_small, small.model_id(), 1);
  send_edit(via_small, small.model_id());
  const std::string refusal = next_error(via_small);
  EXPECT_TRUE(refusal.starts_with("ResourceExhausted edit key ellipse of model 'mannequin' ("))
      << refusal;
  EXPECT_NE(
      refusal.find(" vertices, " +
                   console::with_thousands(static_cast<std::int64_t>(stored_before.size())) +
                   " bytes of binding): needs " +
                   console::with_thousands(static_cast<std::int64_t>(12 * stored_before.size())) +
                   " bytes of working memory, over "),
      std::string::npos)
      << refusal;
  EXPECT_TRUE(names_the_small_budget(refusal, "an edit copies the whole binding")) << refusal;
  EXPECT_TRUE(same_bits(bent_positions(via_small, small.model_id(), 2), posed_before))
      << "the refused edit changed the model served";
  EXPECT_EQ(read_bytes(small_binding), stored_before) << "the refused edit changed the store";
  expect_budget_whole(directory / "small", 1);

  FrameClient via_fitting(fitting.port());
  ASSERT_NE(via_fitting.hello(""), nullptr);
  const std::uint64_t binding_bytes =
      fs::file_size(binding_file(directory / "fitting", via_fitting));
  const std::vector<float> unedited = bent_positions(via_fitting, fitting.model_id(), 1);
  const std::uint64_t resident = status_bytes(fitting.pid(), "VmRSS");
  reset_peak(fitting.pid());
  send_edit(via_fitting, fitting.model_id());
  ASSERT_NE(via_fitting.receive_as<protocol::ModelInfo>(), nullptr);
  const std::uint64_t peak = status_bytes(fitting.pid(), "VmHWM");
  std::cout << "editing " << binding_bytes << " bytes of binding: peak over the resident size "
            << (peak - std::min(peak, resident)) / 1000000 << " MB, reserved "
            << 12 * binding_bytes / 1000000 << " MB\n";
  // The reservation is an upper bound (measured 27 MB of 43 MB at 20k vertices; it also
  // covers an edit that reads the store's version again).
  EXPECT_LE(peak - std::min(peak, resident), 12 * binding_bytes);
  EXPECT_FALSE(same_bits(bent_positions(via_fitting, fitting.model_id(), 2), unedited));
  expect_budget_whole(directory / "fitting", 0);
  fs::remove_all(directory);
}

}  // namespace
}  // namespace sweepd::test

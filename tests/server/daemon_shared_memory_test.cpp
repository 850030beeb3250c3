// Shared-memory replies (protocol 1.10) over the daemon's Unix socket: a client maps a region
// (MapSharedMemory; the descriptor arrives with the SharedMemory reply), poses into it at
// offsets it chooses, and reads the same bits a TCP client gets in its replies — positions and
// normals, sweep with features and LBS, with clients that sleep or poll while they wait. Requests
// that cannot be placed get an InvalidArgument naming the problem, and the connection goes on; TCP
// cannot map, nor a connection twice; the client cannot shrink the region under the server; the
// region's bytes count against the server's buffer budget until its connection closes. Hostile
// clients of the region (issue 49 item 5) — one that asks for a reply larger than its region,
// one that unmaps its mapping and closes its descriptor and poses on, one that sends descriptors
// with its frames, sixteen that map, pose into the region and vanish without reading — leave
// the daemon's descriptors and budget as they were and an honest client's replies unchanged.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>

#include "client/connection.h"
#include "protocol/descriptor_passing.h"
#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"

namespace sweepd::test {
namespace {

namespace pb = sweepd::protocol;

struct Reply {
  std::vector<float> positions, normals;
};

// One pose; its reply read from the frame (no shared offset) or from the region.
Reply pose(client::Connection& connection, std::uint32_t model_id,
           const std::vector<pb::Quat>& rotations, std::uint64_t sequence,
           std::optional<std::uint64_t> shared_offset, pb::DeformMethod method,
           pb::Features features) {
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  pb::PoseFields fields = pose_fields(model_id, sequence, rotations);
  fields.method = method;
  fields.features = features;
  fields.normals = true;
  fields.shared_offset = shared_offset;
  connection.send(pb::finish_message(builder, pb::add_pose(builder, fields)));
  const pb::PosedVertices& reply = connection.expect<pb::PosedVertices>();
  EXPECT_EQ(reply.sequence(), sequence);
  EXPECT_EQ(reply.in_shared_memory(), shared_offset.has_value());
  if (!shared_offset) return {copy_floats(reply.positions_f32()), copy_floats(reply.normals_f32())};
  // Nothing crossed the socket but where the vertices are.
  EXPECT_EQ(reply.positions_f32(), nullptr);
  EXPECT_EQ(reply.normals_f32(), nullptr);
  EXPECT_EQ(reply.shared_offset(), *shared_offset);
  const std::span<const float> positions = connection.shared_positions(reply);
  const std::span<const float> normals = connection.shared_normals(reply);
  EXPECT_EQ(positions.size(), 3u * reply.vertex_count());
  EXPECT_EQ(normals.size(), 3u * reply.vertex_count());
  return {{positions.begin(), positions.end()}, {normals.begin(), normals.end()}};
}

template <typename Request>
void expect_refused(Request request, pb::ErrorCode code, const std::string& reason) {
  try {
    request();
    ADD_FAILURE() << "accepted; expected " << reason;
  } catch (const client::ServerError& error) {
    EXPECT_EQ(error.code(), code) << error.what();
    EXPECT_NE(std::string(error.what()).find(reason), std::string::npos) << error.what();
  }
}

TEST(DaemonSharedMemory, UnixSocketRepliesInTheRegionEqualTcpRepliesBitForBit) {
  const ScratchDirectory directory("shared_memory");
  const fs::path socket = directory / "sweepd.sock";
  DaemonProcess daemon(directory, {"--mannequin-vertices", "4000", "--unix-socket", socket});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  client::Connection tcp("127.0.0.1", std::to_string(daemon.port()));
  client::Connection local("unix:" + socket.string());
  // Welcome says where MapSharedMemory works.
  const auto has_shared_memory = [](const pb::Welcome& welcome) {
    for (const auto* capability : *welcome.capabilities())
      if (capability->str() == "shared_memory") return true;
    return false;
  };
  EXPECT_FALSE(has_shared_memory(tcp.hello("", "shared memory test, tcp")));
  EXPECT_TRUE(has_shared_memory(local.hello("", "shared memory test, unix")));
  const pb::ModelInfo& info = local.load_model("mannequin");
  const std::uint32_t id = info.model_id();
  const std::size_t vertices = info.vertex_count();
  const std::size_t joints = info.joint_names()->size();
  ASSERT_EQ(tcp.load_model("mannequin").model_id(), id);

  // Two slots of positions and normals; the second starts at a multiple of 4, not of a page.
  const std::size_t slot = 2 * 3 * vertices * sizeof(float);
  const std::uint64_t second = slot + 4;
  const std::span<const std::uint8_t> region = local.map_shared_memory(2 * slot + 4);
  EXPECT_EQ(region.size(), 2 * slot + 4);

  const struct {
    pb::DeformMethod method;
    pb::Features features;
  } cases[] = {{pb::DeformMethod::Sweep, pb::Features::NONE},
               {pb::DeformMethod::Sweep, pb::Features::Volume | pb::Features::Folding},
               {pb::DeformMethod::Lbs, pb::Features::NONE}};
  std::uint64_t sequence = 0;
  for (const auto& c : cases) {
    for (const float phase : {0.0f, 0.7f}) {
      // The second pose of each case read by clients that poll before they sleep
      // (set_receive_spin): the TCP reply (48 KB of positions) then arrives in pieces.
      const std::chrono::microseconds spin(phase > 0.0f ? 5000 : 0);
      tcp.set_receive_spin(spin);
      local.set_receive_spin(spin);
      const std::vector<pb::Quat> wire = to_wire(bent_rotations(joints, phase));
      ++sequence;
      const Reply expected = pose(tcp, id, wire, sequence, std::nullopt, c.method, c.features);
      const std::uint64_t offset = sequence % 2 == 0 ? 0 : second;
      const Reply shared = pose(local, id, wire, sequence, offset, c.method, c.features);
      // The same deformation written to another place: the same bits.
      EXPECT_TRUE(same_bits(shared.positions, expected.positions)) << "pose " << sequence;
      EXPECT_TRUE(same_bits(shared.normals, expected.normals)) << "pose " << sequence;
    }
  }

  // What cannot be placed is refused by name, and the connection goes on.
  const std::vector<pb::Quat> rest = to_wire(bent_rotations(joints, 0.0f));
  const auto shared_pose = [&](std::uint64_t offset, pb::PositionFormat format) {
    return [&, offset, format]() {
      flatbuffers::FlatBufferBuilder& builder = local.builder();
      builder.Clear();
      pb::PoseFields fields = pose_fields(id, 99, rest);
      fields.positions = format;
      fields.shared_offset = offset;
      local.send(pb::finish_message(builder, pb::add_pose(builder, fields)));
      local.expect<pb::PosedVertices>();
    };
  };
  expect_refused(shared_pose(2 * slot, pb::PositionFormat::Float32), pb::ErrorCode::InvalidArgument,
                 "do not fit the shared region of " + std::to_string(2 * slot + 4));
  expect_refused(shared_pose(2, pb::PositionFormat::Float32), pb::ErrorCode::InvalidArgument,
                 "multiple of 4");
  expect_refused(shared_pose(~std::uint64_t{0} - 3, pb::PositionFormat::Float32),
                 pb::ErrorCode::InvalidArgument, "do not fit");
  expect_refused(shared_pose(0, pb::PositionFormat::Float16), pb::ErrorCode::InvalidArgument,
                 "Float32 only");
  // The library maps one region per connection (the server's refusal: the raw test below).
  EXPECT_THROW(local.map_shared_memory(4096), std::logic_error);
  const Reply again = pose(local, id, rest, 100, 0, pb::DeformMethod::Sweep, pb::Features::NONE);
  EXPECT_EQ(again.positions.size(), 3 * vertices);

  // TCP cannot carry a descriptor, and a pose there that asks for shared memory has none.
  expect_refused([&]() { tcp.map_shared_memory(4096); }, pb::ErrorCode::NotAvailable,
                 "needs a Unix socket");
  expect_refused(
      [&]() { pose(tcp, id, rest, 101, 0, pb::DeformMethod::Sweep, pb::Features::NONE); },
      pb::ErrorCode::InvalidArgument, "this connection has mapped none");
  tcp.close();
  local.close();
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait(), 0) << daemon.log();
}

// The raw exchange: the descriptor is a sealed memfd the client can write but not resize;
// a region past max_frame_bytes or past the buffer budget is refused.
TEST(DaemonSharedMemory, TheRegionIsSealedAndBoundedByTheServersLimits) {
  const ScratchDirectory directory("shared_memory_limits");
  const fs::path socket = directory / "sweepd.sock";
  DaemonProcess daemon(
      directory, {"--mannequin-vertices", "4000", "--unix-socket", socket, "--max-frame-bytes",
                  "8388608", "--max-buffered-bytes", "12582912"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  client::Connection first("unix:" + socket.string());
  first.hello("", "limits test");
  expect_refused([&]() { first.map_shared_memory((8u << 20) + 1); }, pb::ErrorCode::InvalidArgument,
                 "a region has 1 to 8388608");
  expect_refused([&]() { first.map_shared_memory(0); }, pb::ErrorCode::InvalidArgument,
                 "asks for 0 bytes");
  EXPECT_EQ(first.map_shared_memory(8u << 20).size(), 8u << 20);
  // 8 of the budget's 12 MiB are the first region's: a second of 8 does not fit.
  client::Connection second("unix:" + socket.string());
  second.hello("", "limits test 2");
  expect_refused([&]() { second.map_shared_memory(8u << 20); }, pb::ErrorCode::ResourceExhausted,
                 "buffer budget");
  // Closing the first gives its bytes back.
  first.close();
  bool mapped = false;
  for (int attempt = 0; attempt < 50 && !mapped; ++attempt) {
    try {
      second.map_shared_memory(8u << 20);
      mapped = true;
    } catch (const client::ServerError&) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  EXPECT_TRUE(mapped) << "the closed connection's region still counts against the budget";

  // The descriptor itself, read as a client without the library would.
  FrameClient raw(socket);
  ASSERT_TRUE(raw.connected());
  flatbuffers::FlatBufferBuilder builder;
  ASSERT_TRUE(raw.send_bytes(pb::build_hello(builder, "", "raw")));
  ASSERT_NE(raw.receive_as<pb::Welcome>(), nullptr);
  builder.Clear();
  ASSERT_TRUE(
      raw.send_bytes(pb::finish_message(builder, pb::CreateMapSharedMemory(builder, 65536))));
  std::vector<std::uint8_t> frame(4096);
  int descriptor = -1;
  // The reply is one small frame, sent in one sendmsg: it arrives whole with its descriptor.
  const std::size_t got = pb::receive_with_descriptor(raw.fd(), frame, descriptor);
  ASSERT_GT(got, 4u);
  flatbuffers::Verifier verifier(frame.data(), got);
  ASSERT_TRUE(pb::VerifySizePrefixedMessageBuffer(verifier));
  const pb::SharedMemory* granted =
      pb::GetSizePrefixedMessage(frame.data())->body_as_SharedMemory();
  ASSERT_NE(granted, nullptr);
  EXPECT_EQ(granted->bytes(), 65536u);
  ASSERT_GE(descriptor, 0);
  EXPECT_EQ(lseek(descriptor, 0, SEEK_END), 65536);
  const int seals = fcntl(descriptor, F_GET_SEALS);
  EXPECT_EQ(seals & (F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL),
            F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL);
  EXPECT_NE(ftruncate(descriptor, 0), 0) << "the client could shrink the server's region";
  EXPECT_EQ(errno, EPERM);
  close(descriptor);
  // One region per connection: a second is refused by name, and the session goes on.
  builder.Clear();
  ASSERT_TRUE(
      raw.send_bytes(pb::finish_message(builder, pb::CreateMapSharedMemory(builder, 4096))));
  const pb::Error* error = raw.receive_as<pb::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), pb::ErrorCode::InvalidArgument);
  EXPECT_NE(error->message()->str().find("has a shared region already (65536 bytes)"),
            std::string::npos)
      << error->message()->str();
  builder.Clear();
  ASSERT_TRUE(raw.send_bytes(pb::finish_message(builder, pb::CreateListModels(builder))));
  EXPECT_NE(raw.receive_as<pb::ModelList>(), nullptr);
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait(), 0) << daemon.log();
}

// The daemon's open descriptors (/proc/PID/fd).
std::size_t open_descriptors(pid_t pid) {
  const fs::directory_iterator entries("/proc/" + std::to_string(pid) + "/fd");
  return static_cast<std::size_t>(std::distance(entries, fs::directory_iterator()));
}

// The same once they are `expected`, or after 5 s: the daemon closes a connection's socket when
// its I/O thread has seen the end, soon after the client's close.
std::size_t settled_descriptors(pid_t pid, std::size_t expected) {
  for (int attempt = 0; attempt < 100 && open_descriptors(pid) != expected; ++attempt)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  return open_descriptors(pid);
}

// On a greeted raw client: MapSharedMemory of `bytes`; the descriptor that comes with the
// SharedMemory reply (-1 when none came: an Error refused it).
int map_raw(FrameClient& raw, std::uint64_t bytes) {
  flatbuffers::FlatBufferBuilder builder;
  if (!raw.send_bytes(pb::finish_message(builder, pb::CreateMapSharedMemory(builder, bytes))))
    return -1;
  std::vector<std::uint8_t> frame(4096);
  int descriptor = -1;
  // The reply is one small frame, sent in one sendmsg: it arrives whole with its descriptor.
  const std::size_t got = pb::receive_with_descriptor(raw.fd(), frame, descriptor);
  flatbuffers::Verifier verifier(frame.data(), got);
  EXPECT_TRUE(got > 4 && pb::VerifySizePrefixedMessageBuffer(verifier));
  return descriptor;
}

// A pose of `rotations` on `client` (Float32, no normals), into its region at `offset` or in
// the reply.
bool send_shared_pose(FrameClient& client, std::uint32_t model_id,
                      const std::vector<pb::Quat>& rotations, std::uint64_t sequence,
                      std::optional<std::uint64_t> offset) {
  pb::PoseFields fields = pose_fields(model_id, sequence, rotations);
  fields.shared_offset = offset;
  return send_pose(client, fields);
}

// A pose on `client` answered in its reply with `expected`'s bits.
void expect_reply_bits(FrameClient& client, std::uint32_t model_id,
                       const std::vector<pb::Quat>& rotations, std::uint64_t sequence,
                       const std::vector<float>& expected) {
  ASSERT_TRUE(send_shared_pose(client, model_id, rotations, sequence, std::nullopt));
  const pb::PosedVertices* reply = client.receive_as<pb::PosedVertices>();
  ASSERT_NE(reply, nullptr);
  EXPECT_TRUE(same_bits(copy_floats(reply->positions_f32()), expected)) << "pose " << sequence;
}

TEST(DaemonSharedMemory, HostileClientsOfTheRegionLeaveTheDaemonAndAnHonestClientAsTheyWere) {
  const ScratchDirectory directory("shared_memory_hostile");
  const fs::path socket = directory / "sweepd.sock";
  constexpr std::size_t kBudget = 24u << 20;
  DaemonProcess daemon(
      directory, {"--mannequin-vertices", "4000", "--unix-socket", socket, "--max-buffered-bytes",
                  std::to_string(kBudget), "--max-frame-bytes", std::to_string(kBudget),
                  "--max-connections", "40", "--position-maps", "0"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  const std::uint32_t id = daemon.model_id();
  const std::vector<pb::Quat> rotations = to_wire(bent_rotations(31));  // the mannequin's joints
  // The honest client's reply before any hostile one came, to compare the ones after with.
  FrameClient honest(socket);
  ASSERT_NE(honest.hello(""), nullptr);
  ASSERT_TRUE(send_shared_pose(honest, id, rotations, 1, std::nullopt));
  const pb::PosedVertices* first = honest.receive_as<pb::PosedVertices>();
  ASSERT_NE(first, nullptr);
  const std::vector<float> expected = copy_floats(first->positions_f32());
  const std::size_t reply_bytes = expected.size() * sizeof(float);  // 4,000 × 12: 48 KB
  const std::size_t descriptors_at_rest = open_descriptors(daemon.pid());

  // 1. A reply larger than the region: refused by name, and the session goes on.
  {
    FrameClient small(socket);
    ASSERT_NE(small.hello(""), nullptr);
    const int descriptor = map_raw(small, 4096);
    ASSERT_GE(descriptor, 0);
    close(descriptor);
    ASSERT_TRUE(send_shared_pose(small, id, rotations, 2, 0));
    const pb::Error* error = small.receive_as<pb::Error>();
    ASSERT_NE(error, nullptr);
    EXPECT_EQ(error->code(), pb::ErrorCode::InvalidArgument);
    EXPECT_FALSE(error->fatal());
    EXPECT_NE(error->message()->str().find(std::to_string(reply_bytes) +
                                           " bytes at offset 0 do not fit the shared region of "
                                           "4096 bytes"),
              std::string::npos)
        << error->message()->str();
    expect_reply_bits(small, id, rotations, 3, expected);
  }

  // 2. A client that unmaps its mapping and closes its descriptor, then poses into the region:
  // the daemon writes its own mapping (the memfd lives while the daemon holds it) and answers.
  {
    FrameClient unmapper(socket);
    ASSERT_NE(unmapper.hello(""), nullptr);
    const int descriptor = map_raw(unmapper, reply_bytes);
    ASSERT_GE(descriptor, 0);
    void* memory = mmap(nullptr, reply_bytes, PROT_READ | PROT_WRITE, MAP_SHARED, descriptor, 0);
    ASSERT_NE(memory, MAP_FAILED);
    ASSERT_EQ(munmap(memory, reply_bytes), 0);
    close(descriptor);
    for (std::uint64_t sequence = 10; sequence < 14; ++sequence) {
      ASSERT_TRUE(send_shared_pose(unmapper, id, rotations, sequence, 0));
      const pb::PosedVertices* reply = unmapper.receive_as<pb::PosedVertices>();
      ASSERT_NE(reply, nullptr);
      EXPECT_TRUE(reply->in_shared_memory());
      EXPECT_EQ(reply->sequence(), sequence);
    }
  }

  // 3. Descriptors sent to the daemon with a client's frames (SCM_RIGHTS): the daemon reads
  // bytes only, so the kernel closes what came with them; none stays open in the daemon.
  {
    FrameClient sender(socket);
    ASSERT_NE(sender.hello(""), nullptr);
    flatbuffers::FlatBufferBuilder builder;
    const std::span<const std::uint8_t> frame =
        pb::finish_message(builder, pb::add_pose(builder, pose_fields(id, 20, rotations)));
    const int null = open("/dev/null", O_RDONLY | O_CLOEXEC);
    ASSERT_GE(null, 0);
    for (int f = 0; f < 32; ++f) {
      const std::optional<std::size_t> sent = pb::send_with_descriptor(sender.fd(), frame, null);
      ASSERT_TRUE(sent.has_value());
      if (*sent < frame.size()) {
        ASSERT_TRUE(sender.send_raw(frame.subspan(*sent)));
      }
      const pb::PosedVertices* reply = sender.receive_as<pb::PosedVertices>();
      ASSERT_NE(reply, nullptr);
      EXPECT_TRUE(same_bits(copy_floats(reply->positions_f32()), expected));
    }
    close(null);
    EXPECT_EQ(settled_descriptors(daemon.pid(), descriptors_at_rest + 1), descriptors_at_rest + 1)
        << "the sender's own connection, and no descriptor it sent";
  }

  // 4. Sixteen clients each map 1 MiB, ask for 20 poses into it and vanish without reading.
  {
    std::vector<std::unique_ptr<FrameClient>> vanishing;
    for (int c = 0; c < 16; ++c) {
      vanishing.push_back(std::make_unique<FrameClient>(socket));
      ASSERT_NE(vanishing.back()->hello(""), nullptr);
      const int descriptor = map_raw(*vanishing.back(), 1u << 20);
      ASSERT_GE(descriptor, 0);
      close(descriptor);
      for (std::uint64_t p = 0; p < 20; ++p)
        ASSERT_TRUE(
            send_shared_pose(*vanishing.back(), id, rotations, 100 + p, (p % 16) * reply_bytes));
    }
  }
  expect_reply_bits(honest, id, rotations, 30, expected);

  // Every region given back: within 5 s a new client maps the whole budget but what the honest
  // connection holds (its read buffer: less than 1 MiB), and the daemon holds no descriptor more
  // than at rest but that client's own and its region's.
  FrameClient last(socket);
  ASSERT_NE(last.hello(""), nullptr);
  int region = -1;
  for (int attempt = 0; attempt < 100 && region < 0; ++attempt) {
    region = map_raw(last, kBudget - (1u << 20));  // refused (no descriptor) while they count
    if (region < 0) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_GE(region, 0) << "the vanished clients' regions still count against the budget";
  if (region >= 0) close(region);
  EXPECT_EQ(settled_descriptors(daemon.pid(), descriptors_at_rest + 2), descriptors_at_rest + 2)
      << "the last client's connection and its region, and nothing of the hostile ones";
  EXPECT_TRUE(daemon.running());
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait(), 0) << daemon.log();
}

}  // namespace
}  // namespace sweepd::test

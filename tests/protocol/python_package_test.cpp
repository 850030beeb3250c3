// Tests that the Python protocol code (flatc's, committed in client_examples/python/sweepd)
// speaks the same frames as the C++ code: Python reads a C++ PosedVertices frame, and C++
// reads a Python Hello frame.
// Runs Debian's /usr/bin/python3 with python3-flatbuffers and the standard library only.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "protocol/float16.h"
#include "protocol/framing.h"
#include "protocol/messages.h"

namespace sweepd::protocol {
namespace {

namespace fs = std::filesystem;
constexpr char kPython[] = "/usr/bin/python3";

// Reads a C++ frame (argv[1]), prints what it holds, writes a Hello frame (argv[2]).
constexpr char kScript[] = R"(
import struct, sys
import flatbuffers
from sweepd.protocol import Body, Hello, Message, PoseDelivery, PosedVertices

data = open(sys.argv[1], "rb").read()
length, = struct.unpack_from("<I", data, 0)
assert length + 4 == len(data), (length, len(data))
assert Message.Message.MessageBufferHasIdentifier(data, 0, size_prefixed=True)
message = Message.Message.GetRootAs(data, 4)
assert message.BodyType() == Body.Body.PosedVertices, message.BodyType()
reply = PosedVertices.PosedVertices()
reply.Init(message.Body().Bytes, message.Body().Pos)
halves = [reply.PositionsF16(j) for j in range(reply.PositionsF16Length())]
values = [struct.unpack("<e", struct.pack("<H", h))[0] for h in halves]
start = reply._tab.Vector(reply._tab.Offset(14))  # bulk read, as protocol/README.md shows
assert list(struct.unpack_from("<%de" % len(halves), data, start)) == values
print(message.RequestId(), reply.Sequence(), reply.VertexCount(), reply.DroppedBefore())
print(" ".join(repr(v) for v in values))

builder = flatbuffers.Builder(256)
token = builder.CreateString("s3cret")
name = builder.CreateString("python")
Hello.Start(builder)
Hello.AddVersionMajor(builder, 1)
Hello.AddAuthToken(builder, token)
Hello.AddClientName(builder, name)
Hello.AddDelivery(builder, PoseDelivery.PoseDelivery.LatestWins)
hello = Hello.End(builder)
Message.Start(builder)
Message.AddRequestId(builder, 42)
Message.AddBodyType(builder, Body.Body.Hello)
Message.AddBody(builder, hello)
builder.FinishSizePrefixed(Message.End(builder), b"SWPD")
open(sys.argv[2], "wb").write(builder.Output())
)";

class PythonPackage : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::system((std::string(kPython) + " -c 'import flatbuffers' 2>/dev/null").c_str()) != 0) {
      GTEST_SKIP() << kPython << " with python3-flatbuffers is not installed";
    }
    directory_ = fs::temp_directory_path() / ("sweepd_python_" + std::to_string(getpid()));
    fs::create_directories(directory_);
  }
  void TearDown() override {
    if (!directory_.empty()) fs::remove_all(directory_);
  }
  fs::path directory_;
};

TEST_F(PythonPackage, ReadsCppFramesAndWritesFramesCppReads) {
  const fs::path package = fs::path(SWEEPD_SOURCE_DIR) / "client_examples/python";
  ASSERT_TRUE(fs::exists(package / "sweepd/protocol/Message.py")) << package;
  // C++ → Python: a float16 reply for two vertices.
  const std::vector<float> positions = {0.5f, -1.25f, 3.0f, 0.1f, 100.0f, -0.0078125f};
  flatbuffers::FlatBufferBuilder builder;
  PosedVerticesFrame frame(builder, {.request_id = 7,
                                     .model_id = 1,
                                     .sequence = 31,
                                     .vertex_count = 2,
                                     .format = PositionFormat::Float16,
                                     .dropped_before = 4});
  encode_float16(positions, frame.positions_f16());
  const fs::path cpp_frame = directory_ / "posed.swpd", python_frame = directory_ / "hello.swpd";
  const fs::path script = directory_ / "exchange.py", printed = directory_ / "printed.txt";
  std::ofstream(cpp_frame, std::ios::binary)
      .write(reinterpret_cast<const char*>(frame.bytes().data()),
             static_cast<std::streamsize>(frame.bytes().size()));
  std::ofstream(script) << kScript;
  const std::string command = "PYTHONPATH=" + package.string() + " " + kPython + " " +
                              script.string() + " " + cpp_frame.string() + " " +
                              python_frame.string() + " > " + printed.string();
  ASSERT_EQ(std::system(command.c_str()), 0) << command;

  std::ifstream printed_stream(printed);
  std::uint64_t request_id = 0, sequence = 0, vertex_count = 0, dropped = 0;
  printed_stream >> request_id >> sequence >> vertex_count >> dropped;
  EXPECT_EQ(request_id, 7u);
  EXPECT_EQ(sequence, 31u);
  EXPECT_EQ(vertex_count, 2u);
  EXPECT_EQ(dropped, 4u);
  for (float position : positions) {
    double python_value = 0;
    ASSERT_TRUE(printed_stream >> python_value);
    // Python's '<e' and half_to_float both decode binary16 exactly: tolerance 0.
    EXPECT_EQ(python_value, static_cast<double>(half_to_float(float_to_half(position))));
  }

  // Python → C++: the Hello goes through the FrameReader like any socket bytes.
  std::ifstream hello_stream(python_frame, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(hello_stream)), {});
  FrameReader reader;
  std::span<const std::uint8_t> input(bytes);
  const FrameEvent event = reader.read(input);
  ASSERT_EQ(event.status, FrameStatus::kFrame) << event.reason;
  EXPECT_TRUE(input.empty());
  EXPECT_EQ(event.message->request_id(), 42u);
  const Hello* hello = event.message->body_as_Hello();
  ASSERT_NE(hello, nullptr);
  EXPECT_EQ(hello->version_major(), 1);
  EXPECT_EQ(hello->auth_token()->str(), "s3cret");
  EXPECT_EQ(hello->client_name()->str(), "python");
  EXPECT_EQ(hello->delivery(), PoseDelivery::LatestWins);
}

}  // namespace
}  // namespace sweepd::protocol

// The fuzzed entry points (fuzz/fuzz_inputs.h) in every test run: each target's seeds (valid
// inputs from sweepd's own writers) and every input a fuzzer once crashed on
// (fuzz/regressions/<target>/, kept for good) go through them without a crash or an escaping
// exception; and the seeds are valid, so the fuzzers start from inputs the parsers accept.
#include "fuzz/fuzz_inputs.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>

#include "fuzz/seed_inputs.h"
#include "protocol/framing.h"

namespace sweepd::fuzz {
namespace {

namespace fs = std::filesystem;

const std::map<std::string, std::function<bool(std::span<const std::uint8_t>)>> kTargets = {
    {"frames", fuzz_frames}, {"gltf", fuzz_gltf},           {"fbx", fuzz_fbx},
    {"bvh", fuzz_bvh},       {"sweepbind", fuzz_sweepbind}, {"json", fuzz_json},
    {"vmc", fuzz_vmc},       {"http", fuzz_http},           {"websocket", fuzz_websocket}};

const std::map<std::string, std::vector<Input>>& seeds() {
  static const auto all = seed_inputs();
  return all;
}

TEST(FuzzInputs, EverySeedIsAnInputItsParserAccepts) {
  // Not refusals: a fuzzer mutating a valid input reaches the code past the first check.
  for (const auto& [target, run] : kTargets) {
    ASSERT_TRUE(seeds().contains(target)) << target;
    EXPECT_FALSE(seeds().at(target).empty()) << target;
    for (std::size_t i = 0; i < seeds().at(target).size(); ++i)
      EXPECT_TRUE(run(seeds().at(target)[i])) << target << " seed " << i;
  }
}

TEST(FuzzInputs, DamagedInputsAreRefusedNotAccepted) {
  // The same entry points say no: a truncated .glb, FBX, .sweepbind, frame stream, VMC datagram,
  // request head and WebSocket session.
  for (const std::string target :
       {"frames", "gltf", "fbx", "sweepbind", "vmc", "http", "websocket"}) {
    Input cut = seeds().at(target).front();
    cut.resize(cut.size() / 2);
    EXPECT_FALSE(kTargets.at(target)(cut)) << target;
  }
}

TEST(FuzzInputs, TheFramesSeedIsAWholeSession) {
  // Every frame whole and verified (the first byte is the read size).
  const Input& frames = seeds().at("frames").front();
  std::span<const std::uint8_t> input(frames.data() + 1, frames.size() - 1);
  protocol::FrameReader reader;
  int whole = 0;
  for (protocol::FrameEvent event = reader.read(input);
       event.status != protocol::FrameStatus::kPending; event = reader.read(input)) {
    EXPECT_EQ(event.status, protocol::FrameStatus::kFrame) << event.reason;
    ++whole;
  }
  EXPECT_EQ(whole, 11) << "Hello, Pose, Pose into shared memory, LoadModel, EditKeyEllipse, "
                          "PositionMapRequest, UploadClip, PoseFromClip, PositionMapRequest of a "
                          "clip frame, PoseByName, ContactSheetRequest";
}

TEST(FuzzInputs, AnInputIsReadInAtMostFourThousandPieces) {
  // The WebSocket session's cost is per read (fuzz_inputs.h): fuzz_websocket's slow inputs
  // (fuzz/regressions/websocket/slow-*, 65 and 132 KB, first byte 0) were read a byte at a
  // time, 131,945 reads. Counted: each size's reads at most kMostReads, exactly.
  for (const std::size_t size : {0, 1, 4095, 4096, 4097, 64'991, 131'945, 1 << 20}) {
    for (const int first : {0, 7, 255}) {
      const std::size_t piece = read_bytes(static_cast<std::uint8_t>(first), size);
      const std::size_t reads = (size + piece - 1) / piece;
      EXPECT_LE(reads, kMostReads) << size << " bytes, first byte " << first;
      EXPECT_GE(piece, static_cast<std::size_t>(first) + 1)
          << "never finer than the first byte asks";
    }
  }
  // Up to 4 KiB the first byte alone says: a byte at a time is still tried.
  EXPECT_EQ(read_bytes(0, 4096), 1u);
  EXPECT_EQ(read_bytes(0, 4097), 2u);
  EXPECT_EQ(read_bytes(0, 131'945), 33u);  // 3,999 reads, not 131,945
  EXPECT_EQ(read_bytes(99, 131'945), 100u);
}

TEST(FuzzInputs, EveryRegressionStillPasses) {
  const fs::path root = fs::path(SWEEPD_SOURCE_DIR) / "fuzz" / "regressions";
  int replayed = 0;
  for (const auto& [target, run] : kTargets) {
    const fs::path folder = root / target;
    if (!fs::is_directory(folder)) continue;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
      std::ifstream in(entry.path(), std::ios::binary);
      const Input bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      EXPECT_NO_THROW(run(bytes)) << entry.path();  // accepted or refused, never a crash
      ++replayed;
    }
  }
  std::printf("%d fuzzer regressions replayed\n", replayed);
}

}  // namespace
}  // namespace sweepd::fuzz

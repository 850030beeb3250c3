// sweepctl --server positionmap: the daemon's EXR (its GPU worker, llvmpipe here) decodes to
// the same positions and coverage as the local `sweepctl positionmap` with the server's
// 4-texel gutter; another gutter is refused with the reason.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <gtest/gtest.h>

#include "tests/io/position_map_exr.h"
#include "tests/server/sweepctl_remote.h"

namespace sweepd::test {
namespace {

constexpr int kSide = 64;

// The channels `names` of an EXR file, one float plane each.
std::vector<std::vector<float>> read_planes(const fs::path& file,
                                            const std::vector<std::string>& names) {
  Imf::InputFile input(file.c_str());
  const Imath::Box2i window = input.header().dataWindow();
  const int width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
  EXPECT_EQ(width, kSide);
  EXPECT_EQ(height, kSide);
  std::vector<std::vector<float>> planes(
      names.size(), std::vector<float>(static_cast<std::size_t>(kSide) * kSide));
  if (width != kSide || height != kSide) return planes;
  Imf::FrameBuffer frame_buffer;
  for (std::size_t c = 0; c < names.size(); ++c) {
    EXPECT_NE(input.header().channels().findChannel(names[c]), nullptr) << names[c];
    frame_buffer.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(planes[c].data()),
                                             sizeof(float), sizeof(float) * kSide));
  }
  input.setFrameBuffer(frame_buffer);
  input.readPixels(window.min.y, window.max.y);
  return planes;
}

TEST_F(SweepctlRemote, RemotePositionMapDecodesToTheLocalPositions) {
  const std::string map = "positionmap " + kSharedMale.string() + " --bvh " + kClip.string() +
                          " --frame " + std::to_string(kClipFrame) + " --size " +
                          std::to_string(kSide) + " -o ";
  // The local map's run without LeakSanitizer: under the asan preset its tracer thread crashed
  // (signal 11) at this run's exit only when started from this test, never by hand with the same
  // options (stop 62, not explained); ASan's other checks stay on, and the remote run below and
  // every other sweepctl run keep the leak check.
  const ClientRun local = run_client("env ASAN_OPTIONS=\"${ASAN_OPTIONS}:detect_leaks=0\" " +
                                     std::string(SWEEPD_SWEEPCTL) + " " + map +
                                     path("local.exr").string() + " --gutter 4");
  ASSERT_EQ(local.exit_code, 0) << local.output;
  const ClientRun remote = run_sweepctl(server() + " " + map + path("remote.exr").string());
  ASSERT_EQ(remote.exit_code, 0) << remote.output << log();

  // The header says the same of both: the clip frame asked for, the pose's hash (the server's
  // retargeting is the library's), the units (issue 52 item 6).
  const io::test_support::PositionMapHeader local_header = io::test_support::read_position_map_header(
      Imf::InputFile(path("local.exr").c_str()).header());
  const io::test_support::PositionMapHeader remote_header =
      io::test_support::read_position_map_header(Imf::InputFile(path("remote.exr").c_str()).header());
  EXPECT_EQ(local_header.frame, kClipFrame);
  EXPECT_EQ(remote_header.frame, kClipFrame);
  EXPECT_EQ(remote_header.pose_hash, local_header.pose_hash);
  EXPECT_NE(remote_header.pose_hash, io::test_support::pose_hash_text(0)) << "a hash, not none";
  EXPECT_EQ(remote_header.units, "metres");
  EXPECT_EQ(remote_header.model, local_header.model);

  const std::vector<std::string> channels = {"P.X", "P.Y", "P.Z", "A"};
  const auto expected = read_planes(path("local.exr"), channels);
  const auto served = read_planes(path("remote.exr"), channels);
  // The same deformed positions rasterised by the same renderer, stored as float32: equal
  // within float32 round-off of a metre-sized body (1e-6 m).
  double worst = 0.0;
  for (int c = 0; c < 3; ++c)
    for (std::size_t t = 0; t < expected[c].size(); ++t)
      worst = std::max(worst, double{std::abs(served[c][t] - expected[c][t])});
  EXPECT_LE(worst, 1e-6);
  EXPECT_EQ(served[3], expected[3]) << "coverage";
  int covered = 0;
  for (float a : served[3]) covered += a == 1.0f;
  EXPECT_GT(covered, kSide * kSide / 10) << "the UV charts cover a real share of the map";
}

TEST_F(SweepctlRemote, RemotePositionMapRefusesAGutterTheServerDoesNotRender) {
  const ClientRun result = run_sweepctl(server() + " positionmap mannequin --size 16 " +
                                        "--gutter 2 -o " + path("never.exr").string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("4-texel gutter"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace sweepd::test

// PositionMapRequest over localhost: the daemon renders the posed mannequin into UV space on
// its GPU worker (llvmpipe here) and sends an OpenEXR file whose P and A channels must equal
// what the library renders in this process for the same bound model and pose.
#include <ImfChannelList.h>
#include <ImfInputFile.h>
#include <gtest/gtest.h>
#include <half.h>

#include <cstring>

#include "gpu/egl_context.h"
#include "gpu/position_map_renderer.h"
#include "io/sweepbind/sweepbind.h"
#include "tests/io/exr_memory_stream.h"
#include "tests/io/position_map_exr.h"
#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"
#include "tests/server/stored_binding.h"

namespace sweepd::test {
namespace {

constexpr int kSide = 96;

io::test_support::DecodedPositionMap decode(const std::vector<std::uint8_t>& bytes) {
  io::test_support::ExrMemoryStream stream(bytes);
  Imf::InputFile file(stream);
  return io::test_support::decode_position_map(file);
}

class DaemonPositionMap : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fresh_directory("position_map");
    daemon_ = std::make_unique<DaemonProcess>(directory_, std::vector<std::string>{});
    ASSERT_TRUE(daemon_->running()) << daemon_->log();
    client_ = std::make_unique<FrameClient>(daemon_->port());
    const protocol::Welcome* welcome = client_->hello("");
    ASSERT_NE(welcome, nullptr);
    bool offered = false;
    for (const auto* c : *welcome->capabilities()) offered |= c->str() == "position_map";
    EXPECT_TRUE(offered) << "position_map missing from Welcome.capabilities";
  }
  void TearDown() override {
    client_.reset();
    daemon_.reset();
    fs::remove_all(directory_);
  }
  void request(std::uint32_t width, std::uint32_t height, protocol::ExrCompression compression,
               std::span<const protocol::Quat> rotations, bool half_normals = false) {
    flatbuffers::FlatBufferBuilder builder;
    const auto pose = protocol::add_pose(builder, pose_fields(daemon_->model_id(), 5, rotations));
    const auto layers = protocol::MapLayers::Position | protocol::MapLayers::Coverage |
                        (half_normals ? protocol::MapLayers::Normal : protocol::MapLayers::NONE);
    client_->send_bytes(protocol::finish_message(
        builder,
        protocol::CreatePositionMapRequest(builder, pose, width, height, compression, layers,
                                           half_normals),
        31));
  }

  fs::path directory_;
  std::unique_ptr<DaemonProcess> daemon_;
  std::unique_ptr<FrameClient> client_;
};

TEST_F(DaemonPositionMap, ExrDecodesToTheLibrarysOwnRenderOfThePose) {
  const deform::BoundModel bound =
      io::load_sweepbind(stored_binding(directory_ / "store", "mannequin"));
  const std::vector<glm::quat> rotations = bent_rotations(bound.model.skeleton.joints.size());
  const std::vector<protocol::Quat> wire = to_wire(rotations);
  request(kSide, kSide, protocol::ExrCompression::Zip, wire);
  const protocol::PositionMap* reply = client_->receive_as<protocol::PositionMap>();
  ASSERT_NE(reply, nullptr);
  EXPECT_EQ(reply->sequence(), 5u);
  EXPECT_EQ(reply->width(), static_cast<std::uint32_t>(kSide));
  const std::vector<std::uint8_t> exr(reply->exr()->begin(), reply->exr()->end());
  const io::test_support::DecodedPositionMap served = decode(exr);
  ASSERT_EQ(served.width, kSide);
  ASSERT_EQ(served.height, kSide);

  // The same pose rendered here with the same renderer (the server uses a 4-texel gutter).
  const Deformed posed = library_deformation(bound, rotations, deform::DeformMethod::kSweep);
  gpu::Context context;
  gpu::PositionMapRenderer renderer(context);
  std::vector<float> p(kSide * kSide * 3), a(kSide * kSide);
  renderer.render({bound.model.uvs, posed.positions, {}, bound.model.indices},
                  {.width = kSide, .height = kSide, .gutter_pixels = 4, .view = std::nullopt},
                  {p, {}, a});
  // Exact: same inputs, same rasteriser; EXR stores float32 losslessly (ZIP).
  EXPECT_EQ(std::memcmp(served.positions.data(), p.data(), p.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(served.coverage.data(), a.data(), a.size() * sizeof(float)), 0);
  int covered = 0;
  for (float value : served.coverage) covered += value == 1.0f;
  EXPECT_GT(covered, kSide * kSide / 10) << "the UV charts cover a real share of the map";
}

// half_normals: the N channels come back HALF, each the library's normal rounded to the nearest
// half; P stays FLOAT and equal to the library's bit for bit.
TEST_F(DaemonPositionMap, HalfNormalsAreTheLibrarysNormalsRoundedToHalf) {
  const deform::BoundModel bound =
      io::load_sweepbind(stored_binding(directory_ / "store", "mannequin"));
  const std::vector<glm::quat> rotations = bent_rotations(bound.model.skeleton.joints.size());
  request(kSide, kSide, protocol::ExrCompression::Zip, to_wire(rotations), /*half_normals=*/true);
  const protocol::PositionMap* reply = client_->receive_as<protocol::PositionMap>();
  ASSERT_NE(reply, nullptr);
  const std::vector<std::uint8_t> exr(reply->exr()->begin(), reply->exr()->end());
  io::test_support::ExrMemoryStream stream(exr);
  Imf::InputFile file(stream);
  ASSERT_NE(file.header().channels().findChannel("N.X"), nullptr);
  EXPECT_EQ(file.header().channels().findChannel("N.X")->type, Imf::HALF);
  EXPECT_EQ(file.header().channels().findChannel("P.X")->type, Imf::FLOAT);
  std::vector<float> served(kSide * kSide * 3);
  Imf::FrameBuffer normals;
  const char* channels[3] = {"N.X", "N.Y", "N.Z"};
  for (int c = 0; c < 3; ++c)
    normals.insert(channels[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(served.data() + c),
                                           3 * sizeof(float), 3 * sizeof(float) * kSide));
  file.setFrameBuffer(normals);
  file.readPixels(0, kSide - 1);

  const Deformed posed = library_deformation(bound, rotations, deform::DeformMethod::kSweep);
  gpu::Context context;
  gpu::PositionMapRenderer renderer(context);
  std::vector<float> p(kSide * kSide * 3), n(kSide * kSide * 3), a(kSide * kSide);
  renderer.render({bound.model.uvs, posed.positions, posed.normals, bound.model.indices},
                  {.width = kSide, .height = kSide, .gutter_pixels = 4, .view = std::nullopt},
                  {p, n, a});
  // Exact: the same float normals, rounded by the same conversion (OpenEXR's to half).
  int covered = 0;
  for (std::size_t i = 0; i < n.size(); ++i) {
    ASSERT_EQ(served[i], static_cast<float>(Imath::half(n[i]))) << i;
    covered += n[i] != 0.0f;
  }
  EXPECT_GT(covered, kSide * kSide / 10) << "normals were rendered, not only zeros";
}

TEST_F(DaemonPositionMap, ZeroSizedMapIsAnInvalidArgument) {
  const std::vector<protocol::Quat> wire = to_wire(bent_rotations(31));
  request(0, 0, protocol::ExrCompression::Zip, wire);
  const protocol::Error* error = client_->receive_as<protocol::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), protocol::ErrorCode::InvalidArgument);
  EXPECT_NE(error->message()->str().find("0 x 0"), std::string::npos) << error->message()->str();
}

TEST_F(DaemonPositionMap, UnofferedCompressionIsAnInvalidArgument) {
  const std::vector<protocol::Quat> wire = to_wire(bent_rotations(31));
  request(kSide, kSide, protocol::ExrCompression::Rle, wire);
  const protocol::Error* error = client_->receive_as<protocol::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), protocol::ErrorCode::InvalidArgument);
  EXPECT_NE(error->message()->str().find("Rle"), std::string::npos) << error->message()->str();
}

}  // namespace
}  // namespace sweepd::test

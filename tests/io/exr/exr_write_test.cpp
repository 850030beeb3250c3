// Tests for io::write_exr / io::encode_exr: files read back with OpenEXR's own InputFile give the
// same floats bit for bit under every compression, the channels and header attributes asked
// for, and bad inputs fail with a reason.
#include "io/exr/exr_write.h"

#include <ImfChannelList.h>
#include <ImfCheckFile.h>
#include <ImfCompressionAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfStringAttribute.h>
#include <gtest/gtest.h>
#include <half.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "tests/io/exr_memory_stream.h"
#include "tests/scratch_directory.h"

namespace sweepd::io::exr_write_test {
namespace {

namespace fs = std::filesystem;
using test_support::ExrMemoryStream;

// A 37 x 23 map (odd sizes catch stride mistakes) of random floats plus special values.
struct Layers {
  static constexpr int kWidth = 37, kHeight = 23;
  std::vector<float> positions, normals, coverage;
  Layers() {
    std::mt19937 random(7);
    std::uniform_real_distribution<float> value(-3.0f, 3.0f);
    for (int i = 0; i < kWidth * kHeight * 3; ++i) positions.push_back(value(random));
    for (int i = 0; i < kWidth * kHeight * 3; ++i) normals.push_back(value(random));
    for (int i = 0; i < kWidth * kHeight; ++i) coverage.push_back(i % 3 == 0 ? 0.0f : 1.0f);
    positions[0] = -0.0f;
    positions[1] = std::numeric_limits<float>::denorm_min();
    positions[2] = std::numeric_limits<float>::infinity();
    positions[3] = std::numeric_limits<float>::max();
  }
  ExrLayers view(bool with_normals = true, bool with_coverage = true) const {
    return {kWidth, kHeight, positions, with_normals ? normals : std::span<const float>{},
            with_coverage ? coverage : std::span<const float>{}};
  }
};

ExrOptions sample_options(ExrCompression compression) {
  ExrOptions options;
  options.compression = compression;
  options.model = "mannequin";
  options.frame = 42;
  options.pose_hash = 0x0123456789abcdefull;
  options.space = "camera";
  return options;
}

// Reads `channel` (FLOAT) of every pixel into out[i * stride + offset].
void read_channel(Imf::InputFile& file, const char* channel, std::vector<float>& out,
                  int components, int offset) {
  const Imath::Box2i window = file.header().dataWindow();
  const int width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
  out.resize(static_cast<std::size_t>(width) * height * components);
  Imf::FrameBuffer frame_buffer;
  frame_buffer.insert(channel,
                      Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(out.data() + offset),
                                 sizeof(float) * components, sizeof(float) * components * width));
  file.setFrameBuffer(frame_buffer);
  file.readPixels(window.min.y, window.max.y);
}

std::vector<float> read_layer(Imf::InputFile& file, const std::string& name, int components) {
  std::vector<float> values;
  if (components == 1) {
    read_channel(file, name.c_str(), values, 1, 0);
    return values;
  }
  const char* axes[3] = {".X", ".Y", ".Z"};
  for (int c = 0; c < components; ++c) read_channel(file, (name + axes[c]).c_str(), values, 3, c);
  return values;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

class ExrWriteTest : public ::testing::Test {
 protected:
  test::ScratchDirectory scratch_{"exr_write"};
};

class ExrCompressionTest : public ExrWriteTest,
                           public ::testing::WithParamInterface<ExrCompression> {};

TEST_P(ExrCompressionTest, FileReadsBackBitExactWithChannelsAndAttributes) {
  const Layers layers;
  const fs::path file = scratch_ / "frame.exr";
  write_exr(file, layers.view(), sample_options(GetParam()));

  Imf::InputFile input(file.c_str());
  const Imf::Header& header = input.header();
  const Imath::Box2i window = header.dataWindow();
  EXPECT_EQ(window.min, Imath::V2i(0, 0));
  EXPECT_EQ(window.max, Imath::V2i(Layers::kWidth - 1, Layers::kHeight - 1));
  std::vector<std::string> channels;
  for (auto c = header.channels().begin(); c != header.channels().end(); ++c) {
    channels.push_back(c.name());
    EXPECT_EQ(c.channel().type, Imf::FLOAT) << c.name();
  }
  EXPECT_EQ(channels, (std::vector<std::string>{"A", "N.X", "N.Y", "N.Z", "P.X", "P.Y", "P.Z"}));
  const Imf::Compression expected_compression[] = {Imf::NO_COMPRESSION, Imf::ZIP_COMPRESSION,
                                                   Imf::ZIPS_COMPRESSION, Imf::PIZ_COMPRESSION};
  EXPECT_EQ(header.compression(), expected_compression[static_cast<int>(GetParam())]);
  ASSERT_NE(header.findTypedAttribute<Imf::StringAttribute>("model"), nullptr);
  EXPECT_EQ(header.typedAttribute<Imf::StringAttribute>("model").value(), "mannequin");
  ASSERT_NE(header.findTypedAttribute<Imf::IntAttribute>("frame"), nullptr);
  EXPECT_EQ(header.typedAttribute<Imf::IntAttribute>("frame").value(), 42);
  ASSERT_NE(header.findTypedAttribute<Imf::StringAttribute>("poseHash"), nullptr);
  EXPECT_EQ(header.typedAttribute<Imf::StringAttribute>("poseHash").value(), "0123456789abcdef");
  ASSERT_NE(header.findTypedAttribute<Imf::StringAttribute>("space"), nullptr);
  EXPECT_EQ(header.typedAttribute<Imf::StringAttribute>("space").value(), "camera");
  ASSERT_NE(header.findTypedAttribute<Imf::StringAttribute>("units"), nullptr);
  EXPECT_EQ(header.typedAttribute<Imf::StringAttribute>("units").value(), "metres");

  EXPECT_TRUE(same_bits(read_layer(input, "P", 3), layers.positions));
  EXPECT_TRUE(same_bits(read_layer(input, "N", 3), layers.normals));
  EXPECT_TRUE(same_bits(read_layer(input, "A", 1), layers.coverage));
}

INSTANTIATE_TEST_SUITE_P(AllCompressions, ExrCompressionTest,
                         ::testing::Values(ExrCompression::kNone, ExrCompression::kZip,
                                           ExrCompression::kZips, ExrCompression::kPiz));

TEST_F(ExrWriteTest, MemoryBytesEqualTheFileAndReadBack) {
  const Layers layers;
  const fs::path file = scratch_ / "frame.exr";
  write_exr(file, layers.view(), sample_options(ExrCompression::kZip));
  std::vector<std::uint8_t> bytes;
  bytes.reserve(1);
  encode_exr(layers.view(), sample_options(ExrCompression::kZip), bytes);
  std::ifstream in(file, std::ios::binary);
  const std::vector<std::uint8_t> on_disk((std::istreambuf_iterator<char>(in)),
                                          std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes, on_disk);

  ExrMemoryStream stream(bytes);
  Imf::InputFile input(stream);
  EXPECT_TRUE(same_bits(read_layer(input, "P", 3), layers.positions));
  // A second encode into the same vector replaces its content.
  encode_exr(layers.view(false, false), sample_options(ExrCompression::kNone), bytes);
  ExrMemoryStream again(bytes);
  Imf::InputFile second(again);
  EXPECT_EQ(second.header().compression(), Imf::NO_COMPRESSION);
  EXPECT_EQ(second.header().channels().findChannel("A"), nullptr);
  EXPECT_TRUE(same_bits(read_layer(second, "P", 3), layers.positions));
}

TEST_F(ExrWriteTest, OptionalLayersAreLeftOutWhenEmpty) {
  const Layers layers;
  std::vector<std::uint8_t> bytes;
  encode_exr(layers.view(false, true), {}, bytes);
  ExrMemoryStream stream(bytes);
  Imf::InputFile input(stream);
  std::vector<std::string> channels;
  for (auto c = input.header().channels().begin(); c != input.header().channels().end(); ++c)
    channels.push_back(c.name());
  EXPECT_EQ(channels, (std::vector<std::string>{"A", "P.X", "P.Y", "P.Z"}));
  EXPECT_EQ(input.header().compression(), Imf::ZIP_COMPRESSION);  // the default
  EXPECT_EQ(input.header().typedAttribute<Imf::StringAttribute>("space").value(), "object");
}

TEST_F(ExrWriteTest, ZipCompressesASmoothMap) {
  // A smooth ramp compresses: ZIP output is smaller than NONE (the option reaches the encoder).
  std::vector<float> ramp(64 * 64 * 3);
  for (std::size_t i = 0; i < ramp.size(); ++i) ramp[i] = static_cast<float>(i / 3 % 64) * 0.01f;
  const ExrLayers layers{64, 64, ramp, {}, {}};
  std::vector<std::uint8_t> none, zip;
  ExrOptions options;
  options.compression = ExrCompression::kNone;
  encode_exr(layers, options, none);
  options.compression = ExrCompression::kZip;
  encode_exr(layers, options, zip);
  EXPECT_LT(zip.size() * 2, none.size());
}

// The zip level reaches zlib: level 9 makes a smaller file of the same ramp than level 1 (the
// ramp is long-range repetitive, which zlib's faster levels search less), and both read back
// bit for bit — the level trades time for bytes, never values.
TEST_F(ExrWriteTest, ZipLevelTradesBytesNotValues) {
  const Layers layers;
  std::vector<float> ramp(256 * 256 * 3);
  for (std::size_t i = 0; i < ramp.size(); ++i)
    ramp[i] = static_cast<float>(i / 3 % 256) * 0.01f + static_cast<float>(i % 3);
  const ExrLayers big{256, 256, ramp, {}, {}};
  std::vector<std::uint8_t> fast, small;
  ExrOptions options;
  options.zip_level = 1;
  encode_exr(big, options, fast);
  options.zip_level = 9;
  encode_exr(big, options, small);
  EXPECT_LT(small.size(), fast.size());
  for (const std::vector<std::uint8_t>* bytes : {&fast, &small}) {
    ExrMemoryStream stream(*bytes);
    Imf::InputFile input(stream);
    EXPECT_TRUE(same_bits(read_layer(input, "P", 3), ramp));
  }
  options.zip_level = 0;
  EXPECT_NE(validate_exr(layers.view(), options).find("zip level 0"), std::string::npos);
}

// Half normals: the N channels are HALF and hold each float rounded to the nearest half (what
// Imath::half's conversion gives, exactly); the positions and coverage stay FLOAT, bit for bit;
// and the file is smaller by about the normals' half of their bytes.
TEST_F(ExrWriteTest, HalfNormalsRoundEachNormalAndKeepPositionsFloat) {
  const Layers layers;
  std::vector<std::uint8_t> full, half;
  ExrOptions options = sample_options(ExrCompression::kNone);
  encode_exr(layers.view(), options, full);
  options.half_normals = true;
  encode_exr(layers.view(), options, half);
  ExrMemoryStream stream(half);
  Imf::InputFile input(stream);
  for (auto c = input.header().channels().begin(); c != input.header().channels().end(); ++c)
    EXPECT_EQ(c.channel().type, std::string(c.name()).starts_with("N.") ? Imf::HALF : Imf::FLOAT)
        << c.name();
  EXPECT_TRUE(same_bits(read_layer(input, "P", 3), layers.positions));
  EXPECT_TRUE(same_bits(read_layer(input, "A", 1), layers.coverage));
  const std::vector<float> normals = read_layer(input, "N", 3);
  ASSERT_EQ(normals.size(), layers.normals.size());
  for (std::size_t i = 0; i < normals.size(); ++i)
    ASSERT_EQ(normals[i], static_cast<float>(Imath::half(layers.normals[i]))) << i;
  // Uncompressed, the header and line table are the same size: 3 channels of 2 bytes fewer a
  // texel, exactly.
  EXPECT_EQ(full.size() - half.size(),
            static_cast<std::size_t>(Layers::kWidth * Layers::kHeight * 3 * 2));
}

TEST_F(ExrWriteTest, EncodingWithThreadsGivesTheSameBytes) {
  const Layers layers;
  for (const ExrCompression compression : {ExrCompression::kPiz, ExrCompression::kZip}) {
    std::vector<std::uint8_t> single, threaded;
    set_exr_threads(0);
    encode_exr(layers.view(), sample_options(compression), single);
    set_exr_threads(4);
    encode_exr(layers.view(), sample_options(compression), threaded);
    set_exr_threads(0);
    EXPECT_EQ(single, threaded);
  }
}

// OpenEXR's own checker (exrcheck's): true when reading the file in its several ways threw.
bool openexr_finds_problems(const std::vector<std::uint8_t>& bytes) {
  return Imf::checkOpenEXRFile(reinterpret_cast<const char*>(bytes.data()), bytes.size(),
                               /*reduceMemory=*/false, /*reduceTime=*/false,
                               /*runCoreCheck=*/true);
}

// ZIP is written here with libdeflate (io/exr/exr_zip_encode.h), not by OpenEXR: OpenEXR's own
// checker finds nothing wrong with the file, and it decodes to the same bits as OpenEXR's own
// ZIP of the same layers — with and without normals (FLOAT and HALF) and coverage, for a map
// whose last block is short (23 lines) and one of several full blocks with a partial one.
TEST_F(ExrWriteTest, LibdeflateZipDecodesAsOpenExrsOwnZip) {
  const Layers layers;
  std::vector<float> ramp(300 * 70 * 3), ones(300 * 70, 1.0f);
  for (std::size_t i = 0; i < ramp.size(); ++i)
    ramp[i] = std::sin(static_cast<float>(i) * 0.001f) + static_cast<float>(i % 3);
  const ExrLayers wide{300, 70, ramp, ramp, ones};
  for (const ExrLayers& view : {layers.view(), layers.view(false, true), layers.view(true, false),
                                layers.view(false, false), wide}) {
    for (const bool half_normals : {false, true}) {
      ExrOptions options = sample_options(ExrCompression::kZip);
      options.half_normals = half_normals;
      std::vector<std::uint8_t> ours, openexr;
      encode_exr(view, options, ours);
      options.openexr_zip = true;
      encode_exr(view, options, openexr);
      EXPECT_FALSE(openexr_finds_problems(ours));
      EXPECT_TRUE(openexr_finds_problems({ours.begin(), ours.begin() + ours.size() / 2}))
          << "the checker's answer for a file cut in half";
      ExrMemoryStream our_stream(ours), their_stream(openexr);
      Imf::InputFile mine(our_stream), theirs(their_stream);
      EXPECT_EQ(mine.header().compression(), Imf::ZIP_COMPRESSION);
      for (auto c = theirs.header().channels().begin(); c != theirs.header().channels().end();
           ++c) {
        const Imf::Channel* channel = mine.header().channels().findChannel(c.name());
        ASSERT_NE(channel, nullptr) << c.name();
        EXPECT_EQ(channel->type, c.channel().type) << c.name();
        std::vector<float> a, b;
        read_channel(mine, c.name(), a, 1, 0);
        read_channel(theirs, c.name(), b, 1, 0);
        EXPECT_TRUE(same_bits(a, b)) << c.name();
      }
      EXPECT_EQ(mine.header().channels().begin().name(),
                std::string(theirs.header().channels().begin().name()));
      for (const char* name : {"model", "poseHash", "space", "units"}) {
        EXPECT_EQ(mine.header().typedAttribute<Imf::StringAttribute>(name).value(),
                  theirs.header().typedAttribute<Imf::StringAttribute>(name).value())
            << name;
      }
      EXPECT_EQ(mine.header().typedAttribute<Imf::IntAttribute>("frame").value(), 42);
      // libdeflate's level 1 finds at least as much as zlib's here (within 2 %).
      EXPECT_LT(static_cast<double>(ours.size()), 1.02 * static_cast<double>(openexr.size()));
    }
  }
}

TEST_F(ExrWriteTest, BadInputsSayWhatIsWrong) {
  const Layers layers;
  ExrLayers short_positions = layers.view();
  short_positions.positions = short_positions.positions.first(10);
  EXPECT_NE(validate_exr(short_positions, {}).find("positions hold 10 floats"), std::string::npos);
  std::vector<std::uint8_t> bytes;
  EXPECT_THROW(encode_exr(short_positions, {}, bytes), std::invalid_argument);
  ExrLayers short_coverage = layers.view();
  short_coverage.coverage = short_coverage.coverage.first(5);
  EXPECT_NE(validate_exr(short_coverage, {}).find("coverage"), std::string::npos);
  ExrOptions bad_space;
  bad_space.space = "world";
  EXPECT_NE(validate_exr(layers.view(), bad_space).find("world"), std::string::npos);
  EXPECT_NE(validate_exr({0, 5, {}, {}, {}}, {}).find("not positive"), std::string::npos);
  EXPECT_EQ(validate_exr(layers.view(), {}), "");

  const fs::path unwritable = scratch_ / "missing_folder" / "frame.exr";
  try {
    write_exr(unwritable, layers.view());
    FAIL() << "writing into a missing folder succeeded";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(unwritable.string()), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace sweepd::io::exr_write_test

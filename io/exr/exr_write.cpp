#include "io/exr/exr_write.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfIntAttribute.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <ImfThreading.h>
#include <half.h>

#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <type_traits>

#include "io/exr/exr_zip_encode.h"
#include "io/files/write_whole_file.h"

namespace sweepd::io {
namespace {

// An Imf::OStream over a caller's byte vector; OpenEXR seeks back to fill in the offset table.
class ByteVectorStream : public Imf::OStream {
 public:
  explicit ByteVectorStream(std::vector<std::uint8_t>& bytes)
      : Imf::OStream("memory"), bytes_(bytes) {
    bytes_.clear();
  }
  void write(const char c[], int n) override {
    const std::size_t end = position_ + static_cast<std::size_t>(n);
    if (end > bytes_.size()) bytes_.resize(end);
    std::memcpy(bytes_.data() + position_, c, static_cast<std::size_t>(n));
    position_ = end;
  }
  std::uint64_t tellp() override { return position_; }
  void seekp(std::uint64_t position) override { position_ = position; }

 private:
  std::vector<std::uint8_t>& bytes_;
  std::size_t position_ = 0;
};

Imf::Compression to_imf(ExrCompression compression) {
  switch (compression) {
    case ExrCompression::kNone:
      return Imf::NO_COMPRESSION;
    case ExrCompression::kZips:
      return Imf::ZIPS_COMPRESSION;
    case ExrCompression::kPiz:
      return Imf::PIZ_COMPRESSION;
    case ExrCompression::kZip:
      break;
  }
  return Imf::ZIP_COMPRESSION;
}

// Adds channels <prefix>X, Y, Z (or just <prefix> for one component) reading `values`, whose
// elements are `type` (FLOAT, or HALF) — the file's channels are the same type: OpenEXR's writer
// does not convert.
template <typename Value>
void add_layer(Imf::Header& header, Imf::FrameBuffer& frame_buffer, const ExrLayers& layers,
               std::span<const Value> values, const std::string& name, int components) {
  constexpr Imf::PixelType type = std::is_same_v<Value, Imath::half> ? Imf::HALF : Imf::FLOAT;
  const std::size_t x_stride = sizeof(Value) * components;
  const std::size_t y_stride = x_stride * static_cast<std::size_t>(layers.width);
  static const char* const kAxes[3] = {".X", ".Y", ".Z"};
  for (int c = 0; c < components; ++c) {
    const std::string channel = components == 1 ? name : name + kAxes[c];
    header.channels().insert(channel, Imf::Channel(type));
    // OpenEXR's Slice takes a non-const pointer but only reads from it when writing.
    char* base = reinterpret_cast<char*>(const_cast<Value*>(values.data() + c));
    frame_buffer.insert(channel, Imf::Slice(type, base, x_stride, y_stride));
  }
}

std::string hex16(std::uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

}  // namespace

std::string validate_exr(const ExrLayers& layers, const ExrOptions& options) {
  if (layers.width < 1 || layers.height < 1) {
    return "image size " + std::to_string(layers.width) + "x" + std::to_string(layers.height) +
           " is not positive";
  }
  const std::size_t texels = static_cast<std::size_t>(layers.width) * layers.height;
  if (layers.positions.size() != texels * 3) {
    return "positions hold " + std::to_string(layers.positions.size()) +
           " floats, not W*H*3 = " + std::to_string(texels * 3);
  }
  if (!layers.normals.empty() && layers.normals.size() != texels * 3) {
    return "normals hold " + std::to_string(layers.normals.size()) +
           " floats, not W*H*3 = " + std::to_string(texels * 3);
  }
  if (!layers.coverage.empty() && layers.coverage.size() != texels) {
    return "coverage holds " + std::to_string(layers.coverage.size()) +
           " floats, not W*H = " + std::to_string(texels);
  }
  if (options.zip_level < 1 || options.zip_level > 9) {
    return "zip level " + std::to_string(options.zip_level) + " is not 1 to 9";
  }
  if (options.space != "object" && options.space != "camera") {
    return "space is \"" + options.space + "\", not \"object\" or \"camera\"";
  }
  return {};
}

void encode_exr(const ExrLayers& layers, const ExrOptions& options,
                std::vector<std::uint8_t>& bytes) {
  if (const std::string problem = validate_exr(layers, options); !problem.empty()) {
    throw std::invalid_argument("EXR position map: " + problem);
  }
  if (options.compression == ExrCompression::kZip && !options.openexr_zip) {  // libdeflate
    encode_zip_exr(layers, options, bytes);
    return;
  }
  Imf::Header header(layers.width, layers.height);
  header.compression() = to_imf(options.compression);
  header.zipCompressionLevel() = options.zip_level;
  header.insert("model", Imf::StringAttribute(options.model));
  header.insert("frame", Imf::IntAttribute(options.frame));
  header.insert("poseHash", Imf::StringAttribute(hex16(options.pose_hash)));
  header.insert("space", Imf::StringAttribute(options.space));
  header.insert("units", Imf::StringAttribute(options.units));
  Imf::FrameBuffer frame_buffer;
  add_layer(header, frame_buffer, layers, layers.positions, "P", 3);
  // Half normals are rounded here, into scratch this thread keeps between frames.
  thread_local std::vector<Imath::half> half_normals;
  if (!layers.normals.empty() && options.half_normals) {
    half_normals.assign(layers.normals.begin(), layers.normals.end());
    add_layer(header, frame_buffer, layers, std::span<const Imath::half>(half_normals), "N", 3);
  } else if (!layers.normals.empty()) {
    add_layer(header, frame_buffer, layers, layers.normals, "N", 3);
  }
  if (!layers.coverage.empty()) add_layer(header, frame_buffer, layers, layers.coverage, "A", 1);
  ByteVectorStream stream(bytes);
  Imf::OutputFile file(stream, header);
  file.setFrameBuffer(frame_buffer);
  file.writePixels(layers.height);
}

void write_exr(const std::filesystem::path& file, const ExrLayers& layers,
               const ExrOptions& options) {
  std::vector<std::uint8_t> bytes;
  encode_exr(layers, options, bytes);
  write_whole_file(file, bytes, "write_exr");
}

void set_exr_threads(int threads) { Imf::setGlobalThreadCount(threads < 0 ? 0 : threads); }

}  // namespace sweepd::io

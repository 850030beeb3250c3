// Reads a sweepd EXR position map back with OpenEXR itself: the positions P.X, P.Y, P.Z
// interleaved per texel (x y z, rows top to bottom, as gpu::PositionMapRenderer fills them) and
// the coverage A, for comparison with the library's own render; and the header attributes that
// say what the map is (model, frame, poseHash, space, units), to check against the request.
#pragma once

#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfStringAttribute.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace sweepd::io::test_support {

struct DecodedPositionMap {
  int width = 0, height = 0;
  std::vector<float> positions, coverage;  // width·height·3, width·height
};

inline DecodedPositionMap decode_position_map(Imf::InputFile& file) {
  const Imath::Box2i window = file.header().dataWindow();
  DecodedPositionMap map;
  map.width = window.max.x - window.min.x + 1;
  map.height = window.max.y - window.min.y + 1;
  const std::size_t texels = static_cast<std::size_t>(map.width) * map.height;
  map.positions.resize(texels * 3);
  map.coverage.resize(texels);
  Imf::FrameBuffer frame_buffer;
  const char* channels[3] = {"P.X", "P.Y", "P.Z"};
  for (int c = 0; c < 3; ++c) {
    frame_buffer.insert(channels[c],
                        Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(map.positions.data() + c),
                                   3 * sizeof(float), 3 * sizeof(float) * map.width));
  }
  frame_buffer.insert("A", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(map.coverage.data()),
                                      sizeof(float), sizeof(float) * map.width));
  file.setFrameBuffer(frame_buffer);
  file.readPixels(window.min.y, window.max.y);
  return map;
}

struct PositionMapHeader {
  std::string model;
  int frame = -1;
  std::string pose_hash, space, units;  // pose_hash: 16 hex digits
};

// The attributes io::write_exr sets; an attribute the file lacks stays empty (frame -1).
inline PositionMapHeader read_position_map_header(const Imf::Header& header) {
  PositionMapHeader read;
  const auto text = [&](const char* name) {
    const auto* attribute = header.findTypedAttribute<Imf::StringAttribute>(name);
    return attribute ? attribute->value() : std::string();
  };
  if (const auto* frame = header.findTypedAttribute<Imf::IntAttribute>("frame"))
    read.frame = frame->value();
  read.model = text("model");
  read.pose_hash = text("poseHash");
  read.space = text("space");
  read.units = text("units");
  return read;
}

// A pose hash as the header writes it: 16 lowercase hex digits.
inline std::string pose_hash_text(std::uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace sweepd::io::test_support

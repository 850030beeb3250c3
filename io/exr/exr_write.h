// write_exr / encode_exr: a position map (gpu::PositionMapRenderer's output) as an OpenEXR
// image, to a file or to bytes in memory (what the server sends over the network).
//
// Input:  ExrLayers of width W × height H, row-major, row 0 written as the image's top row
//         (EXR's first scan line; with the position map's orientation that puts uv (0, 0) at
//         the top-left, like glTF textures):
//           positions  W·H·3 floats → channels P.X, P.Y, P.Z (required)
//           normals    W·H·3 floats → channels N.X, N.Y, N.Z (optional: empty span)
//           coverage   W·H   floats → channel  A            (optional: empty span)
//         ExrOptions: compression (ZIP by default; NONE, ZIPS, PIZ — all lossless for FLOAT),
//         zip_level (deflate's, 1-9, for ZIP and ZIPS; default 1: on the 72k mannequin's 1024²
//         maps zlib encodes in about 0.6× the time of its default 6 for 3 % more bytes —
//         float positions' low mantissa bits barely compress at any level; ZIP is deflated by
//         libdeflate, io/exr/exr_zip_encode.h, in 0.52–0.63× zlib level 1's time) and header
//         attributes: "model" (string), "frame" (int), "poseHash" (string, 16 hex
//         digits), "space" ("object" or "camera"), "units" (string, "metres").
// Output: a scan-line EXR, every channel FLOAT (32-bit) — the normals HALF with
//         ExrOptions::half_normals (each float rounded to the nearest half) — data window
//         (0,0)-(W-1,H-1); the FLOAT channels read back bit for bit.
// Throws std::invalid_argument when the layers do not fit W × H or an option is invalid, and
// std::runtime_error (naming the file and the reason) when the file cannot be written.
// Encoding uses OpenEXR's global thread pool: set_exr_threads(n) sizes it for the process.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace sweepd::io {

enum class ExrCompression { kNone, kZip, kZips, kPiz };

struct ExrLayers {
  int width = 0;
  int height = 0;
  std::span<const float> positions;
  std::span<const float> normals;
  std::span<const float> coverage;
};

struct ExrOptions {
  ExrCompression compression = ExrCompression::kZip;
  int zip_level = 1;
  bool half_normals = false;
  // ZIP compressed by OpenEXR's own writer (zlib, about 1.8× the time) instead of
  // io/exr/exr_zip_encode.h's libdeflate: the same format, for comparisons.
  bool openexr_zip = false;
  std::string model;
  int frame = 0;
  std::uint64_t pose_hash = 0;
  std::string space = "object";
  std::string units = "metres";
};

// Empty when layers and options are consistent; otherwise the reason, in words.
std::string validate_exr(const ExrLayers& layers, const ExrOptions& options);

void write_exr(const std::filesystem::path& file, const ExrLayers& layers,
               const ExrOptions& options = {});

// The same file's bytes, into a caller-owned vector (resized; its capacity is reused).
void encode_exr(const ExrLayers& layers, const ExrOptions& options,
                std::vector<std::uint8_t>& bytes);

// Threads OpenEXR uses to compress (process-wide; 0 = encode on the calling thread only).
void set_exr_threads(int threads);

}  // namespace sweepd::io

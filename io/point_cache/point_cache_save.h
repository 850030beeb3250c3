// PointCacheWriter: posed vertices written frame by frame as a point cache, the files Blender's
// Mesh Cache modifier, 3ds Max and Houdini play (laid out as Blender's reader,
// MOD_meshcache_pc2.c and MOD_meshcache_mdd.c, reads them):
//   PC2 (.pc2, little-endian)  "POINTCACHE2\0" (12 bytes), int32 version 1, int32 point count,
//                              float32 start frame (the clip frame of sample 0), float32
//                              sampling (frames per sample: 1), int32 sample count; then
//                              float32 x y z per point per sample
//   MDD (.mdd, big-endian)     int32 frame count, int32 point count, float32 time per frame
//                              (the clip's seconds of each frame); then float32 x y z per point
//                              per frame (no rest frame before them: Blender's reader takes the
//                              first block as frame 0)
// Axes (PointCacheAxes): kGltf (default) writes the model's own glTF axes, +Y up, metres, as
// sweepd poses them; kBlender writes Blender's +Z up: (x, y, z) -> (x, -z, y), the turn
// Blender's glTF importer gives a scene, so the cache plays on the imported mesh with the Mesh
// Cache modifier's default axes.
//
// Inputs: the file (FILE.pc2 or FILE.mdd: point_cache_format), a PointCacheLayout, then
// frame_count calls of write_frame with point_count positions each (in order), or write_frame_at
// with each frame's index (any order: a render farm's frames arrive as its servers finish them),
// then finish(). The joiner (io/point_cache/point_cache_join.h) gives a PointCacheHeader (and the axes its
// frames are in) instead and copies frames already in the file's axes and byte order with
// write_frame_bytes.
// Streams: the header goes first, then each frame as it comes (memory: one frame's bytes), into
// FILE.partial, at its own place in the file; finish() checks that every promised frame came and
// renames it to FILE, so a run cut short never leaves a cache whose header promises frames it
// lacks (the destructor removes an unfinished FILE.partial).
// Throws std::invalid_argument naming the file for a bad layout, a frame of the wrong size, a
// frame index outside the cache, a frame written twice or frames missing at finish();
// std::runtime_error naming the file and the system's reason when it cannot be written.
//
// point_cache_axes_names, kPointCacheAxesHelp: the --axes flag's names and help, one text for
// every program that writes caches (sweepctl pose, render_frames).
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <glm/vec3.hpp>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "io/point_cache/point_cache_header.h"

namespace sweepd::io {

enum class PointCacheAxes { kGltf, kBlender };

const std::map<std::string, PointCacheAxes>& point_cache_axes_names();
inline constexpr const char* kPointCacheAxesHelp =
    "a point cache's axes: gltf (default: the model's own, +Y up) or blender (+Z up: "
    "(x, y, z) -> (x, -z, y), as Blender's glTF importer turns the model)";

struct PointCacheLayout {
  PointCacheFormat format = PointCacheFormat::kPc2;
  PointCacheAxes axes = PointCacheAxes::kGltf;
  int point_count = 0;              // > 0
  int frame_count = 0;              // > 0
  int first_frame = 0;              // >= 0: PC2's start frame; MDD's first time's frame
  double frames_per_second = 30.0;  // > 0: MDD's times are (first_frame + i) / fps
};

class PointCacheWriter {
 public:
  PointCacheWriter(const std::filesystem::path& file, const PointCacheLayout& layout);
  PointCacheWriter(const std::filesystem::path& file, const PointCacheHeader& header,
                   PointCacheAxes axes);
  ~PointCacheWriter();
  PointCacheWriter(const PointCacheWriter&) = delete;
  PointCacheWriter& operator=(const PointCacheWriter&) = delete;

  void write_frame(std::span<const glm::vec3> positions);  // the next frame after the last
  void write_frame_at(int index, std::span<const glm::vec3> positions);
  void write_frame_bytes(int index, std::span<const std::uint8_t> bytes);
  void finish();

 private:
  void write_bytes(std::span<const std::uint8_t> bytes);
  void abandon();  // closes and removes FILE.partial; nothing once finished
  [[noreturn]] void fail_system(const char* step) const;

  std::filesystem::path file_, partial_;
  PointCacheHeader header_;
  PointCacheAxes axes_ = PointCacheAxes::kGltf;
  std::FILE* out_ = nullptr;
  int next_frame_ = 0;         // write_frame's index
  std::vector<bool> written_;  // per frame
  int frames_written_ = 0;
  std::vector<float> frame_floats_;  // one frame in the file's axes and byte order; reused
};

}  // namespace sweepd::io

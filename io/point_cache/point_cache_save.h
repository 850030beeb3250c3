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
// frame_count calls of write_frame with point_count positions each, then finish().
// Streams: the header goes first, then each frame as it comes (memory: one frame's bytes), into
// FILE.partial; finish() checks that every promised frame came and renames it to FILE, so a run
// cut short never leaves a cache whose header promises frames it lacks (the destructor removes
// an unfinished FILE.partial).
// Throws std::invalid_argument naming the file for a bad layout, a frame of the wrong size or a
// frame too many or too few; std::runtime_error naming the file and the system's reason when it
// cannot be written.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <glm/vec3.hpp>
#include <optional>
#include <span>
#include <vector>

namespace sweepd::io {

enum class PointCacheFormat { kPc2, kMdd };
enum class PointCacheAxes { kGltf, kBlender };

// The format a file's extension names (.pc2, .mdd, any case); nothing for any other.
std::optional<PointCacheFormat> point_cache_format(const std::filesystem::path& file);

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
  ~PointCacheWriter();
  PointCacheWriter(const PointCacheWriter&) = delete;
  PointCacheWriter& operator=(const PointCacheWriter&) = delete;

  void write_frame(std::span<const glm::vec3> positions);
  void finish();

 private:
  void write_bytes(std::span<const std::uint8_t> bytes);
  void abandon();  // closes and removes FILE.partial; nothing once finished
  [[noreturn]] void fail_system(const char* step) const;

  std::filesystem::path file_, partial_;
  PointCacheLayout layout_;
  std::FILE* out_ = nullptr;
  int frames_written_ = 0;
  std::vector<float> frame_floats_;  // one frame in the file's axes and byte order; reused
};

}  // namespace sweepd::io

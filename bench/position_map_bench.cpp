// Where one position-map frame's time goes on this node (issue 14 item 7): the 72k mannequin
// posed at a clip-like bend, deformed (with normals when the map has them), rasterised in UV
// space at 1024², gutter, read back, and encoded as EXR, each stage timed alone (the GL stages
// end with glFinish), then whole frames back to back the way the daemon's GPU worker makes
// them, in frames per second. Encoding is timed on the calling thread only and with OpenEXR's
// thread pool at the machine's core count; "Nh" is the normals as half floats. ZIP is at zlib
// level 1 (ExrOptions' default), and once at level 6, zlib's own default, for comparison.
//
//   position_map_bench [frames per row, default 12] [side, default 1024]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/gtc/quaternion.hpp>
#include <string>
#include <thread>
#include <vector>

#include "deform/binding/bind.h"
#include "deform/job/deform_job.h"
#include "deform/rig/rig_map.h"
#include "gpu/egl_context.h"
#include "gpu/position_map_renderer.h"
#include "io/exr_write.h"
#include "mannequin/mannequin.h"

namespace {

using namespace sweepd;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// Every joint bent a little, a different amount per frame, so no frame repeats.
deform::Pose pose_at(const deform::Model& model, int frame) {
  deform::Pose pose = deform::rest_pose(model.skeleton);
  for (std::size_t j = 1; j < pose.local_rotations.size(); ++j) {
    const float angle = 0.3f * std::sin(0.1f * static_cast<float>(frame + 3 * j));
    pose.local_rotations[j] =
        pose.local_rotations[j] * glm::angleAxis(angle, glm::normalize(glm::vec3(1, 0.5f, 0.25f)));
  }
  return pose;
}

struct Row {
  const char* name;
  bool normals;
  io::ExrCompression compression;
  int exr_threads;
  bool half_normals = false;
  int zip_level = io::ExrOptions{}.zip_level;
};

}  // namespace

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::max(3, std::atoi(argv[1])) : 12;
  const int side = argc > 2 ? std::atoi(argv[2]) : 1024;
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const deform::Model model = mannequin::make_mannequin({.target_vertices = 72000});
  const deform::BoundModel bound = deform::bind(model, deform::detect_rig_map(model.skeleton));
  const deform::ModelRuntime runtime(bound);
  deform::DeformContext context;
  gpu::Context gl;
  gpu::PositionMapRenderer renderer(gl);
  std::printf("%s, %zu vertices, %d x %d, %d frames per row, %d cores\n\n", gl.renderer().c_str(),
              model.vertex_count(), side, side, frames, cores);

  const std::size_t texels = static_cast<std::size_t>(side) * side;
  std::vector<glm::vec3> positions(model.vertex_count()), normals(model.vertex_count());
  std::vector<float> p(texels * 3), n(texels * 3), a(texels);
  std::vector<std::uint8_t> exr;

  std::printf(
      "| layers | EXR | threads | deform | upload | raster | gutter | readback | encode | "
      "sum ms | whole frame ms | frames/s |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& row : {Row{"P A", false, io::ExrCompression::kNone, 0},
                         Row{"P A", false, io::ExrCompression::kZip, 0},
                         Row{"P A", false, io::ExrCompression::kZip, cores},
                         Row{"P A", false, io::ExrCompression::kZip, cores, false, 6},
                         Row{"P N A", true, io::ExrCompression::kZip, cores},
                         Row{"P Nh A", true, io::ExrCompression::kZip, cores, true}}) {
    io::set_exr_threads(row.exr_threads);
    const std::span<float> n_out = row.normals ? std::span<float>(n) : std::span<float>();
    std::vector<double> deform_ms, encode_ms, whole_ms;
    std::vector<gpu::PositionMapTimings> stages;
    auto frame = [&](int f, gpu::PositionMapTimings* timings) {
      Clock::time_point start = Clock::now();
      deform::Pose pose = pose_at(model, f);
      deform::DeformJob job{runtime, pose};
      job.positions = positions;
      if (row.normals) job.normals = normals;
      job.run(context);
      if (timings) deform_ms.push_back(ms_since(start));
      renderer.render(
          {model.uvs, positions,
           row.normals ? std::span<const glm::vec3>(normals) : std::span<const glm::vec3>(),
           model.indices},
          {.width = side, .height = side, .gutter_pixels = 4, .view = std::nullopt}, {p, n_out, a},
          timings);
      start = Clock::now();
      io::ExrOptions options;
      options.compression = row.compression;
      options.half_normals = row.half_normals;
      options.zip_level = row.zip_level;
      io::encode_exr({side, side, p, n_out, a}, options, exr);
      if (timings) encode_ms.push_back(ms_since(start));
    };
    frame(0, nullptr);  // warm up: shaders, targets, pages
    for (int f = 1; f <= frames; ++f) {
      gpu::PositionMapTimings timings;
      frame(f, &timings);
      stages.push_back(timings);
    }
    for (int f = 1; f <= frames; ++f) {
      const Clock::time_point start = Clock::now();
      frame(frames + f, nullptr);
      whole_ms.push_back(ms_since(start));
    }
    auto stage = [&](double gpu::PositionMapTimings::*member) {
      std::vector<double> values;
      for (const gpu::PositionMapTimings& t : stages) values.push_back(t.*member);
      return median(values);
    };
    const double upload = stage(&gpu::PositionMapTimings::upload);
    const double raster = stage(&gpu::PositionMapTimings::raster);
    const double gutter = stage(&gpu::PositionMapTimings::gutter);
    const double readback = stage(&gpu::PositionMapTimings::readback);
    const double sum = median(deform_ms) + upload + raster + gutter + readback + median(encode_ms);
    const double whole = median(whole_ms);
    std::printf("| %s | %s | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.2f |\n",
                row.name,
                row.compression == io::ExrCompression::kNone ? "none"
                : row.zip_level == 1                         ? "ZIP"
                                                             : "ZIP level 6",
                row.exr_threads, median(deform_ms), upload, raster, gutter, readback,
                median(encode_ms), sum, whole, 1000.0 / whole);
  }
  std::printf("\nEXR bytes of the last frame: %zu\n", exr.size());
  return 0;
}

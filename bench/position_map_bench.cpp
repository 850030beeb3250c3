// Where one position-map frame's time goes on this node (issue 14 item 7): the 72k mannequin
// posed at a clip-like bend, deformed (with normals when the map has them), rasterised in UV
// space at 1024², gutter, read back, and encoded as EXR, each stage timed alone (the GL stages
// end with glFinish), then whole frames back to back the way the daemon's GPU worker makes
// them, in frames per second. Encoding is timed on the calling thread only and with OpenEXR's
// thread pool at the machine's core count; "Nh" is the normals as half floats. ZIP is deflated
// by libdeflate at level 1 (io/exr/exr_zip_encode.h, ExrOptions' default), once at level 6, and
// once by OpenEXR's own writer with zlib at level 1 (ExrOptions::openexr_zip), as before.
// Last, the ZIP encode alone of one frame, libdeflate and OpenEXR's zlib interleaved frame by
// frame so that the machine's load falls on both alike: medians and their ratio.
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
#include "io/exr/exr_write.h"
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
  bool openexr_zip = false;
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
                         Row{"P A", false, io::ExrCompression::kZip, cores, false, 1, true},
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
      options.openexr_zip = row.openexr_zip;
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
                : row.openexr_zip                            ? "ZIP by OpenEXR (zlib)"
                : row.zip_level == 1                         ? "ZIP"
                                                             : "ZIP level 6",
                row.exr_threads, median(deform_ms), upload, raster, gutter, readback,
                median(encode_ms), sum, whole, 1000.0 / whole);
  }
  std::printf("\nEXR bytes of the last frame: %zu\n\n", exr.size());

  io::set_exr_threads(cores);
  std::vector<double> ours_ms, openexr_ms;
  std::size_t ours_bytes = 0, openexr_bytes = 0;
  for (int f = 0; f < 2 * frames; ++f) {
    for (const bool openexr : {false, true}) {
      io::ExrOptions options;
      options.openexr_zip = openexr;
      const Clock::time_point start = Clock::now();
      io::encode_exr({side, side, p, {}, a}, options, exr);
      (openexr ? openexr_ms : ours_ms).push_back(ms_since(start));
      (openexr ? openexr_bytes : ours_bytes) = exr.size();
    }
  }
  std::printf("| P A, ZIP level 1, %d threads, %d frames interleaved | encode ms | bytes |\n"
              "|---|---|---|\n| libdeflate | %.1f | %zu |\n| OpenEXR (zlib) | %.1f | %zu |\n"
              "| libdeflate ÷ OpenEXR | %.3f | %.3f |\n",
              cores, 2 * frames, median(ours_ms), ours_bytes, median(openexr_ms), openexr_bytes,
              median(ours_ms) / median(openexr_ms),
              static_cast<double>(ours_bytes) / static_cast<double>(openexr_bytes));
  double load = 0.0;
  if (std::FILE* loadavg = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(loadavg, "%lf", &load) == 1) std::printf("\nload average: %.2f\n", load);
    std::fclose(loadavg);
  }
  return 0;
}

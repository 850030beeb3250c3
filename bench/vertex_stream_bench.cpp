// vertex_stream_bench: PosedVertices' position formats (protocol/README.md, "Compact vertex
// streams") — float32, float16 and meshopt — in bytes per pose and encode / decode time per
// pose, as ratios against float32 measured in the same run (issue 18's target: meshopt ≥ 3×
// fewer bytes than float32 with error ≤ 0.1 mm).
//
//   vertex_stream_bench [--poses N]     (default 40)
//
// On the procedural mannequin at about 72k vertices and the shared 14.5k MakeHuman male (when
// ../shared/data has it): N sweep-deformed poses (every joint bent, a different phase per pose;
// the codec's cost depends on the mesh's vertex order and spacing, hardly on the pose), each
// built into a whole PosedVertices frame as the server builds it (protocol::PosedVerticesFrame;
// float32: a copy into the frame, which the server avoids by deforming in place; float16:
// protocol::encode_float16; meshopt: protocol::MeshoptEncoder, then the copy), and decoded as
// the C++ client does (protocol::copy_positions / copy_normals). Bytes are whole frames, length
// prefix included. Times are the fastest of 5 passes over the poses, one thread. Prints a
// Markdown table for docs/performance.md. Exit code 1 when a format's error is out of bounds.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench/bench_models.h"
#include "deform/binding/bind.h"
#include "deform/job/deform_job.h"
#include "deform/model/pose.h"
#include "deform/rig/rig_map.h"
#include "protocol/float16.h"
#include "protocol/messages.h"

namespace {

using namespace sweepd;
namespace pb = sweepd::protocol;
using Clock = std::chrono::steady_clock;

struct PosedFrame {
  std::vector<float> positions, normals;  // 3 per vertex
};

// `count` poses of `model`: every joint bent by up to 0.35 rad about its own axis, by phase.
std::vector<PosedFrame> posed_frames(const deform::Model& model, int count) {
  const deform::BoundModel bound = deform::bind(model, deform::detect_rig_map(model.skeleton));
  const deform::ModelRuntime runtime(bound);
  deform::DeformContext context;
  std::vector<PosedFrame> frames(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    deform::Pose pose = deform::rest_pose(model.skeleton);
    for (std::size_t j = 0; j < pose.local_rotations.size(); ++j) {
      const float f = static_cast<float>(j) + 0.1f * static_cast<float>(k);
      const glm::vec3 axis = glm::normalize(glm::vec3(std::sin(f), std::cos(2.0f * f), 0.5f));
      pose.local_rotations[j] = glm::angleAxis(0.35f * std::sin(f + 1.0f), axis);
    }
    PosedFrame& frame = frames[static_cast<std::size_t>(k)];
    frame.positions.resize(3 * model.vertex_count());
    frame.normals.resize(3 * model.vertex_count());
    deform::DeformJob job{runtime, pose, deform::DeformMethod::kSweep, {}};
    job.positions = {reinterpret_cast<glm::vec3*>(frame.positions.data()), model.vertex_count()};
    job.normals = {reinterpret_cast<glm::vec3*>(frame.normals.data()), model.vertex_count()};
    job.run(context);  // throws on a problem (none: the poses are unit quaternions)
  }
  return frames;
}

struct Measured {
  double frame_bytes = 0.0;  // mean per pose
  double encode_ms = 1e30;   // fastest pass, mean per pose
  double decode_ms = 1e30;
  float position_error = 0.0f;  // metres, largest over all poses
  float normal_error = 0.0f;
};

// One format over every pose, 5 passes.
Measured measure(const std::vector<PosedFrame>& frames, pb::PositionFormat format, bool normals) {
  flatbuffers::FlatBufferBuilder builder(1 << 20);
  pb::MeshoptEncoder meshopt;
  const std::size_t values = frames.front().positions.size();
  std::vector<float> decoded(values), decoded_normals(normals ? values : 0);
  Measured out;
  for (int pass = 0; pass < 5; ++pass) {
    double encode_s = 0.0, decode_s = 0.0, bytes = 0.0;
    for (const PosedFrame& frame : frames) {
      const std::span<const float> positions = frame.positions;
      const std::span<const float> frame_normals =
          normals ? std::span<const float>(frame.normals) : std::span<const float>();
      const Clock::time_point start = Clock::now();
      pb::PosedVerticesHeader header{.vertex_count = static_cast<std::uint32_t>(values / 3),
                                     .format = format,
                                     .normals = normals};
      if (format == pb::PositionFormat::Meshopt) {
        header.grid = meshopt.encode(positions, frame_normals);
        header.meshopt_positions_bytes = meshopt.positions().size();
        header.meshopt_normals_bytes = meshopt.normals().size();
      }
      const pb::PosedVerticesFrame built(builder, header);
      if (format == pb::PositionFormat::Float32) {
        std::ranges::copy(positions, built.positions_f32().begin());
        std::ranges::copy(frame_normals, built.normals_f32().begin());
      } else if (format == pb::PositionFormat::Float16) {
        pb::encode_float16(positions, built.positions_f16());
        if (normals) pb::encode_float16(frame_normals, built.normals_f16());
      } else {
        std::ranges::copy(meshopt.positions(), built.positions_meshopt().begin());
        std::ranges::copy(meshopt.normals(), built.normals_meshopt().begin());
      }
      const Clock::time_point encoded = Clock::now();
      const auto* reply = pb::GetSizePrefixedMessage(built.bytes().data())->body_as_PosedVertices();
      const bool ok = pb::copy_positions(*reply, decoded) &&
                      (!normals || pb::copy_normals(*reply, decoded_normals));
      const Clock::time_point done = Clock::now();
      if (!ok) {
        std::fprintf(stderr, "vertex_stream_bench: a frame did not decode\n");
        std::exit(1);
      }
      encode_s += std::chrono::duration<double>(encoded - start).count();
      decode_s += std::chrono::duration<double>(done - encoded).count();
      bytes += static_cast<double>(built.bytes().size());
      for (std::size_t i = 0; i < values; ++i)
        out.position_error = std::max(out.position_error, std::abs(decoded[i] - positions[i]));
      for (std::size_t i = 0; i < decoded_normals.size(); ++i)
        out.normal_error =
            std::max(out.normal_error, std::abs(decoded_normals[i] - frame_normals[i]));
    }
    const double poses = static_cast<double>(frames.size());
    out.frame_bytes = bytes / poses;
    out.encode_ms = std::min(out.encode_ms, 1e3 * encode_s / poses);
    out.decode_ms = std::min(out.decode_ms, 1e3 * decode_s / poses);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  int poses = 40;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--poses") == 0 && i + 1 < argc && std::atoi(argv[i + 1]) > 0) {
      poses = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: vertex_stream_bench [--poses N]\n");
      return 2;
    }
  }
  std::vector<std::pair<std::string, const deform::Model*>> models = {
      {"mannequin", &bench::mannequin_72k()}};
  if (const deform::Model* male = bench::shared_male()) models.emplace_back("MakeHuman male", male);

  struct Format {
    const char* name;
    pb::PositionFormat format;
    float bound;  // the largest position error the format promises, metres
  };
  const Format formats[] = {
      {"float32", pb::PositionFormat::Float32, 0.0f},
      {"float16", pb::PositionFormat::Float16, 1e-3f},
      {"meshopt", pb::PositionFormat::Meshopt, 0.5f * pb::kMeshoptPositionStep + 1e-6f}};
  bool within_bounds = true;
  std::printf(
      "| mesh | vertices | format | bytes/pose | float32 / format | + normals bytes/pose | "
      "float32 / format | encode ms/pose | decode ms/pose | max error mm | encode / float32 | "
      "decode / float32 |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& [name, model] : models) {
    const std::vector<PosedFrame> frames = posed_frames(*model, poses);
    Measured reference, reference_normals;
    for (const Format& format : formats) {
      const Measured positions = measure(frames, format.format, false);
      const Measured with_normals = measure(frames, format.format, true);
      if (format.format == pb::PositionFormat::Float32) {
        reference = positions;
        reference_normals = with_normals;
      }
      within_bounds = within_bounds && positions.position_error <= format.bound;
      std::printf(
          "| %s | %zu | %s | %.0f | %.2f | %.0f | %.2f | %.3f | %.3f | %.4f | %.2f | %.2f |\n",
          name.c_str(), model->vertex_count(), format.name, positions.frame_bytes,
          reference.frame_bytes / positions.frame_bytes, with_normals.frame_bytes,
          reference_normals.frame_bytes / with_normals.frame_bytes, positions.encode_ms,
          positions.decode_ms, 1e3 * positions.position_error,
          positions.encode_ms / reference.encode_ms, positions.decode_ms / reference.decode_ms);
    }
  }
  if (!within_bounds) std::fprintf(stderr, "vertex_stream_bench: an error is out of bounds\n");
  return within_bounds ? 0 : 1;
}

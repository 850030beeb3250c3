#include "bench/bench_poses.h"

#include <algorithm>
#include <filesystem>
#include <limits>

#include "cli/served_rest_skeleton.h"
#include "io/bvh/bvh_load.h"
#include "motion/retarget.h"
#include "tests/test_paths.h"

namespace sweepd::bench {

namespace pb = sweepd::protocol;

std::vector<BenchPose> clip_poses(const pb::ModelInfo& info, int count) {
  const std::filesystem::path clip =
      std::filesystem::path(SWEEPD_SHARED_DATA) / "motion" / "cmu_01_01.bvh";
  // Retargeted here with the library (the benchmarks time the server's Pose path, so they send
  // rotations), onto the skeleton and floor that ModelInfo carries.
  const motion::Retargeter retargeter(io::load_bvh(clip, {.length_scale = 0.056444f}),
                                      cli::rest_skeleton(info), {}, info.floor_height());
  std::vector<BenchPose> poses;
  for (int i = 0; i < count; ++i) {
    BenchPose p;
    p.pose = retargeter.pose_at_frame(i * (retargeter.frame_count() - 1) / std::max(1, count - 1));
    for (const glm::quat& q : p.pose.local_rotations) p.rotations.emplace_back(q.x, q.y, q.z, q.w);
    const glm::vec3& t = p.pose.root_translation;
    p.root = pb::Vec3(t.x, t.y, t.z);
    poses.push_back(std::move(p));
  }
  return poses;
}

void send_pose(client::Connection& connection, std::uint32_t model_id, std::uint64_t sequence,
               const BenchPose& pose, std::optional<std::uint64_t> shared_offset,
               pb::PositionFormat format) {
  pb::PoseFields fields;
  fields.model_id = model_id;
  fields.sequence = sequence;
  fields.rotations = pose.rotations;
  fields.root_translation = pose.root;
  fields.shared_offset = shared_offset;
  fields.positions = format;
  flatbuffers::FlatBufferBuilder& builder = connection.builder();
  builder.Clear();
  connection.send(pb::finish_message(builder, pb::add_pose(builder, fields)));
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1))];
}

double milliseconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace sweepd::bench

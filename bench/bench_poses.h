// What the network benchmarks (server_bench, fleet_bench) send and how they summarise times.
//
// clip_poses(info, count): `count` frames spread over CMU clip 01_01, retargeted client-side
//   onto the served model (motion::Retargeter on its ModelInfo's skeleton), each as the wire's
//   rotations and root translation and as the library's Pose.
// send_pose(connection, model_id, sequence, pose): one Pose frame, float32 positions asked
//   (or the format given).
// percentile(values, q): the q-quantile (0..1) by rank, NaN for none.
// milliseconds_since(start): steady-clock milliseconds since `start`.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include "client/connection.h"
#include "deform/model/pose.h"
#include "protocol/messages.h"

namespace sweepd::bench {

struct BenchPose {
  std::vector<protocol::Quat> rotations;
  protocol::Vec3 root;
  deform::Pose pose;
};

std::vector<BenchPose> clip_poses(const protocol::ModelInfo& info, int count);
// `shared_offset`: the reply's vertices go into the connection's shared region there (1.10).
void send_pose(client::Connection& connection, std::uint32_t model_id, std::uint64_t sequence,
               const BenchPose& pose, std::optional<std::uint64_t> shared_offset = std::nullopt,
               protocol::PositionFormat format = protocol::PositionFormat::Float32);
double percentile(std::vector<double> values, double q);
double milliseconds_since(std::chrono::steady_clock::time_point start);

}  // namespace sweepd::bench

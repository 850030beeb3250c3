#include "server/handlers/pose_request.h"

#include <algorithm>

#include "deform/model/pose_hash.h"
#include "protocol/float16.h"

namespace sweepd::server {
namespace {

using Clock = std::chrono::steady_clock;

std::uint64_t nanoseconds_between(Clock::time_point from, Clock::time_point to) {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(to - from).count());
}

std::span<glm::vec3> as_vectors(std::span<float> values) {
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
  return {reinterpret_cast<glm::vec3*>(values.data()), values.size() / 3};
}

std::span<const float> as_floats(std::span<const glm::vec3> vectors) {
  return {reinterpret_cast<const float*>(vectors.data()), vectors.size() * 3};
}

// The reply's timings: queued before work started, deforming (volume and bulge included: the
// sweep poser applies them), folding and protrusion, and everything else (encoding).
void fill_timings(protocol::ServerTimings& timings, const PoseRequest& request,
                  Clock::time_point started, std::pair<std::uint64_t, std::uint64_t> work_ns) {
  const auto [deform_ns, features_ns] = work_ns;
  timings.mutate_queued_ns(nanoseconds_between(request.received, started));
  timings.mutate_deform_ns(deform_ns);
  timings.mutate_features_ns(features_ns);
  timings.mutate_encode_ns(nanoseconds_between(started, Clock::now()) - deform_ns - features_ns);
}

deform::AnatomicalFeatures features_of(protocol::Features bits) {
  auto has = [&](protocol::Features bit) {
    return (static_cast<unsigned>(bits) & static_cast<unsigned>(bit)) != 0;
  };
  return {.folding = has(protocol::Features::Folding),
          .protrusion = has(protocol::Features::Protrusion),
          .volume = has(protocol::Features::Volume),
          .bulge = has(protocol::Features::Bulge),
          .contact = has(protocol::Features::Contact)};
}

}  // namespace

glm::vec3 root_translation_of(const protocol::Pose& pose, const deform::Skeleton& skeleton) {
  const protocol::Vec3* root = pose.root_translation();
  return root != nullptr           ? glm::vec3(root->x(), root->y(), root->z())
         : skeleton.joints.empty() ? glm::vec3(0.0f)
                                   : skeleton.joints[0].rest_translation;
}

std::optional<protocol::PoseProblem> read_pose_request(const protocol::Pose& pose,
                                                       const ModelHandle& model,
                                                       std::uint64_t request_id, PoseRequest& out) {
  // As many rotations as the wire holds (the frame limit bounds them); the job names a count
  // other than the skeleton's.
  deform::Pose posed;
  if (const auto* rotations = pose.rotations()) {
    posed.local_rotations.reserve(rotations->size());
    for (const protocol::Quat* q : *rotations)
      posed.local_rotations.emplace_back(q->w(), q->x(), q->y(), q->z());
  }
  posed.root_translation = root_translation_of(pose, model->bound.model.skeleton);
  return read_posed_request(pose, std::move(posed), model, request_id, out);
}

std::optional<protocol::PoseProblem> read_posed_request(const protocol::Pose& pose,
                                                        deform::Pose posed,
                                                        const ModelHandle& model,
                                                        std::uint64_t request_id,
                                                        PoseRequest& out) {
  if (auto problem = protocol::check_pose_enums(pose)) return problem;
  out.request_id = request_id;
  out.model = model;
  out.sequence = pose.sequence();
  out.client_time_ns = pose.client_time_ns();
  out.format = pose.positions();
  out.normals = pose.normals();
  if (pose.into_shared_memory()) out.shared_offset = pose.shared_offset();
  out.features = features_of(pose.features());
  switch (pose.method()) {
    case protocol::DeformMethod::Lbs:
      out.method = deform::DeformMethod::kLbs;
      break;
    case protocol::DeformMethod::Dqs:
      out.method = deform::DeformMethod::kDqs;
      break;
    default:
      out.method = deform::DeformMethod::kSweep;
  }
  out.pose = std::move(posed);
  deform::DeformJob job = out.job(0, {}, {});
  const deform::JobProblem problem = job.validate();
  if (!problem) return std::nullopt;
  const protocol::ErrorCode code =
      problem.input == deform::JobProblem::Input::kJointCount ? protocol::ErrorCode::WrongJointCount
      : problem.input == deform::JobProblem::Input::kPose     ? protocol::ErrorCode::InvalidPose
                                                          : protocol::ErrorCode::InvalidArgument;
  return protocol::PoseProblem{code, "pose " + std::to_string(pose.sequence()) + " for model " +
                                         std::to_string(model->id) + ": " + problem.message};
}

std::optional<RequestError> place_in_shared_region(PoseRequest& request,
                                                   std::shared_ptr<const SharedRegion> region) {
  if (!request.shared_offset) return std::nullopt;
  const std::string pose = "pose " + std::to_string(request.sequence);
  auto refuse = [&](const std::string& why) {
    return RequestError{protocol::ErrorCode::InvalidArgument, pose + ": " + why, request.sequence,
                        request.model->id};
  };
  if (region == nullptr) {
    return refuse(
        "asks for its reply in shared memory, but this connection has mapped none "
        "(MapSharedMemory, on a Unix socket)");
  }
  if (request.position_map) return refuse("a position map is not written into shared memory");
  if (request.format != protocol::PositionFormat::Float32) {
    return refuse("replies in shared memory are Float32 only");
  }
  const std::size_t values = 3 * request.model->bound.model.vertex_count();
  const std::size_t floats = request.normals ? 2 * values : values;
  if (!region->floats(*request.shared_offset, floats)) {
    return refuse(std::to_string(floats * sizeof(float)) + " bytes at offset " +
                  std::to_string(*request.shared_offset) + " do not fit the shared region of " +
                  std::to_string(region->size()) + " bytes, or the offset is not a multiple of 4");
  }
  request.shared_region = std::move(region);
  return std::nullopt;
}

deform::DeformJob PoseRequest::job(int threads, std::span<glm::vec3> positions,
                                   std::span<glm::vec3> normals) {
  return {.runtime = *model->runtime,
          .pose = pose,
          .method = method,
          .features = features,
          .options = {.rotation_length_tolerance = protocol::kRotationNormTolerance,
                      .threads = threads},
          .positions = positions,
          .normals = normals};
}

std::pair<std::uint64_t, std::uint64_t> PosedVerticesWriter::deform(PoseRequest& request,
                                                                    std::span<glm::vec3> positions,
                                                                    std::span<glm::vec3> normals) {
  // One context per worker thread, whichever connection's request it runs: a connection holds
  // no deformation state.
  thread_local deform::DeformContext context;
  const Clock::time_point start = Clock::now();
  // Split over the cores no other job holds, when there are any and the pose is large.
  const SpareCores::Loan extra =
      deform_threads_ == 0
          ? spare_cores_.borrow(static_cast<int>(positions.size() / kVerticesPerSplit) - 1)
          : SpareCores::Loan{};
  // Validated once, when the pose arrived (read_pose_request).
  deform::DeformJob job =
      request.job(deform_threads_ == 0 ? 1 + extra.count() : deform_threads_, positions, normals);
  const bool collide =
      request.method == deform::DeformMethod::kSweep && request.features.collision();
  if (collide) job.options.detect = pair_finder_.begin();
  const deform::DeformReport report = job.run_validated(context);
  if (collide) pair_finder_.finish(report.features);
  const auto total = static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - start).count());
  const auto features = static_cast<std::uint64_t>(report.features_time.count());
  return {total - std::min(total, features), features};
}

std::uint64_t PosedVerticesWriter::write(PoseRequest& request, std::uint32_t dropped_before,
                                         flatbuffers::FlatBufferBuilder& builder) {
  const Clock::time_point started = Clock::now();
  const deform::BoundModel& bound = request.model->bound;
  const std::size_t vertex_count = bound.model.vertex_count();
  protocol::PosedVerticesHeader header;
  header.request_id = request.request_id;
  header.model_id = request.model->id;
  header.sequence = request.sequence;
  header.client_time_ns = request.client_time_ns;
  header.vertex_count = static_cast<std::uint32_t>(vertex_count);
  header.format = request.format;
  header.normals = request.normals;
  header.dropped_before = dropped_before;
  std::pair<std::uint64_t, std::uint64_t> work_ns;
  if (request.format == protocol::PositionFormat::Float32) {
    // Deformed in place: into the frame, or (placed and checked when queued,
    // place_in_shared_region) into the shared region, the frame then carrying only the offset.
    header.shared_offset = request.shared_offset;
    protocol::PosedVerticesFrame frame(builder, header);
    std::span<float> positions = frame.positions_f32(), normals = frame.normals_f32();
    if (request.shared_region) {
      const std::size_t values = 3 * vertex_count;
      const std::uint64_t offset = *request.shared_offset;
      positions = *request.shared_region->floats(offset, values);
      if (request.normals)
        normals = *request.shared_region->floats(offset + values * sizeof(float), values);
    }
    work_ns = deform(request, as_vectors(positions), as_vectors(normals));
    fill_timings(frame.timings(), request, started, work_ns);
    return work_ns.first + work_ns.second;
  }
  positions_scratch_.resize(vertex_count);
  normals_scratch_.resize(request.normals ? vertex_count : 0);
  work_ns = deform(request, positions_scratch_, normals_scratch_);
  if (request.format == protocol::PositionFormat::Meshopt) {
    header.grid = meshopt_.encode(as_floats(positions_scratch_), as_floats(normals_scratch_));
    header.meshopt_positions_bytes = meshopt_.positions().size();
    header.meshopt_normals_bytes = meshopt_.normals().size();
  }
  protocol::PosedVerticesFrame frame(builder, header);
  if (request.format == protocol::PositionFormat::Meshopt) {
    std::ranges::copy(meshopt_.positions(), frame.positions_meshopt().begin());
    std::ranges::copy(meshopt_.normals(), frame.normals_meshopt().begin());
  } else {
    protocol::encode_float16(as_floats(positions_scratch_), frame.positions_f16());
    if (request.normals) protocol::encode_float16(as_floats(normals_scratch_), frame.normals_f16());
  }
  fill_timings(frame.timings(), request, started, work_ns);
  return work_ns.first + work_ns.second;
}

std::uint64_t PosedVerticesWriter::write_position_map(PoseRequest& request,
                                                      PositionMapService& service,
                                                      flatbuffers::FlatBufferBuilder& builder) {
  const Clock::time_point started = Clock::now();
  const PositionMapParams& params = *request.position_map;
  std::vector<std::uint8_t> exr;
  const std::size_t vertex_count = request.model->bound.model.vertex_count();
  positions_scratch_.resize(vertex_count);
  normals_scratch_.resize(vertex_count);
  const std::pair<std::uint64_t, std::uint64_t> work_ns =
      deform(request, positions_scratch_, normals_scratch_);
  service.render({.model = &request.model->bound.model,
                  .positions = positions_scratch_,
                  .normals = normals_scratch_,
                  .width = params.width,
                  .height = params.height,
                  .layers = params.layers,
                  .compression = params.compression,
                  .half_normals = params.half_normals,
                  .frame = params.frame,
                  .pose_hash = deform::pose_hash(request.pose)},
                 exr);
  protocol::PositionMapFrame frame(builder, {.request_id = request.request_id,
                                             .model_id = request.model->id,
                                             .sequence = request.sequence,
                                             .width = params.width,
                                             .height = params.height,
                                             .exr_bytes = exr.size()});
  // encode_exr writes a growing vector, so the file is copied once into the frame.
  // The file is not kept between maps: a connection would hold its largest map's bytes, outside
  // the work budget, for as long as it stays open.
  std::copy(exr.begin(), exr.end(), frame.exr().begin());
  fill_timings(frame.timings(), request, started, work_ns);
  return work_ns.first + work_ns.second;
}

}  // namespace sweepd::server

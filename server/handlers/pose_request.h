// PoseRequest: a client's Pose message checked once against its model and turned into what
// the deformer takes; PosedVerticesWriter: the answer to it, deformed straight into the
// outgoing PosedVertices frame.
//
// read_pose_request(pose, model, request_id, out): fills `out` (rotations converted from the
//   wire's x,y,z,w to glm's w,x,y,z; an absent root translation becomes the model's rest root
//   position) and validates it once, as the deformation job it will be
//   (deform::DeformJob::validate, which normalises the rotations). Returns the problem (code +
//   message naming the pose's sequence) instead when the pose cannot be posed: a method,
//   feature or format this server does not know (NotAvailable), a wrong joint count
//   (WrongJointCount), NaN/inf or rotations further than protocol::kRotationNormTolerance
//   from unit length (InvalidPose), features on a method other than sweep (InvalidArgument).
// root_translation_of(pose, skeleton): the pose's root translation, or the skeleton's rest one
//   when the pose has none.
// read_posed_request(pose, posed, model, request_id, out): the same with the joint rotations
//   and root translation given (`posed`: a clip frame, named rotations) instead of the wire's;
//   the rest of `pose` (method, features, output, sequence) is read as above.
// PoseRequest::job(threads, positions, normals): the request as a deform::DeformJob, writing
//   into the given buffers; the worker runs it with run_validated.
// PosedVerticesWriter::write(request, dropped_before, builder): builds the complete reply
//   frame in `builder` (protocol::PosedVerticesFrame) — float32 positions/normals are
//   written by the deformer in place (in the frame, or in the shared region); float16 and meshopt
//   (protocol::MeshoptEncoder) go through scratch buffers kept between frames, meshopt's encoded
//   bytes copied into the frame once their size is known. write_position_map: the same pose
//   rendered to an EXR position map instead. The request runs as one deform::DeformJob on the
//   model's shared ModelRuntime (RegisteredModel::runtime) with the worker thread's own
//   DeformContext (one per thread, not per connection), each request standing alone
//   (VolumeChangeSource::kFixedPoint), so the vertices equal the library's bit for bit;
//   ServerTimings.features_ns times folding and protrusion (DeformReport::features_time). Folding's
//   pairs come from the server's collision backend (CollisionService: the CPU reference, or jobs on
//   the GPU thread), which counts the pose and its stage times. One writer per connection (its
//   encoding scratch and pair finder are not shared between threads).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "deform/job/anatomical_features.h"
#include "deform/job/deform_job.h"
#include "deform/job/deform_method.h"
#include "deform/model/pose.h"
#include "protocol/messages.h"
#include "server/handlers/request_error.h"
#include "server/models/model_registry.h"
#include "server/services/collision_service.h"
#include "server/services/position_map_service.h"
#include "server/services/spare_cores.h"
#include "server/services/work_budget.h"
#include "server/transport/shared_region.h"

namespace sweepd::server {

// What a PositionMapRequest asks for beyond its pose.
struct PositionMapParams {
  std::uint32_t width = 0, height = 0;
  protocol::MapLayers layers = protocol::MapLayers::Position;
  protocol::ExrCompression compression = protocol::ExrCompression::Zip;
  bool half_normals = false;
  // The EXR header's "frame": the clip frame asked for (PositionMapRequest.clip.frame), else the
  // pose's sequence, the client's frame number.
  std::uint64_t frame = 0;
};

struct PoseRequest {
  std::uint64_t request_id = 0;
  ModelHandle model;
  std::uint64_t sequence = 0;
  std::uint64_t client_time_ns = 0;
  deform::Pose pose;
  deform::DeformMethod method = deform::DeformMethod::kSweep;
  deform::AnatomicalFeatures features;  // sweep only
  protocol::PositionFormat format = protocol::PositionFormat::Float32;
  bool normals = false;
  std::optional<PositionMapParams> position_map;  // set: answer with a PositionMap
  std::chrono::steady_clock::time_point received;
  // Pose.into_shared_memory (1.10): where in the connection's region the reply's vertices go,
  // and the region (held by the request: the connection may close while it runs).
  std::optional<std::uint64_t> shared_offset = std::nullopt;
  std::shared_ptr<const SharedRegion> shared_region;
  // Its working memory, reserved from the server's work budget at intake (work_size.h) and
  // given back when the request, queued or running, is gone.
  std::shared_ptr<const WorkReservation> work;

  deform::DeformJob job(int threads, std::span<glm::vec3> positions, std::span<glm::vec3> normals);
};

std::optional<protocol::PoseProblem> read_pose_request(const protocol::Pose& pose,
                                                       const ModelHandle& model,
                                                       std::uint64_t request_id, PoseRequest& out);
glm::vec3 root_translation_of(const protocol::Pose& pose, const deform::Skeleton& skeleton);
std::optional<protocol::PoseProblem> read_posed_request(const protocol::Pose& pose,
                                                        deform::Pose posed,
                                                        const ModelHandle& model,
                                                        std::uint64_t request_id, PoseRequest& out);

// A request with shared_offset given the connection's region (null: none mapped), after
// checking that its vertices fit there: Float32 only, no position map, [offset, offset + the
// positions and normals' bytes) inside the region, offset a multiple of 4. The InvalidArgument
// that names what does not hold otherwise.
std::optional<RequestError> place_in_shared_region(PoseRequest& request,
                                                   std::shared_ptr<const SharedRegion> region);

class PosedVerticesWriter {
 public:
  // deform_threads: threads one pose is split over; 0: one, plus the cores no other job holds
  // (SpareCores) for a pose of kVerticesPerSplit vertices or more per thread.
  PosedVerticesWriter(int deform_threads, SpareCores& spare_cores, CollisionService& collision)
      : deform_threads_(deform_threads), spare_cores_(spare_cores), pair_finder_(collision) {}

  // Below this many vertices per thread, starting a thread costs more than it saves.
  static constexpr std::size_t kVerticesPerSplit = 20000;

  // Returns the time spent deforming (features included), in nanoseconds.
  std::uint64_t write(PoseRequest& request, std::uint32_t dropped_before,
                      flatbuffers::FlatBufferBuilder& builder);
  // The PositionMap reply for a request with position_map set (PositionMapService::render's
  // exceptions pass through). Returns the deformation time, in nanoseconds.
  std::uint64_t write_position_map(PoseRequest& request, PositionMapService& service,
                                   flatbuffers::FlatBufferBuilder& builder);

 private:
  // Deforms the request's pose with its method and features; returns (deform, features) ns.
  std::pair<std::uint64_t, std::uint64_t> deform(PoseRequest& request,
                                                 std::span<glm::vec3> positions,
                                                 std::span<glm::vec3> normals);

  int deform_threads_;
  SpareCores& spare_cores_;
  CollisionPairFinder pair_finder_;
  std::vector<glm::vec3> positions_scratch_, normals_scratch_;  // float16, meshopt, maps
  protocol::MeshoptEncoder meshopt_;
};

}  // namespace sweepd::server

// Messages: small typed helpers to build and check sweepd protocol messages (sweepd.fbs).
//
// The generated API (protocol/sweepd_generated.h: CreateHelloDirect, CreateModelInfoDirect,
// ...) builds any body; these helpers wrap a body in the Message envelope as one frame,
// build the hot-path messages, and check what a generic verifier cannot:
//
//   finish_message(builder, body, request_id)  any body → one frame (framing.h layout)
//   build_hello / build_error                  the session's first and most common replies
//   add_pose(builder, PoseFields)              a Pose table (in a Pose message or a request)
//   check_pose_enums(pose)                     method, features, format a newer client sent
//   PosedVerticesFrame, PositionMapFrame       replies with their arrays left for the caller
//                                              to write straight into the builder's buffer
//   copy_positions / copy_normals              a reply's arrays as float32, any format
//
// The wire format is little-endian; arrays are written and read in place, so this code
// builds only on little-endian hosts (a static_assert says so).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "protocol/framing.h"
#include "protocol/meshopt_vertices.h"
#include "protocol/sweepd_generated.h"

namespace sweepd::protocol {

// Hello.version_major must equal the server's; minor versions only add (README.md).
inline constexpr std::uint16_t kProtocolVersionMajor = 1;
inline constexpr std::uint16_t kProtocolVersionMinor = 16;

// Wraps `body` in a Message (with `request_id`) and finishes the builder as one frame.
template <typename BodyTable>
std::span<const std::uint8_t> finish_message(flatbuffers::FlatBufferBuilder& builder,
                                             flatbuffers::Offset<BodyTable> body,
                                             std::uint64_t request_id = 0) {
  static_assert(BodyTraits<BodyTable>::enum_value != Body::NONE, "not a Body member");
  return finish_frame(
      builder, CreateMessage(builder, request_id, BodyTraits<BodyTable>::enum_value, body.Union()));
}

std::span<const std::uint8_t> build_hello(flatbuffers::FlatBufferBuilder& builder,
                                          std::string_view auth_token, std::string_view client_name,
                                          PoseDelivery delivery = PoseDelivery::InOrder,
                                          std::uint64_t request_id = 0);

// `sequence`: the offending Pose's sequence, else 0. `fatal`: the sender closes afterwards.
std::span<const std::uint8_t> build_error(flatbuffers::FlatBufferBuilder& builder, ErrorCode code,
                                          std::string_view message, std::uint64_t sequence = 0,
                                          std::uint64_t request_id = 0, bool fatal = false);

struct PoseFields {
  std::uint32_t model_id = 0;
  std::uint64_t sequence = 0;
  std::uint64_t client_time_ns = 0;
  std::span<const Quat> rotations;       // one local rotation per joint, model order
  std::optional<Vec3> root_translation;  // nullopt: the rest-pose root position
  DeformMethod method = DeformMethod::Sweep;
  Features features = Features::NONE;
  PositionFormat positions = PositionFormat::Float32;
  bool normals = false;
  // Since 1.10: the reply's positions (and normals) written into the connection's shared
  // region (MapSharedMemory) at this byte offset; nullopt: in the reply.
  std::optional<std::uint64_t> shared_offset = std::nullopt;
};

flatbuffers::Offset<Pose> add_pose(flatbuffers::FlatBufferBuilder& builder,
                                   const PoseFields& fields);

// The wire's contract for rotations: they may be off unit length by kRotationNormTolerance
// (the server normalises them); more is an InvalidPose. The pose itself is checked against
// its model by deform::DeformJob::validate, with this tolerance.
inline constexpr float kRotationNormTolerance = 0.01f;

// What only the wire can get wrong in a pose: a method, feature flag or position format this
// build does not know (from a newer client): NotAvailable, in words that name the pose's
// sequence; nullopt otherwise.
struct PoseProblem {
  ErrorCode code = ErrorCode::NotAvailable;
  std::string message;
};
std::optional<PoseProblem> check_pose_enums(const Pose& pose);

struct PosedVerticesHeader {
  std::uint64_t request_id = 0;
  std::uint32_t model_id = 0;
  std::uint64_t sequence = 0;
  std::uint64_t client_time_ns = 0;
  std::uint32_t vertex_count = 0;
  PositionFormat format = PositionFormat::Float32;
  bool normals = false;
  std::uint32_t dropped_before = 0;
  // Meshopt only: the encoded streams' sizes (the caller encodes before building the frame)
  // and the grid the positions were quantised on.
  std::size_t meshopt_positions_bytes = 0;
  std::size_t meshopt_normals_bytes = 0;
  PositionGrid grid{};
  // Float32 into the shared region (1.10): the frame holds no arrays, only where they are.
  std::optional<std::uint64_t> shared_offset = std::nullopt;
};

// Builds a complete PosedVertices frame in `builder` (cleared first, its memory reused)
// with the arrays uninitialised, and hands out spans into the builder's own buffer: the
// server deforms (or encodes float16) straight into them — no copy. Every element of the
// spans for the chosen format must be written before bytes() is sent.
//   positions_f32 / normals_f32: 3 * vertex_count floats (empty unless format is Float32)
//   positions_f16 / normals_f16: 3 * vertex_count halves (empty unless format is Float16)
//   positions_meshopt / normals_meshopt: header.meshopt_positions_bytes /
//     meshopt_normals_bytes (empty unless format is Meshopt; the grid is written from the header)
//   normals_*: empty unless header.normals
//   all empty when header.shared_offset is set (the vertices are in the shared region)
// The spans and bytes() stay valid until the builder changes.
class PosedVerticesFrame {
 public:
  PosedVerticesFrame(flatbuffers::FlatBufferBuilder& builder, const PosedVerticesHeader& header);

  std::span<float> positions_f32() const { return positions_f32_; }
  std::span<std::uint16_t> positions_f16() const { return positions_f16_; }
  std::span<float> normals_f32() const { return normals_f32_; }
  std::span<std::uint16_t> normals_f16() const { return normals_f16_; }
  std::span<std::uint8_t> positions_meshopt() const { return positions_meshopt_; }
  std::span<std::uint8_t> normals_meshopt() const { return normals_meshopt_; }
  // Set the timings in place (e.g. encode_ns, known last) before sending.
  ServerTimings& timings() const { return *timings_; }
  // The whole frame, length prefix included.
  std::span<const std::uint8_t> bytes() const { return bytes_; }

 private:
  std::span<float> positions_f32_, normals_f32_;
  std::span<std::uint16_t> positions_f16_, normals_f16_;
  std::span<std::uint8_t> positions_meshopt_, normals_meshopt_;
  ServerTimings* timings_ = nullptr;
  std::span<const std::uint8_t> bytes_;
};

struct PositionMapHeader {
  std::uint64_t request_id = 0;
  std::uint32_t model_id = 0;
  std::uint64_t sequence = 0;  // the request's Pose.sequence
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::size_t exr_bytes = 0;  // size of the OpenEXR file the caller will write
};

// A complete PositionMap frame in `builder` (cleared first) whose `exr` array of
// header.exr_bytes is left for the caller to write the OpenEXR file straight into.
// Valid until the builder changes; every byte of exr() must be written before sending.
class PositionMapFrame {
 public:
  PositionMapFrame(flatbuffers::FlatBufferBuilder& builder, const PositionMapHeader& header);

  std::span<std::uint8_t> exr() const { return exr_; }
  ServerTimings& timings() const { return *timings_; }
  std::span<const std::uint8_t> bytes() const { return bytes_; }

 private:
  std::span<std::uint8_t> exr_;
  ServerTimings* timings_ = nullptr;
  std::span<const std::uint8_t> bytes_;
};

// A reply's positions (or normals) as 3 * vertex_count floats into `out`, decoding float16 or
// meshopt (meshopt_vertices.h). False when the reply lacks them, their length is not
// 3 * vertex_count (float formats), the meshopt bytes do not decode to vertex_count vertices,
// or `out` is not 3 * vertex_count floats; `out` is untouched then, except after meshopt bytes
// that fail to decode.
bool copy_positions(const PosedVertices& reply, std::span<float> out);
bool copy_normals(const PosedVertices& reply, std::span<float> out);

}  // namespace sweepd::protocol

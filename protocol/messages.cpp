#include "protocol/messages.h"

#include <cstring>
#include <initializer_list>

#include "protocol/float16.h"

namespace sweepd::protocol {
namespace {

static_assert(FLATBUFFERS_LITTLEENDIAN,
              "sweepd writes and reads protocol arrays in place: little-endian hosts only");

std::string pose_name(const Pose& pose) {
  return "pose " + std::to_string(pose.sequence()) + " for model " +
         std::to_string(pose.model_id());
}

// A span over a vector the builder has just finished, or empty when it is absent.
template <typename T>
std::span<T> writable(flatbuffers::Vector<T>* vector) {
  if (vector == nullptr) return {};
  return {vector->data(), vector->size()};
}

// 3 * vertex_count floats from whichever of the two arrays holds them.
bool copy_xyz(const flatbuffers::Vector<float>* f32, const flatbuffers::Vector<std::uint16_t>* f16,
              std::uint32_t vertex_count, std::span<float> out) {
  const std::size_t expected = 3 * static_cast<std::size_t>(vertex_count);
  if (out.size() != expected) return false;
  if (f32 != nullptr && f32->size() == expected) {
    if (expected > 0) std::memcpy(out.data(), f32->data(), expected * sizeof(float));
    return true;
  }
  if (f16 != nullptr && f16->size() == expected) {
    decode_float16({f16->data(), expected}, out);
    return true;
  }
  return false;
}

}  // namespace

std::span<const std::uint8_t> build_hello(flatbuffers::FlatBufferBuilder& builder,
                                          std::string_view auth_token, std::string_view client_name,
                                          PoseDelivery delivery, std::uint64_t request_id) {
  builder.Clear();
  const auto token = builder.CreateString(auth_token.data(), auth_token.size());
  const auto name = builder.CreateString(client_name.data(), client_name.size());
  const auto hello =
      CreateHello(builder, kProtocolVersionMajor, kProtocolVersionMinor, token, name, delivery);
  return finish_message(builder, hello, request_id);
}

std::span<const std::uint8_t> build_error(flatbuffers::FlatBufferBuilder& builder, ErrorCode code,
                                          std::string_view message, std::uint64_t sequence,
                                          std::uint64_t request_id, bool fatal) {
  builder.Clear();
  const auto text = builder.CreateString(message.data(), message.size());
  return finish_message(builder, CreateError(builder, code, text, sequence, fatal), request_id);
}

flatbuffers::Offset<Pose> add_pose(flatbuffers::FlatBufferBuilder& builder,
                                   const PoseFields& fields) {
  const auto rotations =
      builder.CreateVectorOfStructs(fields.rotations.data(), fields.rotations.size());
  const Vec3* root = fields.root_translation ? &*fields.root_translation : nullptr;
  return CreatePose(builder, fields.model_id, fields.sequence, fields.client_time_ns, rotations,
                    root, fields.method, fields.features, fields.positions, fields.normals,
                    fields.shared_offset.has_value(), fields.shared_offset.value_or(0));
}

std::optional<PoseProblem> check_pose_enums(const Pose& pose) {
  if (pose.method() > DeformMethod::MAX) {
    return PoseProblem{ErrorCode::NotAvailable,
                       pose_name(pose) + ": unknown deformation method " +
                           std::to_string(static_cast<int>(pose.method()))};
  }
  if ((static_cast<unsigned>(pose.features()) & ~static_cast<unsigned>(Features::ANY)) != 0) {
    return PoseProblem{ErrorCode::NotAvailable,
                       pose_name(pose) + ": unknown feature flags " +
                           std::to_string(static_cast<unsigned>(pose.features()))};
  }
  if (pose.positions() > PositionFormat::MAX) {
    return PoseProblem{ErrorCode::NotAvailable,
                       pose_name(pose) + ": unknown position format " +
                           std::to_string(static_cast<int>(pose.positions()))};
  }
  return std::nullopt;
}

PosedVerticesFrame::PosedVerticesFrame(flatbuffers::FlatBufferBuilder& builder,
                                       const PosedVerticesHeader& header) {
  builder.Clear();
  const std::size_t values = 3 * static_cast<std::size_t>(header.vertex_count);
  const bool half = header.format == PositionFormat::Float16;
  const bool meshopt = header.format == PositionFormat::Meshopt;
  const bool shared = header.shared_offset.has_value();
  // The pointers CreateUninitializedVector returns move when the builder grows; the spans
  // are taken from the finished buffer below instead.
  float* moving_f32 = nullptr;
  std::uint16_t* moving_f16 = nullptr;
  flatbuffers::Offset<flatbuffers::Vector<float>> positions_f32, normals_f32;
  flatbuffers::Offset<flatbuffers::Vector<std::uint16_t>> positions_f16, normals_f16;
  flatbuffers::Offset<flatbuffers::Vector<std::uint8_t>> positions_meshopt, normals_meshopt;
  if (shared) {
    // Nothing to carry: the vertices are in the shared region.
  } else if (meshopt) {
    std::uint8_t* moving_bytes = nullptr;
    positions_meshopt =
        builder.CreateUninitializedVector(header.meshopt_positions_bytes, &moving_bytes);
    if (header.normals)
      normals_meshopt =
          builder.CreateUninitializedVector(header.meshopt_normals_bytes, &moving_bytes);
  } else if (half) {
    positions_f16 = builder.CreateUninitializedVector(values, &moving_f16);
    if (header.normals) normals_f16 = builder.CreateUninitializedVector(values, &moving_f16);
  } else {
    positions_f32 = builder.CreateUninitializedVector(values, &moving_f32);
    if (header.normals) normals_f32 = builder.CreateUninitializedVector(values, &moving_f32);
  }
  const ServerTimings no_timings{};
  const auto reply = CreatePosedVertices(
      builder, header.model_id, header.sequence, header.client_time_ns, header.vertex_count,
      positions_f32, positions_f16, normals_f32, normals_f16, &no_timings, header.dropped_before,
      positions_meshopt, normals_meshopt, meshopt ? &header.grid.origin : nullptr,
      meshopt ? header.grid.step : 0.0f, shared, header.shared_offset.value_or(0));
  bytes_ = finish_message(builder, reply, header.request_id);

  auto* finished = static_cast<PosedVertices*>(
      GetMutableSizePrefixedMessage(builder.GetBufferPointer())->mutable_body());
  positions_f32_ = writable(finished->mutable_positions_f32());
  positions_f16_ = writable(finished->mutable_positions_f16());
  normals_f32_ = writable(finished->mutable_normals_f32());
  normals_f16_ = writable(finished->mutable_normals_f16());
  positions_meshopt_ = writable(finished->mutable_positions_meshopt());
  normals_meshopt_ = writable(finished->mutable_normals_meshopt());
  timings_ = finished->mutable_timings();
}

PositionMapFrame::PositionMapFrame(flatbuffers::FlatBufferBuilder& builder,
                                   const PositionMapHeader& header) {
  builder.Clear();
  std::uint8_t* moving = nullptr;  // moves as the builder grows: the span is taken below
  const auto exr = builder.CreateUninitializedVector(header.exr_bytes, &moving);
  const ServerTimings no_timings{};
  const auto map = CreatePositionMap(builder, header.model_id, header.sequence, header.width,
                                     header.height, exr, &no_timings);
  bytes_ = finish_message(builder, map, header.request_id);

  auto* finished = static_cast<PositionMap*>(
      GetMutableSizePrefixedMessage(builder.GetBufferPointer())->mutable_body());
  exr_ = writable(finished->mutable_exr());
  timings_ = finished->mutable_timings();
}

bool copy_positions(const PosedVertices& reply, std::span<float> out) {
  if (const auto* meshopt = reply.positions_meshopt()) {
    const Vec3* origin = reply.position_origin();
    return origin != nullptr && out.size() == 3 * std::size_t{reply.vertex_count()} &&
           decode_meshopt_positions({meshopt->data(), meshopt->size()},
                                    {*origin, reply.position_step()}, out);
  }
  return copy_xyz(reply.positions_f32(), reply.positions_f16(), reply.vertex_count(), out);
}

bool copy_normals(const PosedVertices& reply, std::span<float> out) {
  if (const auto* meshopt = reply.normals_meshopt()) {
    return out.size() == 3 * std::size_t{reply.vertex_count()} &&
           decode_meshopt_normals({meshopt->data(), meshopt->size()}, out);
  }
  return copy_xyz(reply.normals_f32(), reply.normals_f16(), reply.vertex_count(), out);
}

}  // namespace sweepd::protocol

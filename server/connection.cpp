#include "server/connection.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "deform/edits/rest_key_edit.h"
#include "protocol/messages.h"
#include "server/constant_time_equal.h"
#include "server/log_event.h"
#include "server/model_info.h"

namespace sweepd::server {
namespace {

namespace pb = sweepd::protocol;
constexpr std::size_t kReadChunkBytes = 64 * 1024;
constexpr std::size_t kSpareBuilders = 4;

std::uint64_t nanoseconds_since(std::chrono::steady_clock::time_point from) {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - from)
          .count());
}

std::vector<std::string> capabilities(bool position_maps) {
  std::vector<std::string> list = {"sweep",      "lbs",         "dqs",   "folding",
                                   "protrusion", "volume",      "bulge", "float16",
                                   "normals",    "latest_wins", "upload"};
  if (position_maps) list.push_back("position_map");
  return list;
}

// The answer to MeshRequest: the model's rest mesh in its vertex order (protocol 1.1).
void build_mesh(flatbuffers::FlatBufferBuilder& builder, const RegisteredModel& registered,
                std::uint64_t request_id) {
  const deform::Model& model = registered.bound.model;
  const std::size_t n = model.vertex_count();
  static_assert(sizeof(glm::vec2) == 2 * sizeof(float) && sizeof(glm::vec3) == 3 * sizeof(float));
  const auto indices = builder.CreateVector(model.indices);
  const auto uvs =
      builder.CreateVector(reinterpret_cast<const float*>(model.uvs.data()), 2 * model.uvs.size());
  const auto positions =
      builder.CreateVector(reinterpret_cast<const float*>(model.positions.data()), 3 * n);
  const auto joints = builder.CreateVector(
      reinterpret_cast<const std::uint16_t*>(model.skin_joints.data()), deform::kInfluences * n);
  const auto weights = builder.CreateVector(
      reinterpret_cast<const float*>(model.skin_weights.data()), deform::kInfluences * n);
  pb::finish_message(
      builder, pb::CreateMesh(builder, registered.id, indices, uvs, positions, joints, weights),
      request_id);
}

}  // namespace

Connection::Connection(Socket socket, std::uint64_t id, std::string peer,
                       ConnectionEnvironment& environment)
    : socket_(std::move(socket)),
      environment_(environment),
      hello_deadline_(socket_.get_executor()),
      reader_(environment.config.max_frame_bytes),
      read_buffer_(kReadChunkBytes),
      writer_(environment.config.deform_threads) {
  counters_.connection_id = id;
  counters_.peer = std::move(peer);
}

void Connection::start() {
  log_event("connection_open", {{"connection", id()}, {"peer", counters_.peer}});
  hello_deadline_.expires_after(std::chrono::milliseconds(environment_.config.hello_timeout_ms));
  hello_deadline_.async_wait([self = shared_from_this()](std::error_code error) {
    if (error || self->authenticated_ || self->draining_) return;
    self->send_error(
        pb::ErrorCode::NotAuthenticated,
        "no Hello within " + std::to_string(self->environment_.config.hello_timeout_ms) + " ms", 0,
        0, true);
  });
  read_more();
}

void Connection::refuse(pb::ErrorCode code, const std::string& message) {
  log_event("connection_refused",
            {{"connection", id()}, {"peer", counters_.peer}, {"reason", message}});
  send_error(code, message, 0, 0, true);
}

void Connection::shut_down() {
  shutting_down_ = true;
  drain();
}

// ---------------------------------------------------------------------------------------
// Reading.

void Connection::read_more() {
  if (reading_ || closed_ || (draining_ && !shutting_down_)) return;
  reading_ = true;
  socket_.async_read_some(asio::buffer(read_buffer_), [self = shared_from_this()](
                                                          std::error_code error, std::size_t n) {
    self->reading_ = false;
    if (self->closed_) return;
    if (error) {
      if (self->reader_.mid_frame()) {
        log_event("truncated_frame", {{"connection", self->id()}});
      }
      self->draining_ = true;
      self->close_if_done();
      return;
    }
    self->counters_.bytes_in += n;
    self->input_ = std::span<const std::uint8_t>(self->read_buffer_.data(), n);
    self->process_input();
  });
}

bool Connection::reading_paused() const {
  if (loads_running_ > 0) return true;  // keep replies in request order around a long load
  if (delivery_ == pb::PoseDelivery::LatestWins) {
    return outgoing_.size() >= environment_.config.max_poses_in_flight;
  }
  const std::size_t in_flight = waiting_poses_.size() + (pose_running_ ? 1 : 0);
  return std::max(in_flight, outgoing_.size()) >= environment_.config.max_poses_in_flight;
}

void Connection::process_input() {
  while (!input_.empty() && !closed_ && !reading_paused()) {
    if (draining_ && !shutting_down_) {
      input_ = {};  // after Bye or a fatal error nothing more is read
      break;
    }
    pb::FrameEvent event = reader_.read(input_);
    if (event.status == pb::FrameStatus::kPending) break;
    if (event.status == pb::FrameStatus::kError) {
      log_event("frame_error", {{"connection", id()},
                                {"error", pb::frame_error_name(event.error)},
                                {"reason", event.reason}});
      send_error(pb::error_code_for(event.error), event.reason, 0, 0);
      continue;
    }
    handle_frame(*event.message);
  }
  if (input_.empty()) read_more();
}

// ---------------------------------------------------------------------------------------
// Requests.

void Connection::handle_frame(const pb::Message& message) {
  const std::uint64_t request_id = message.request_id();
  if (!authenticated_) {
    if (const pb::Hello* hello = message.body_as_Hello()) {
      handle_hello(*hello, request_id);
    } else {
      send_error(pb::ErrorCode::NotAuthenticated, "the first message must be Hello", 0, request_id,
                 true);
    }
    return;
  }
  if (shutting_down_) {
    send_error(pb::ErrorCode::ShuttingDown, "the server is shutting down and takes no new work", 0,
               request_id);
    return;
  }
  switch (message.body_type()) {
    case pb::Body::Pose:
      handle_pose(*message.body_as_Pose(), request_id);
      break;
    case pb::Body::ListModels:
      handle_list_models(request_id);
      break;
    case pb::Body::LoadModel:
      handle_load_model(*message.body_as_LoadModel(), request_id);
      break;
    case pb::Body::StatsRequest:
      handle_stats(request_id);
      break;
    case pb::Body::Bye:
      log_event("bye_received", {{"connection", id()}});
      drain();
      break;
    case pb::Body::PositionMapRequest: {
      const pb::PositionMapRequest* map = message.body_as_PositionMapRequest();
      if (map->pose() == nullptr) {
        send_error(pb::ErrorCode::InvalidArgument, "a PositionMapRequest needs a pose", 0,
                   request_id);
      } else {
        handle_pose(*map->pose(), request_id, map);
      }
      break;
    }
    case pb::Body::MeshRequest: {
      const std::uint32_t model_id = message.body_as_MeshRequest()->model_id();
      if (const ModelHandle model = environment_.registry.find(model_id)) {
        flatbuffers::FlatBufferBuilder builder = take_builder();
        build_mesh(builder, *model, request_id);
        send(std::move(builder));
      } else {
        send_error(pb::ErrorCode::UnknownModel,
                   "mesh request: no model with id " + std::to_string(model_id), 0, request_id);
      }
      break;
    }
    case pb::Body::EditKeyEllipse:
      handle_edit_key_ellipse(*message.body_as_EditKeyEllipse(), request_id);
      break;
    case pb::Body::Hello:
      send_error(pb::ErrorCode::InvalidArgument, "Hello was already received on this connection", 0,
                 request_id);
      break;
    default:
      send_error(pb::ErrorCode::UnknownMessage,
                 "message type " + std::to_string(static_cast<int>(message.body_type())) +
                     " is not a request this server answers",
                 0, request_id);
  }
}

void Connection::handle_hello(const pb::Hello& hello, std::uint64_t request_id) {
  counters_.client_name = hello.client_name() ? hello.client_name()->str() : "";
  if (hello.version_major() != pb::kProtocolVersionMajor) {
    send_error(pb::ErrorCode::VersionMismatch,
               "client protocol " + std::to_string(hello.version_major()) + "." +
                   std::to_string(hello.version_minor()) + " is not compatible with server " +
                   std::to_string(pb::kProtocolVersionMajor) + "." +
                   std::to_string(pb::kProtocolVersionMinor),
               0, request_id, true);
    return;
  }
  const std::string_view token =
      hello.auth_token() ? hello.auth_token()->string_view() : std::string_view();
  const std::string& secret = environment_.config.token;
  if (!secret.empty() && !constant_time_equal(secret, token)) {
    log_event("auth_failed", {{"connection", id()}, {"peer", counters_.peer}});
    send_error(pb::ErrorCode::AuthFailed, "the auth token is wrong", 0, request_id, true);
    return;
  }
  authenticated_ = true;
  hello_deadline_.cancel();
  delivery_ = hello.delivery() == pb::PoseDelivery::LatestWins ? pb::PoseDelivery::LatestWins
                                                               : pb::PoseDelivery::InOrder;
  log_event("hello", {{"connection", id()},
                      {"client", counters_.client_name},
                      {"delivery", pb::EnumNamePoseDelivery(delivery_)}});
  flatbuffers::FlatBufferBuilder builder = take_builder();
  const auto welcome = pb::CreateWelcome(
      builder, pb::kProtocolVersionMajor, pb::kProtocolVersionMinor, builder.CreateString("sweepd"),
      builder.CreateVectorOfStrings(capabilities(environment_.position_maps.enabled())),
      environment_.config.max_frame_bytes, environment_.config.max_poses_in_flight, id());
  pb::finish_message(builder, welcome, request_id);
  send(std::move(builder));
}

void Connection::handle_pose(const pb::Pose& pose, std::uint64_t request_id,
                             const pb::PositionMapRequest* map) {
  ++counters_.poses_received;
  const ModelHandle model = environment_.registry.find(pose.model_id());
  if (!model) {
    send_error(pb::ErrorCode::UnknownModel,
               "pose " + std::to_string(pose.sequence()) + ": no model with id " +
                   std::to_string(pose.model_id()),
               pose.sequence(), request_id);
    return;
  }
  PoseRequest request;
  if (auto problem = read_pose_request(pose, model, request_id, request)) {
    ++environment_.model_counters[model->id].errors;
    send_error(problem->code, problem->message, pose.sequence(), request_id);
    return;
  }
  if (map != nullptr) {
    if (const std::string problem = check_position_map_request(*map, model->bound.model);
        !problem.empty()) {
      send_error(pb::ErrorCode::InvalidArgument, problem, pose.sequence(), request_id);
      return;
    }
    request.position_map =
        PositionMapParams{map->width(), map->height(), map->layers(), map->compression()};
  }
  request.received = Clock::now();
  if (delivery_ == pb::PoseDelivery::LatestWins) {
    // Only plain poses go stale; a requested position map is always rendered.
    const std::size_t dropped = std::erase_if(
        waiting_poses_, [](const PoseRequest& waiting) { return !waiting.position_map; });
    dropped_since_reply_ += static_cast<std::uint32_t>(dropped);
    counters_.poses_dropped += dropped;
  }
  waiting_poses_.push_back(std::move(request));
  start_next_pose();
}

void Connection::handle_list_models(std::uint64_t request_id) {
  flatbuffers::FlatBufferBuilder builder = take_builder();
  std::vector<flatbuffers::Offset<pb::ModelSummary>> summaries;
  for (const ModelHandle& model : environment_.registry.models()) {
    summaries.push_back(pb::CreateModelSummaryDirect(
        builder, model->id, model->name.c_str(),
        static_cast<std::uint32_t>(model->bound.model.vertex_count()),
        static_cast<std::uint32_t>(model->bound.model.skeleton.joints.size())));
  }
  for (const std::string& name : environment_.registry.directory_entries()) {
    summaries.push_back(pb::CreateModelSummaryDirect(builder, 0, name.c_str(), 0, 0));
  }
  pb::finish_message(builder, pb::CreateModelListDirect(builder, &summaries), request_id);
  send(std::move(builder));
}

void Connection::handle_edit_key_ellipse(const pb::EditKeyEllipse& request,
                                         std::uint64_t request_id) {
  deform::RestKeyEdit edit;
  edit.sweep = request.sweep() ? request.sweep()->str() : "";
  edit.key = static_cast<int>(std::min<std::uint32_t>(request.key_index(), 1u << 30));
  if (const pb::Vec3* offset = request.centre_offset())
    edit.centre_offset = {offset->x(), offset->y(), offset->z()};
  edit.a = request.half_axis_a();
  edit.b = request.half_axis_b();
  edit.twist_radians = request.twist_radians();
  const std::uint32_t model_id = request.model_id();
  // Storing the edited model durably (fsync) takes milliseconds: on a worker, replies kept in
  // request order.
  ++loads_running_;
  asio::post(environment_.workers, [self = shared_from_this(), edit, model_id, request_id]() {
    ModelHandle model = self->environment_.registry.find(model_id);
    pb::ErrorCode code = pb::ErrorCode::UnknownModel;
    std::string problem = "no model with id " + std::to_string(model_id);
    if (model) {
      deform::BoundModel bound = model->bound;
      problem = deform::apply_rest_key_edit(bound, edit);
      code = pb::ErrorCode::InvalidArgument;
      try {
        if (problem.empty())
          model = self->environment_.registry.replace(model_id, std::move(bound));
      } catch (const ModelError& error) {
        code = error.code();
        problem = error.what();
      }
    }
    asio::post(self->socket_.get_executor(), [self, model, code, problem, request_id]() {
      --self->loads_running_;
      if (problem.empty()) {
        log_event("key_ellipse_edited", {{"connection", self->id()}, {"model", model->id}});
        flatbuffers::FlatBufferBuilder builder = self->take_builder();
        build_model_info(builder, *model, request_id);
        self->send(std::move(builder));
      } else {
        self->send_error(code, "edit key ellipse: " + problem, 0, request_id);
      }
      self->process_input();
    });
  });
}

void Connection::handle_load_model(const pb::LoadModel& load, std::uint64_t request_id) {
  // The request's bytes live in the reader's storage: copy them for the worker.
  auto request = std::make_shared<ModelLoadRequest>();
  auto gltf = std::make_shared<std::vector<std::uint8_t>>();
  request->name = load.name() ? load.name()->str() : "";
  if (load.gltf()) gltf->assign(load.gltf()->begin(), load.gltf()->end());
  request->gltf = *gltf;
  if (load.options() && load.options()->rig_map_json()) {
    request->rig_map_json = load.options()->rig_map_json()->str();
  }
  if (load.options()) request->keys_per_link = load.options()->keys_per_link();
  ++loads_running_;
  log_event("model_load_start",
            {{"connection", id()}, {"name", request->name}, {"upload_bytes", gltf->size()}});
  asio::post(environment_.workers, [self = shared_from_this(), request, gltf, request_id]() {
    ModelHandle model;
    pb::ErrorCode code = pb::ErrorCode::Internal;
    std::string problem;
    try {
      model = self->environment_.registry.load(*request);
    } catch (const ModelError& error) {
      code = error.code();
      problem = error.what();
    } catch (const std::exception& error) {
      problem = error.what();
    }
    asio::post(self->socket_.get_executor(), [self, model, code, problem, request_id]() {
      --self->loads_running_;
      if (model) {
        log_event("model_loaded", {{"connection", self->id()},
                                   {"model", model->id},
                                   {"name", model->name},
                                   {"vertices", model->bound.model.vertex_count()},
                                   {"bind_time_ns", model->bind_time_ns}});
        flatbuffers::FlatBufferBuilder builder = self->take_builder();
        build_model_info(builder, *model, request_id);
        self->send(std::move(builder));
      } else {
        log_event("model_load_failed", {{"connection", self->id()}, {"reason", problem}});
        self->send_error(code, problem, 0, request_id);
      }
      self->process_input();
    });
  });
}

void Connection::handle_stats(std::uint64_t request_id) {
  flatbuffers::FlatBufferBuilder builder = take_builder();
  std::vector<flatbuffers::Offset<pb::ConnectionStats>> connections;
  for (const ConnectionCounters& c : environment_.all_counters()) {
    const pb::LatencyPercentiles latency = c.latency.percentiles();
    connections.push_back(pb::CreateConnectionStatsDirect(
        builder, c.connection_id, c.peer.c_str(), c.client_name.c_str(), c.poses_received,
        c.poses_answered, c.poses_dropped, c.errors, c.bytes_in, c.bytes_out, &latency));
  }
  std::vector<flatbuffers::Offset<pb::ModelStats>> models;
  for (const ModelHandle& model : environment_.registry.models()) {
    const ModelCounters& counters = environment_.model_counters[model->id];
    const pb::LatencyPercentiles latency = counters.deform_latency.percentiles();
    models.push_back(pb::CreateModelStatsDirect(builder, model->id, model->name.c_str(),
                                                counters.poses, counters.errors, &latency));
  }
  pb::finish_message(builder,
                     pb::CreateStatsDirect(builder, nanoseconds_since(environment_.started),
                                           &models, &connections),
                     request_id);
  send(std::move(builder));
}

// ---------------------------------------------------------------------------------------
// Poses on the worker pool.

void Connection::start_next_pose() {
  if (pose_running_ || waiting_poses_.empty() || closed_) return;
  if (outgoing_.size() >= environment_.config.max_poses_in_flight) return;  // client not reading
  pose_running_ = true;
  auto request = std::make_shared<PoseRequest>(std::move(waiting_poses_.front()));
  waiting_poses_.pop_front();
  // Drops are reported by the next PosedVertices (a PositionMap has no field for them).
  const std::uint32_t dropped = request->position_map ? 0 : dropped_since_reply_;
  dropped_since_reply_ -= dropped;
  auto builder = std::make_shared<flatbuffers::FlatBufferBuilder>(take_builder());
  asio::post(environment_.workers, [self = shared_from_this(), request, builder, dropped]() {
    std::string failure;
    pb::ErrorCode code = pb::ErrorCode::Internal;
    std::uint64_t deform_ns = 0;
    try {
      if (request->position_map) {
        deform_ns =
            self->writer_.write_position_map(*request, self->environment_.position_maps, *builder);
      } else {
        deform_ns = self->writer_.write(*request, dropped, *builder);
      }
    } catch (const PositionMapUnavailable& error) {
      code = pb::ErrorCode::NotAvailable;
      failure = error.what();
    } catch (const std::invalid_argument& error) {
      code = pb::ErrorCode::InvalidArgument;
      failure = error.what();
    } catch (const std::exception& error) {
      failure = error.what();
    }
    asio::post(self->socket_.get_executor(), [self, request, builder, failure, code, dropped,
                                              deform_ns]() {
      self->pose_running_ = false;
      if (failure.empty()) {
        self->finish_pose(std::move(*builder), *request, deform_ns);
      } else {
        ++self->environment_.model_counters[request->model->id].errors;
        self->dropped_since_reply_ += dropped;  // still owed to the next reply
        self->send_error(code, "pose " + std::to_string(request->sequence) + ": " + failure,
                         request->sequence, request->request_id);
      }
      self->start_next_pose();
      self->process_input();
      self->close_if_done();
    });
  });
}

void Connection::finish_pose(flatbuffers::FlatBufferBuilder builder, const PoseRequest& request,
                             std::uint64_t deform_ns) {
  ++counters_.poses_answered;
  counters_.latency.add(nanoseconds_since(request.received));
  ModelCounters& model = environment_.model_counters[request.model->id];
  ++model.poses;
  model.deform_latency.add(deform_ns);
  send(std::move(builder));
}

// ---------------------------------------------------------------------------------------
// Writing and closing.

flatbuffers::FlatBufferBuilder Connection::take_builder() {
  if (spare_builders_.empty()) return flatbuffers::FlatBufferBuilder(1024);
  flatbuffers::FlatBufferBuilder builder = std::move(spare_builders_.back());
  spare_builders_.pop_back();
  builder.Clear();
  return builder;
}

void Connection::send(flatbuffers::FlatBufferBuilder builder) {
  if (closed_) return;
  outgoing_.push_back(std::move(builder));
  write_next();
}

void Connection::send_error(pb::ErrorCode code, const std::string& message, std::uint64_t sequence,
                            std::uint64_t request_id, bool fatal) {
  ++counters_.errors;
  flatbuffers::FlatBufferBuilder builder = take_builder();
  pb::build_error(builder, code, message, sequence, request_id, fatal);
  send(std::move(builder));
  if (fatal) {
    log_event("fatal_error",
              {{"connection", id()}, {"code", pb::EnumNameErrorCode(code)}, {"message", message}});
    waiting_poses_.clear();
    draining_ = true;
    input_ = {};
  }
}

void Connection::write_next() {
  if (writing_ || closed_) return;
  if (outgoing_.empty()) {
    close_if_done();
    return;
  }
  writing_ = true;
  const flatbuffers::FlatBufferBuilder& front = outgoing_.front();
  // The whole rest of the frame in each send: asio's default completion condition would cut
  // a 0.85 MB reply into 64 KiB sends (13 system calls instead of one or two).
  const std::size_t size = front.GetSize();
  auto whole_rest = [size](std::error_code error, std::size_t sent) -> std::size_t {
    return error ? 0 : size - sent;
  };
  asio::async_write(socket_, asio::buffer(front.GetBufferPointer(), size), whole_rest,
                    [self = shared_from_this()](std::error_code error, std::size_t n) {
                      self->writing_ = false;
                      self->counters_.bytes_out += n;
                      if (self->spare_builders_.size() < kSpareBuilders) {
                        self->spare_builders_.push_back(std::move(self->outgoing_.front()));
                      }
                      self->outgoing_.pop_front();
                      if (error) {
                        self->close_now();
                        return;
                      }
                      self->write_next();
                      self->start_next_pose();
                      self->process_input();
                    });
}

void Connection::drain() {
  draining_ = true;
  close_if_done();
}

void Connection::close_if_done() {
  if (!draining_ || closed_ || pose_running_ || !waiting_poses_.empty() || loads_running_ > 0) {
    return;
  }
  if (shutting_down_ && authenticated_ && !bye_sent_) {
    bye_sent_ = true;
    flatbuffers::FlatBufferBuilder builder = take_builder();
    pb::finish_message(builder, pb::CreateByeDirect(builder, "server shutting down"));
    send(std::move(builder));
    return;
  }
  if (writing_ || !outgoing_.empty()) return;
  close_now();
}

void Connection::close_now() {
  if (closed_) return;
  closed_ = true;
  hello_deadline_.cancel();
  std::error_code ignored;
  socket_.shutdown(asio::socket_base::shutdown_both, ignored);
  socket_.close(ignored);
  log_event("connection_closed", {{"connection", id()},
                                  {"poses_received", counters_.poses_received},
                                  {"poses_answered", counters_.poses_answered},
                                  {"poses_dropped", counters_.poses_dropped},
                                  {"errors", counters_.errors},
                                  {"bytes_in", counters_.bytes_in},
                                  {"bytes_out", counters_.bytes_out}});
  environment_.on_close(id());
}

}  // namespace sweepd::server

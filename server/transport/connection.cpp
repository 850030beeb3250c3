#include "server/transport/connection.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <utility>
#include <variant>

#include "protocol/descriptor_passing.h"
#include "protocol/messages.h"
#include "server/handlers/client_string_limits.h"
#include "server/handlers/pose_intake.h"
#include "server/log_event.h"
#include "server/replies/clip_info.h"
#include "server/replies/contact_sheet_reply.h"
#include "server/replies/model_info.h"
#include "server/replies/stats_reply.h"
#include "server/replies/welcome_reply.h"
#include "server/transport/constant_time_equal.h"

namespace sweepd::server {
namespace {

namespace pb = sweepd::protocol;
constexpr std::size_t kReadChunkBytes = 64 * 1024;

// The code for what a worker's render or deformation threw: NotAvailable without a GPU for it,
// InvalidArgument for a request the work refused, else Internal.
pb::ErrorCode error_code_of(const std::exception& error) {
  if (dynamic_cast<const PositionMapUnavailable*>(&error) != nullptr)
    return pb::ErrorCode::NotAvailable;
  if (dynamic_cast<const std::invalid_argument*>(&error) != nullptr)
    return pb::ErrorCode::InvalidArgument;
  return pb::ErrorCode::Internal;
}

std::uint64_t nanoseconds_since(std::chrono::steady_clock::time_point from) {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - from)
          .count());
}

// A TLS client's first bytes read as a length prefix: a handshake record's type 0x16 and
// version 0x03 0x0N (N = 1 to 4) make the prefix's low bytes 0x0316 and its value > 64 KiB.
bool starts_like_tls_handshake(std::uint64_t declared_bytes) {
  const std::uint64_t minor = (declared_bytes >> 16) & 0xff;
  return (declared_bytes & 0xffff) == 0x0316 && minor >= 1 && minor <= 4;
}

}  // namespace

Connection::Connection(ConnectionStream stream, std::uint64_t id, std::string peer,
                       ConnectionEnvironment& environment)
    : stream_(std::move(stream)),
      environment_(environment),
      hello_deadline_(stream_.get_executor()),
      frame_deadline_(stream_.get_executor()),
      idle_deadline_(stream_.get_executor()),
      send_deadline_(stream_.get_executor()),
      // Before Hello only a small frame: an unauthenticated peer cannot make the server buffer.
      reader_(
          std::min(environment.config.max_hello_frame_bytes, environment.config.max_frame_bytes),
          &environment.buffer_budget),
      read_buffer_(kReadChunkBytes),
      gate_(stream_.plain_socket_handle()),
      writer_(environment.config.deform_threads, environment.collision) {
  counters_.connection_id = id;
  counters_.peer = std::move(peer);
  secured_ = stream_.pending_handshake().empty();
  // Before Hello only a small message too: websocketpp takes a message whole before the frame
  // reader sees it.
  stream_.set_max_message_bytes(reader_.max_frame_bytes() + protocol::kLengthPrefixBytes);
}

void Connection::start() {
  log_event("connection_open", {{"connection", id()},
                                {"peer", counters_.peer},
                                {"tls", stream_.tls()},
                                {"websocket", stream_.websocket()}});
  arm_hello_deadline();
  arm_idle_deadline();
  secure_then([self = shared_from_this()]() { self->read_more(); });
}

void Connection::refuse(pb::ErrorCode code, const std::string& message) {
  log_event("connection_refused",
            {{"connection", id()}, {"peer", counters_.peer}, {"reason", message}});
  arm_hello_deadline();  // bounds the TLS handshake the refusal waits for
  secure_then([self = shared_from_this(), code, message]() {
    self->send_error(code, message, 0, 0, true);
  });
}

void Connection::arm_hello_deadline() {
  hello_deadline_.expires_after(std::chrono::milliseconds(environment_.config.hello_timeout_ms));
  hello_deadline_.async_wait([self = shared_from_this()](std::error_code error) {
    if (error || self->authenticated_ || self->draining_ || self->closed_) return;
    const std::string timeout = std::to_string(self->environment_.config.hello_timeout_ms);
    if (!self->secured_) {
      self->cut(pb::ErrorCode::NotAuthenticated,
                "no " + self->stream_.pending_handshake() + " handshake within " + timeout + " ms");
      return;
    }
    self->send_error(pb::ErrorCode::NotAuthenticated, "no Hello within " + timeout + " ms", 0, 0,
                     true);
  });
}

void Connection::secure_then(std::function<void()> next) {
  if (secured_) {
    next();
    return;
  }
  stream_.handshake(
      [self = shared_from_this(), next = std::move(next)](const std::string& failure) {
        if (self->closed_) return;
        if (!failure.empty()) {
          self->cut(pb::ErrorCode::NotAuthenticated, failure);
          return;
        }
        self->secured_ = true;
        if (self->stream_.tls()) {
          const TlsSession session = self->stream_.tls_session();
          log_event("tls_established", {{"connection", self->id()},
                                        {"version", session.version},
                                        {"cipher", session.cipher},
                                        {"client_certificate", session.client_subject}});
        }
        if (self->stream_.websocket()) log_event("websocket_open", {{"connection", self->id()}});
        next();
      });
}

void Connection::shut_down() {
  shutting_down_ = true;
  drain();
}

void Connection::cut(pb::ErrorCode code, const std::string& reason) {
  log_event("connection_cut", {{"connection", id()}, {"peer", counters_.peer}, {"reason", reason}});
  if (!secured_) {  // before the TLS handshake there is no channel to send an Error on
    close_now();
    return;
  }
  send_error(code, reason, 0, 0, true);
}

// ---------------------------------------------------------------------------------------
// Deadlines: a timer that fires after its connection closed, or was re-armed, does nothing.

bool Connection::mid_frame() const { return reader_.mid_frame() || stream_.mid_message(); }

void Connection::watch_frame() {
  if (!mid_frame()) {
    if (frame_deadline_armed_) frame_deadline_.cancel();
    frame_deadline_armed_ = false;
    return;
  }
  if (frame_deadline_armed_) return;
  frame_deadline_armed_ = true;
  const std::uint32_t timeout_ms = environment_.config.frame_timeout_ms;
  frame_deadline_.expires_after(std::chrono::milliseconds(timeout_ms));
  frame_deadline_.async_wait([self = shared_from_this(), timeout_ms](std::error_code error) {
    if (error || self->closed_ || self->draining_ || !self->mid_frame()) return;
    self->cut(pb::ErrorCode::BadFrame,
              "a frame was not whole within " + std::to_string(timeout_ms) + " ms");
  });
}

bool Connection::has_work() const {
  return pose_running_ || !waiting_poses_.empty() || loads_running_ > 0 || !outgoing_.empty() ||
         mid_frame();
}

void Connection::arm_idle_deadline() {
  const std::uint32_t timeout_ms = environment_.config.idle_timeout_ms;
  if (timeout_ms == 0) return;
  idle_deadline_.expires_after(std::chrono::milliseconds(timeout_ms));
  idle_deadline_.async_wait([self = shared_from_this(), timeout_ms](std::error_code error) {
    if (error || self->closed_ || self->draining_) return;
    if (self->has_work()) {
      self->arm_idle_deadline();  // busy, not idle: look again later
      return;
    }
    self->cut(pb::ErrorCode::Internal,
              "idle: no request for " + std::to_string(timeout_ms) + " ms; closing");
  });
}

void Connection::arm_send_deadline() {
  const auto timeout = std::chrono::milliseconds(environment_.config.send_timeout_ms);
  send_deadline_.expires_at(last_send_progress_ + timeout);
  send_deadline_.async_wait([self = shared_from_this(), timeout](std::error_code error) {
    if (error || self->closed_ || !self->writing_) return;
    if (Clock::now() - self->last_send_progress_ < timeout) {
      self->arm_send_deadline();  // the client took bytes meanwhile
      return;
    }
    // It reads nothing, so no Error would reach it: closed at once.
    log_event("connection_cut", {{"connection", self->id()},
                                 {"peer", self->counters_.peer},
                                 {"reason", "the client took no reply bytes for " +
                                                std::to_string(timeout.count()) + " ms"}});
    self->close_now();
  });
}

// ---------------------------------------------------------------------------------------
// Reading.

void Connection::read_more() {
  if (reading_ || closed_ || (draining_ && !shutting_down_)) return;
  reading_ = true;
  stream_.async_read_some(asio::buffer(read_buffer_), [self = shared_from_this()](
                                                          std::error_code error, std::size_t n) {
    self->reading_ = false;
    if (self->closed_) return;
    if (error) {
      if (const std::string failure = self->stream_.failure(); !failure.empty()) {
        log_event(
            "connection_cut",
            {{"connection", self->id()}, {"peer", self->counters_.peer}, {"reason", failure}});
      } else if (self->mid_frame()) {
        log_event("truncated_frame", {{"connection", self->id()}});
      }
      self->draining_ = true;
      self->close_if_done();
      return;
    }
    self->counters_.bytes_in += n;
    self->input_ = std::span<const std::uint8_t>(self->read_buffer_.data(), n);
    self->arm_idle_deadline();
    self->process_input();
    self->watch_frame();
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
  if (deferred_ != nullptr) {
    if (reply_uncounted_.load(std::memory_order_acquire) || closed_) return;
    dispatch(*std::exchange(deferred_, nullptr));
  }
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
      if (!authenticated_ && event.error == pb::FrameError::kOversized) {
        cut(pb::ErrorCode::FrameTooLarge,
            starts_like_tls_handshake(event.declared_bytes)
                ? "a TLS handshake on a plain port (this listener has no --tls-cert)"
                : "before Hello a frame may have at most " +
                      std::to_string(reader_.max_frame_bytes()) + " bytes; this one declares " +
                      std::to_string(event.declared_bytes));
        continue;
      }
      send_error(pb::error_code_for(event.error), event.reason, 0, 0);
      // Running out of the shared budget is not this client's fault; garbage is.
      if (event.error != pb::FrameError::kOverBudget &&
          ++frame_errors_ >= environment_.config.max_frame_errors) {
        cut(pb::ErrorCode::BadFrame,
            std::to_string(frame_errors_) + " bad frames on this connection; closing");
      }
      continue;
    }
    if (event.message->body_type() != pb::Body::Pose &&
        reply_uncounted_.load(std::memory_order_acquire)) {
      deferred_ = event.message;  // valid until the reader's next read: none until dispatched
      return;
    }
    dispatch(*event.message);
  }
  if (input_.empty()) read_more();
}

// ---------------------------------------------------------------------------------------
// Requests: authentication here, the rest dispatched to handlers and encoders.

void Connection::dispatch(const pb::Message& message) {
  const std::uint64_t request_id = message.request_id();
  environment_.traffic.count_request(message.body_type());
  if (!authenticated_ && message.body_type() != pb::Body::Hello) {
    send_error(pb::ErrorCode::NotAuthenticated, "the first message must be Hello", 0, request_id,
               true);
    return;
  }
  if (const std::optional<RequestError> refusal = find_overlong_string(message)) {
    send_error(*refusal, request_id);
    return;
  }
  if (!authenticated_) {
    authenticate(*message.body_as_Hello(), request_id);
    return;
  }
  if (shutting_down_) {
    send_error(pb::ErrorCode::ShuttingDown, "the server is shutting down and takes no new work", 0,
               request_id);
    return;
  }
  ModelService& models = environment_.models;
  switch (message.body_type()) {
    case pb::Body::Pose:
      queue_pose(*message.body_as_Pose(), request_id);
      break;
    case pb::Body::ListModels: {
      flatbuffers::FlatBufferBuilder builder = take_builder();
      answer_list_models(models, request_id, builder);
      send(std::move(builder));
      break;
    }
    case pb::Body::LoadModel: {
      // The request's bytes live in the reader's storage: read_load_model copies them.
      auto work =
          std::make_shared<const LoadModelWork>(read_load_model(*message.body_as_LoadModel()));
      log_event("model_load_start",
                {{"connection", id()}, {"name", work->name}, {"upload_bytes", work->gltf.size()}});
      change_model(
          request_id, [models = &models, work]() { return run_load_model(*models, *work); },
          log_load_outcome);
      break;
    }
    case pb::Body::StatsRequest: {
      flatbuffers::FlatBufferBuilder builder = take_builder();
      build_stats(builder, nanoseconds_since(environment_.started), models.models(),
                  environment_.model_counters, environment_.all_counters(),
                  environment_.collision.snapshot(), request_id);
      send(std::move(builder));
      break;
    }
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
        queue_pose(*map->pose(), request_id, map);
      }
      break;
    }
    case pb::Body::MeshRequest: {
      flatbuffers::FlatBufferBuilder builder = take_builder();
      if (const auto error =
              answer_mesh_request(models, *message.body_as_MeshRequest(), request_id, builder)) {
        send_error(*error, request_id);
      } else {
        send(std::move(builder));
      }
      break;
    }
    case pb::Body::EditKeyEllipse: {
      // Storing the edited model durably (fsync) takes milliseconds: on a worker.
      const KeyEllipseEditWork work = read_key_ellipse_edit(*message.body_as_EditKeyEllipse());
      change_model(
          request_id, [models = &models, work]() { return run_key_ellipse_edit(*models, work); },
          log_edit_outcome);
      break;
    }
    case pb::Body::UploadClip:
      upload_clip(*message.body_as_UploadClip(), request_id);
      break;
    case pb::Body::PoseFromClip: {
      const pb::PoseFromClip* request = message.body_as_PoseFromClip();
      if (request->pose() == nullptr || request->clip() == nullptr) {
        send_error(pb::ErrorCode::InvalidArgument, "a PoseFromClip needs a pose and a clip", 0,
                   request_id);
      } else {
        queue_intake(read_clip_pose_message(models, environment_.clips, *request->pose(),
                                            *request->clip(), request_id),
                     request_id);
      }
      break;
    }
    case pb::Body::PoseByName: {
      const pb::PoseByName* request = message.body_as_PoseByName();
      if (request->pose() == nullptr) {
        send_error(pb::ErrorCode::InvalidArgument, "a PoseByName needs a pose", 0, request_id);
      } else {
        queue_intake(read_named_pose_message(models, *request, request_id), request_id);
      }
      break;
    }
    case pb::Body::MapSharedMemory:
      map_shared_memory(*message.body_as_MapSharedMemory(), request_id);
      break;
    case pb::Body::ContactSheetRequest:
      render_contact_sheet(*message.body_as_ContactSheetRequest(), request_id);
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

void Connection::authenticate(const pb::Hello& hello, std::uint64_t request_id) {
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
  reader_.set_max_frame_bytes(environment_.config.max_frame_bytes);
  stream_.set_max_message_bytes(environment_.config.max_frame_bytes + protocol::kLengthPrefixBytes);
  delivery_ = hello.delivery() == pb::PoseDelivery::LatestWins ? pb::PoseDelivery::LatestWins
                                                               : pb::PoseDelivery::InOrder;
  log_event("hello", {{"connection", id()},
                      {"client", counters_.client_name},
                      {"delivery", pb::EnumNamePoseDelivery(delivery_)}});
  flatbuffers::FlatBufferBuilder builder = take_builder();
  build_welcome(builder, environment_.config, environment_.position_maps.enabled(),
                stream_.unix_socket(), id(), request_id);
  send(std::move(builder));
}

void Connection::queue_pose(const pb::Pose& pose, std::uint64_t request_id,
                            const pb::PositionMapRequest* map) {
  if (map != nullptr && map->clip() != nullptr) {
    queue_intake(read_clip_pose_message(environment_.models, environment_.clips, pose, *map->clip(),
                                        request_id, map),
                 request_id);
  } else {
    queue_intake(read_pose_message(environment_.models, pose, request_id, map), request_id);
  }
}

void Connection::queue_intake(std::variant<PoseRequest, RequestError> intake,
                              std::uint64_t request_id) {
  ++counters_.poses_received;
  if (const RequestError* error = std::get_if<RequestError>(&intake)) {
    send_error(*error, request_id);
    return;
  }
  PoseRequest& request = std::get<PoseRequest>(intake);
  if (auto error = place_in_shared_region(request, shared_region_)) {
    send_error(*error, request_id);
    return;
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

void Connection::map_shared_memory(const pb::MapSharedMemory& request, std::uint64_t request_id) {
  const std::uint64_t bytes = request.bytes();
  const std::size_t limit = environment_.config.max_frame_bytes;
  if (!stream_.unix_socket()) {
    send_error(pb::ErrorCode::NotAvailable,
               "MapSharedMemory needs a Unix socket connection: a descriptor cannot cross TCP, TLS "
               "or WebSocket",
               0, request_id);
  } else if (shared_region_) {
    send_error(pb::ErrorCode::InvalidArgument,
               "this connection has a shared region already (" +
                   std::to_string(shared_region_->size()) + " bytes); it maps one",
               0, request_id);
  } else if (bytes == 0 || bytes > limit) {
    send_error(pb::ErrorCode::InvalidArgument,
               "MapSharedMemory asks for " + std::to_string(bytes) + " bytes; a region has 1 to " +
                   std::to_string(limit) + " (max_frame_bytes)",
               0, request_id);
  } else if (!environment_.buffer_budget.take(bytes)) {
    send_error(pb::ErrorCode::ResourceExhausted,
               "the server's buffer budget has no room for a shared region of " +
                   std::to_string(bytes) + " bytes now",
               0, request_id);
  } else {
    try {
      shared_region_ = SharedRegion::create(bytes);
    } catch (const std::system_error& error) {
      environment_.buffer_budget.give_back(bytes);
      send_error(
          pb::ErrorCode::ResourceExhausted,
          "cannot make a shared region of " + std::to_string(bytes) + " bytes: " + error.what(), 0,
          request_id);
      return;
    }
    log_event("shared_memory_mapped", {{"connection", id()}, {"bytes", bytes}});
    flatbuffers::FlatBufferBuilder builder = take_builder();
    pb::finish_message(builder, pb::CreateSharedMemory(builder, bytes), request_id);
    descriptor_frame_ = builder.GetBufferPointer();
    send(std::move(builder));
  }
}

void Connection::upload_clip(const pb::UploadClip& upload, std::uint64_t request_id) {
  // The fields live in the reader's storage, reused by the next frame: copied for the worker.
  auto copied = std::make_shared<const ClipUpload>(ClipUpload::of_message(upload));
  log_event("clip_upload_start",
            {{"connection", id()},
             {"name", copied->name},
             {"format", copied->range_of_motion ? "range_of_motion"
                        : copied->gltf.empty()  ? "bvh"
                                                : "gltf"},
             {"upload_bytes", copied->gltf.empty() ? copied->bvh.size() : copied->gltf.size()}});
  ++loads_running_;
  environment_.workers.post(fair_share_, [self = shared_from_this(), copied, request_id]() {
    std::variant<ClipHandle, RequestError> outcome =
        self->environment_.clips.add(*copied, self->environment_.models);
    // (1.12) Played on the model the client names: what that leaves unmapped is said now, and
    // the player built for it serves the frames asked for next.
    std::vector<std::string> model_warnings;
    if (const ClipHandle* clip = std::get_if<ClipHandle>(&outcome); clip && copied->model_id)
      model_warnings = warnings_on_model(**clip, self->environment_.models, *copied->model_id);
    asio::post(self->stream_.get_executor(), [self, outcome = std::move(outcome),
                                              model_warnings = std::move(model_warnings),
                                              request_id]() {
      --self->loads_running_;
      if (const ClipHandle* clip = std::get_if<ClipHandle>(&outcome)) {
        log_event("clip_uploaded", {{"connection", self->id()},
                                    {"clip", (*clip)->id()},
                                    {"name", (*clip)->name()},
                                    {"frames", (*clip)->clip().frame_count},
                                    {"model_warnings", model_warnings.size()}});
        flatbuffers::FlatBufferBuilder builder = self->take_builder();
        build_clip_info(builder, **clip, request_id, model_warnings);
        self->send(std::move(builder));
      } else {
        const RequestError& error = std::get<RequestError>(outcome);
        log_event("clip_upload_failed", {{"connection", self->id()}, {"reason", error.message}});
        self->send_error(error, request_id);
      }
      self->process_input();
    });
  });
}

void Connection::render_contact_sheet(const pb::ContactSheetRequest& request,
                                      std::uint64_t request_id) {
  // Checked and copied here: the request lives in the reader's storage.
  std::variant<SheetWork, RequestError> read =
      read_contact_sheet_request(environment_.models, environment_.clips, request);
  if (const RequestError* error = std::get_if<RequestError>(&read)) {
    send_error(*error, request_id);
    return;
  }
  auto work = std::make_shared<const SheetWork>(std::move(std::get<SheetWork>(read)));
  // The picture's pixels are held while it is drawn: they count against the buffer budget of
  // every client, as frames and replies do.
  const std::size_t pixel_bytes = work->options.pixel_count() * 4;
  if (!environment_.buffer_budget.take(pixel_bytes)) {
    send_error(pb::ErrorCode::ResourceExhausted,
               "contact sheet: the server's buffer budget has no room for its " +
                   std::to_string(pixel_bytes) + " bytes of pixels now; retry later",
               0, request_id);
    return;
  }
  log_event("contact_sheet_start", {{"connection", id()},
                                    {"model", work->model->id},
                                    {"frames", work->options.frames.size()},
                                    {"methods", work->options.methods.size()}});
  ++loads_running_;
  asio::post(environment_.gpu_waiters, [self = shared_from_this(), work, pixel_bytes,
                                        request_id]() {
    const auto start = Clock::now();
    auto picture = std::make_shared<sheet::SheetPicture>();
    std::optional<RequestError> failure;
    try {
      CollisionPairFinder pairs(self->environment_.collision);
      self->environment_.contact_sheets.render(*work, &pairs, *picture);
    } catch (const std::exception& error) {
      failure = RequestError{error_code_of(error), error.what()};
    }
    const std::uint64_t took_ns = nanoseconds_since(start);
    self->environment_.buffer_budget.give_back(pixel_bytes);
    asio::post(self->stream_.get_executor(), [self, work, picture, failure, took_ns, request_id]() {
      --self->loads_running_;
      if (failure) {
        log_event("contact_sheet_failed",
                  {{"connection", self->id()}, {"reason", failure->message}});
        self->send_error(*failure, request_id);
      } else {
        log_event("contact_sheet", {{"connection", self->id()},
                                    {"width", picture->width},
                                    {"height", picture->height},
                                    {"png_bytes", picture->png.size()},
                                    {"ms", static_cast<double>(took_ns) / 1e6}});
        flatbuffers::FlatBufferBuilder builder = self->take_builder();
        build_contact_sheet(builder, work->model->id, *picture, request_id);
        self->send(std::move(builder));
      }
      self->process_input();
    });
  });
}

void Connection::change_model(std::uint64_t request_id, std::function<ModelChange()> change,
                              LogModelChange log_outcome) {
  ++loads_running_;
  environment_.workers.post(fair_share_, [self = shared_from_this(), change = std::move(change),
                                          log_outcome, request_id]() {
    ModelChange outcome = change();
    asio::post(self->stream_.get_executor(),
               [self, outcome = std::move(outcome), log_outcome, request_id]() {
                 --self->loads_running_;
                 log_outcome(self->id(), outcome);
                 if (const ModelHandle* model = std::get_if<ModelHandle>(&outcome)) {
                   flatbuffers::FlatBufferBuilder builder = self->take_builder();
                   build_model_info(builder, **model, request_id);
                   self->send(std::move(builder));
                 } else {
                   const RequestError& error = std::get<RequestError>(outcome);
                   self->send_error(error.code, error.message, 0, request_id);
                 }
                 self->process_input();
               });
  });
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
  // A pose whose folding waits on the GPU thread runs on the pool kept for that, so that its
  // wait never holds a deformation worker another connection's CPU work could use.
  const bool waits_on_gpu = environment_.collision.backend() == gpu::CollisionBackend::kGpu &&
                            request->method == deform::DeformMethod::kSweep &&
                            request->features.collision();
  auto job = [self = shared_from_this(), request, builder, dropped]() {
    std::string failure;
    pb::ErrorCode code = pb::ErrorCode::Internal;
    std::uint64_t deform_ns = 0;
    try {
      // Another replica's edit of the model on a shared store: posed from here on (one stat).
      request->model = self->environment_.models.current(request->model);
      if (request->position_map) {
        deform_ns =
            self->writer_.write_position_map(*request, self->environment_.position_maps, *builder);
      } else {
        deform_ns = self->writer_.write(*request, dropped, *builder);
      }
    } catch (const std::exception& error) {
      code = error_code_of(error);
      failure = error.what();
    }
    std::optional<std::size_t> sent;
    if (failure.empty()) {
      // Set before the client can see the reply: a request other than a pose that it sends
      // after reading it (a Stats) waits until the I/O thread has counted this pose.
      self->reply_uncounted_.store(true, std::memory_order_release);
      sent = self->gate_.try_send({builder->GetBufferPointer(), builder->GetSize()});
      if (!sent) self->reply_uncounted_.store(false, std::memory_order_relaxed);
    }
    asio::post(self->stream_.get_executor(), [self, request, builder, failure, code, dropped,
                                              deform_ns, sent]() {
      self->pose_running_ = false;
      if (failure.empty()) {
        self->count_pose(*request, deform_ns);
        self->reply_uncounted_.store(false, std::memory_order_relaxed);
        self->deliver_pose(std::move(*builder), sent);
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
  };
  if (waits_on_gpu) {
    asio::post(environment_.gpu_waiters, std::move(job));
  } else {
    environment_.workers.post(fair_share_, std::move(job));
  }
}

void Connection::count_pose(const PoseRequest& request, std::uint64_t deform_ns) {
  ++counters_.poses_answered;
  const std::uint64_t latency_ns = nanoseconds_since(request.received);
  counters_.latency.add(latency_ns);
  (request.position_map ? environment_.traffic.position_map_latency
                        : environment_.traffic.pose_latency)
      .add(latency_ns);
  ModelCounters& model = environment_.model_counters[request.model->id];
  ++model.poses;
  model.deform_latency.add(deform_ns);
}

void Connection::deliver_pose(flatbuffers::FlatBufferBuilder builder,
                              std::optional<std::size_t> sent) {
  if (!sent) {
    send(std::move(builder));
    return;
  }
  counters_.bytes_out += *sent;
  if (*sent == builder.GetSize()) {
    environment_.builders.give_back(std::move(builder));
  } else {
    gate_.take_remainder();
    send(std::move(builder), *sent);
  }
}

// ---------------------------------------------------------------------------------------
// Writing and closing.

flatbuffers::FlatBufferBuilder Connection::take_builder() { return environment_.builders.take(); }

void Connection::send(flatbuffers::FlatBufferBuilder builder, std::size_t already_sent) {
  if (closed_) return;
  // The reply is built: its bytes are in use whatever the budget says.
  environment_.buffer_budget.take_anyway(builder.GetSize());
  queued_reply_bytes_ += builder.GetSize();
  if (already_sent > 0) {
    // Nothing else can be under way: the worker's send held the socket (ReplySendGate).
    outgoing_.push_front(std::move(builder));
    front_sent_ = already_sent;
  } else {
    outgoing_.push_back(std::move(builder));
  }
  if (queued_reply_bytes_ > environment_.config.max_send_queue_bytes) {
    log_event(
        "connection_cut",
        {{"connection", id()},
         {"peer", counters_.peer},
         {"reason", "unread replies passed " +
                        std::to_string(environment_.config.max_send_queue_bytes) + " bytes"}});
    close_now();
    return;
  }
  write_next();
}

void Connection::send_error(pb::ErrorCode code, const std::string& message, std::uint64_t sequence,
                            std::uint64_t request_id, bool fatal) {
  ++counters_.errors;
  environment_.traffic.count_error(code);
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

void Connection::send_error(const RequestError& error, std::uint64_t request_id) {
  if (error.charged_model != 0) ++environment_.model_counters[error.charged_model].errors;
  send_error(error.code, error.message, error.sequence, request_id);
}

void Connection::write_next() {
  if (writing_ || closed_) return;
  if (outgoing_.empty()) {
    gate_.release();
    close_if_done();
    return;
  }
  if (!gate_.acquire()) return;  // a worker's short send: its rest goes first (deliver_pose)
  writing_ = true;
  last_send_progress_ = Clock::now();
  arm_send_deadline();
  if (!write_descriptor()) return;
  const flatbuffers::FlatBufferBuilder& front = outgoing_.front();
  const std::size_t size = front.GetSize();
  const std::size_t from = std::exchange(front_sent_, 0);
  // Each partial send is progress for the send deadline.
  stream_.async_write(
      asio::buffer(front.GetBufferPointer() + from, size - from),
      [this]() { last_send_progress_ = Clock::now(); },
      [self = shared_from_this(), size](std::error_code error, std::size_t n) {
        self->writing_ = false;
        self->send_deadline_.cancel();
        self->counters_.bytes_out += n;
        if (self->closed_) return;  // close_now gave the queue's bytes back
        self->environment_.buffer_budget.give_back(size);
        self->queued_reply_bytes_ -= size;
        self->environment_.builders.give_back(std::move(self->outgoing_.front()));
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

bool Connection::write_descriptor() {
  // A builder's buffer stays where it is when the builder is moved into the queue.
  const flatbuffers::FlatBufferBuilder& front = outgoing_.front();
  if (descriptor_frame_ == nullptr || front.GetBufferPointer() != descriptor_frame_) return true;
  std::optional<std::size_t> sent;
  try {
    sent =
        pb::send_with_descriptor(stream_.plain_socket_handle(),
                                 {front.GetBufferPointer(), front.GetSize()}, shared_region_->fd());
  } catch (const std::system_error&) {
    writing_ = false;
    close_now();
    return false;
  }
  if (!sent) {
    stream_.async_wait_writable([self = shared_from_this()](std::error_code error) {
      self->writing_ = false;
      self->send_deadline_.cancel();
      if (self->closed_) return;
      if (error) {
        self->close_now();
        return;
      }
      self->write_next();
    });
    return false;
  }
  descriptor_frame_ = nullptr;
  front_sent_ = *sent;
  counters_.bytes_out += *sent;
  last_send_progress_ = Clock::now();
  return true;
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
  if (stream_.websocket() && !close_frame_sent_) {
    // A browser sees a clean close (1000); written under the send deadline like a reply.
    close_frame_sent_ = true;
    writing_ = true;
    last_send_progress_ = Clock::now();
    arm_send_deadline();
    stream_.send_close_frame([self = shared_from_this()]() {
      self->writing_ = false;
      self->send_deadline_.cancel();
      self->close_now();
    });
    return;
  }
  close_now();
}

void Connection::close_now() {
  if (closed_) return;
  closed_ = true;
  hello_deadline_.cancel();
  frame_deadline_.cancel();
  idle_deadline_.cancel();
  send_deadline_.cancel();
  environment_.buffer_budget.give_back(queued_reply_bytes_);
  queued_reply_bytes_ = 0;
  // Poses still running hold the region itself until they end.
  if (shared_region_) environment_.buffer_budget.give_back(shared_region_->size());
  gate_.close();  // no worker sends on the socket from here on
  stream_.close();
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

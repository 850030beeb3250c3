#include <string>
#include <utility>

#include "protocol/descriptor_passing.h"
#include "protocol/messages.h"
#include "server/log_event.h"
#include "server/transport/connection.h"

namespace sweepd::server {

namespace pb = sweepd::protocol;

// Writing replies, in the order they were queued, and closing.

flatbuffers::FlatBufferBuilder Connection::take_builder() { return environment_.builders.take(); }

void Connection::queue_reply(flatbuffers::FlatBufferBuilder builder, std::size_t already_sent) {
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

void Connection::send_region(std::shared_ptr<const SharedRegion> region,
                             flatbuffers::FlatBufferBuilder reply) {
  shared_region_ = std::move(region);
  // A builder's buffer stays where it is when the builder is moved into the queue.
  descriptor_frame_ = reply.GetBufferPointer();
  queue_reply(std::move(reply));
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
  if (authenticated_) --environment_.members_open;
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

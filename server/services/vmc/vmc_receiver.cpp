#include "server/services/vmc/vmc_receiver.h"

#include <linux/sockios.h>
#include <sys/ioctl.h>
#include <sys/socket.h>

#include <ctime>
#include <stdexcept>

#include "motion/name_list.h"
#include "server/log_event.h"

namespace sweepd::server {

VmcReceiver::VmcReceiver(asio::io_context& io, ModelService& models, std::string address, int port,
                         std::string stream)
    : models_(models),
      address_(std::move(address)),
      port_(port),
      stream_name_(std::move(stream)),
      socket_(io) {}

int VmcReceiver::open() {
  const std::string where = "--vmc-listen " + address_ + ":" + std::to_string(port_);
  asio::error_code error;
  const asio::ip::address address = asio::ip::make_address(address_, error);
  if (error) throw std::runtime_error(where + ": '" + address_ + "' is not an IP address");
  const asio::ip::udp::endpoint endpoint(address, static_cast<unsigned short>(port_));
  socket_.open(endpoint.protocol(), error);
  if (!error) socket_.bind(endpoint, error);
  if (error) throw std::runtime_error(where + ": " + error.message());
  // The kernel stamps each datagram as it arrives (read back by SIOCGSTAMPNS).
  const int on = 1;
  ::setsockopt(socket_.native_handle(), SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on));
  return socket_.local_endpoint().port();
}

void VmcReceiver::start() { receive_next(); }

void VmcReceiver::close() {
  asio::error_code ignored;
  socket_.close(ignored);
}

void VmcReceiver::receive_next() {
  socket_.async_receive_from(asio::buffer(buffer_), sender_,
                             [this](const asio::error_code& error, std::size_t size) {
                               if (error == asio::error::operation_aborted) return;
                               if (!error) take_packet(size);
                               receive_next();
                             });
}

std::chrono::steady_clock::time_point VmcReceiver::arrival_of_last_datagram() {
  const auto now = std::chrono::steady_clock::now();
  timespec stamp{}, wall{};
  if (::ioctl(socket_.native_handle(), SIOCGSTAMPNS, &stamp) != 0 ||
      ::clock_gettime(CLOCK_REALTIME, &wall) != 0)
    return now;
  // The stamp is wall-clock time: its age now, taken off the steady clock's now.
  const auto age = std::chrono::seconds(wall.tv_sec - stamp.tv_sec) +
                   std::chrono::nanoseconds(wall.tv_nsec - stamp.tv_nsec);
  if (age <= std::chrono::nanoseconds::zero() || age > std::chrono::seconds(1)) return now;
  return now - std::chrono::duration_cast<std::chrono::steady_clock::duration>(age);
}

void VmcReceiver::take_packet(std::size_t size) {
  ++counters_.packets;
  const auto arrived = arrival_of_last_datagram();
  const auto now = std::chrono::steady_clock::now();
  // Forged source addresses must not grow the table without bound.
  if (senders_.size() >= kMostSenders)
    std::erase_if(senders_,
                  [&](const auto& sender) { return sender.second < now - kSenderWindow; });
  if (senders_.size() < kMostSenders || senders_.contains(sender_)) senders_[sender_] = now;
  const std::optional<OscPacket> packet = read_osc_packet({buffer_.data(), size});
  if (!packet) {
    ++counters_.dropped_packets;
    return;
  }
  if (stream_.apply(*packet, counters_)) publish_frame(arrived);
}

ModelHandle VmcReceiver::model() const {
  for (const ModelHandle& held : models_.held_models()) {
    if (held->name == stream_name_) return held;
  }
  return nullptr;
}

const std::array<int, deform::kHumanBodyBoneCount>& VmcReceiver::bones_of(
    const ModelHandle& model) {
  if (mapped_model_ == model->id) return bones_;
  const deform::Skeleton& skeleton = model->bound.model.skeleton;
  bones_ = deform::map_human_body_bones(skeleton, model->bound.rig);
  mapped_model_ = model->id;
  std::vector<std::string> unreached;
  for (int joint : deform::joints_without_human_body_bone(skeleton, bones_))
    unreached.push_back(skeleton.joints[joint].name);
  log_event("vmc_stream_model", {{"stream", stream_name_},
                                 {"model", model->id},
                                 {"joints", skeleton.size()},
                                 {"joints_at_rest", unreached.size()},
                                 {"at_rest", motion::name_list(unreached)}});
  return bones_;
}

void VmcReceiver::publish_frame(std::chrono::steady_clock::time_point arrived) {
  const std::uint64_t frame = ++counters_.frames;
  const ModelHandle model = this->model();
  if (!model) {
    ++counters_.frames_without_model;
    return;
  }
  const deform::Pose pose = stream_.pose_for(model->bound.model.skeleton, bones_of(model));
  std::erase_if(subscribers_, [&](const Subscriber& subscriber) {
    return !subscriber(model, pose, frame, arrived);
  });
}

VmcSnapshot VmcReceiver::snapshot() {
  const auto since = std::chrono::steady_clock::now() - kSenderWindow;
  std::erase_if(senders_, [&](const auto& sender) { return sender.second < since; });
  return {stream_name_, counters_, senders_.size(), subscribers_.size()};
}

}  // namespace sweepd::server

// VmcReceiver: one VMC receiver (sweepd --vmc-listen ADDR[:PORT][=MODEL], VMC's "Marionette";
// vmc_receivers.h holds them all): a UDP socket on the server's I/O thread; each datagram is read
// as an OSC packet (osc_packet.h) into the stream (vmc_stream.h) named by its model; each frame a
// packet ends poses the held model of that name and goes to the stream's subscribers
// (SubscribeStream, server/handlers/).
//
// One stream per receiver: every sender to its port poses it, and the latest frame wins (two
// senders to one port interleave their frames; give each its own --vmc-listen). A subscriber is
// a callback run on the I/O thread with the model, the pose, the frame's number (1, 2, ...) and
// when the datagram that ended it reached this host (the kernel's receive time, SO_TIMESTAMPNS,
// so that a frame's latency counts its wait for the I/O thread); it returns false once its
// connection is gone, and is then forgotten. Frames that end while the model is not held are
// counted (frames_without_model) and go nowhere.
//
// open() binds the socket (throws std::runtime_error naming the address and why) and returns the
// bound port; start() begins reading. Everything else runs on the I/O thread, snapshot() too.
#pragma once

#include <array>
#include <asio.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "deform/model/pose.h"
#include "deform/rig/human_body_bones.h"
#include "server/models/model_service.h"
#include "server/services/vmc/vmc_stream.h"

namespace sweepd::server {

struct VmcSnapshot {
  std::string stream;  // the stream's name (its model's)
  VmcCounters counters;
  std::size_t senders = 0;      // addresses heard from in the last kSenderWindow
  std::size_t subscribers = 0;  // callbacks held
};

class VmcReceiver {
 public:
  using Subscriber =
      std::function<bool(const ModelHandle& model, const deform::Pose& pose, std::uint64_t frame,
                         std::chrono::steady_clock::time_point arrived)>;
  // A sender heard from within this window counts in VmcSnapshot::senders.
  static constexpr std::chrono::seconds kSenderWindow{10};
  // At most this many senders are remembered (a flood of forged addresses counts no further).
  static constexpr std::size_t kMostSenders = 4096;

  VmcReceiver(asio::io_context& io, ModelService& models, std::string address, int port,
              std::string stream);

  int open();
  void start();
  void close();

  const std::string& stream_name() const { return stream_name_; }
  const std::string& address() const { return address_; }
  // The held model the stream poses (its name is the stream's), or null.
  ModelHandle model() const;
  void subscribe(Subscriber subscriber) { subscribers_.push_back(std::move(subscriber)); }
  VmcSnapshot snapshot();

 private:
  void receive_next();
  void take_packet(std::size_t size);
  // When the datagram just read reached the host, on the steady clock (now, if not known).
  std::chrono::steady_clock::time_point arrival_of_last_datagram();
  void publish_frame(std::chrono::steady_clock::time_point arrived);
  const std::array<int, deform::kHumanBodyBoneCount>& bones_of(const ModelHandle& model);

  ModelService& models_;
  std::string address_;
  int port_;
  std::string stream_name_;
  asio::ip::udp::socket socket_;
  asio::ip::udp::endpoint sender_;
  // The largest UDP payload: a datagram is read whole or not at all.
  std::vector<std::byte> buffer_ = std::vector<std::byte>(65536);
  VmcStream stream_;
  VmcCounters counters_;
  std::map<asio::ip::udp::endpoint, std::chrono::steady_clock::time_point> senders_;
  std::vector<Subscriber> subscribers_;
  std::uint32_t mapped_model_ = 0;  // the model id bones_ was mapped for; 0: none
  std::array<int, deform::kHumanBodyBoneCount> bones_{};
};

}  // namespace sweepd::server

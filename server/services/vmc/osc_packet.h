// OSC packets (OSC 1.0: a message, or a bundle of messages and bundles) read with liblo
// (Debian's liblo-dev). read_osc_packet checks the whole packet before it hands out anything:
// every message is deserialised by liblo's lo_message_deserialise (address, type tags and
// arguments bounded by the packet), and only when all are whole does it return them, in the
// packet's order; a packet that is not OSC throughout gives nullopt and no message. A packet
// is all or nothing, so a torn or fuzzed datagram never half-poses a body.
//
// The bundle's framing ("#bundle", the time tag, size-prefixed elements) is read here: liblo
// reads bundles only inside its own socket server (lo_server_dispatch_data needs a lo_server,
// which binds a UDP port of its own on every interface), and sweepd's UDP socket is Asio's, on
// the address --vmc-listen names. Time tags are not scheduled: a VMC frame is shown when it
// comes (VMC senders send "immediately").
#pragma once

#include <cstddef>
#include <lo/lo.h>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace sweepd::server {

struct OscMessage {
  std::string address;
  std::string types;  // type tags without the leading ','
  std::unique_ptr<std::remove_pointer_t<lo_message>, void (*)(lo_message)> message{nullptr,
                                                                                  lo_message_free};
  lo_arg** arguments() const { return lo_message_get_argv(message.get()); }
};

struct OscPacket {
  std::size_t bundles = 0;  // the packet itself, when a bundle, and those nested in it
  std::vector<OscMessage> messages;
};

// Bundles nested deeper than this are not read (the packet is refused).
inline constexpr int kMaxOscBundleDepth = 8;

// `bytes` is liblo's to read (lo_message_deserialise takes it mutable; it copies what it keeps).
std::optional<OscPacket> read_osc_packet(std::span<std::byte> bytes);

}  // namespace sweepd::server

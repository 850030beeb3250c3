// Descriptor passing: a frame sent on a Unix socket with a file descriptor attached to its
// bytes (SCM_RIGHTS), and the receive that takes it — how the SharedMemory reply (1.10) hands a
// client its shared region. The descriptor travels with the first bytes the sendmsg puts on
// the socket; a receive that reads them without room for ancillary data would lose it (the
// kernel closes it), so the client reads the SharedMemory frame's first bytes with
// receive_with_descriptor.
//
//   send_with_descriptor(socket, bytes, fd)   non-blocking sendmsg: the bytes the socket took
//                                             (≥ 1: the descriptor went with them), nullopt
//                                             when it takes none now (EAGAIN); std::system_error
//                                             on any other failure
//   receive_with_descriptor(socket, bytes, fd)  a blocking recvmsg of up to bytes.size():
//                                             the count read (0: the peer closed), and `fd` set
//                                             to a descriptor that came with them (close-on-exec)
//                                             or left as it was; std::system_error on failure
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace sweepd::protocol {

std::optional<std::size_t> send_with_descriptor(int socket, std::span<const std::uint8_t> bytes,
                                                int fd);
std::size_t receive_with_descriptor(int socket, std::span<std::uint8_t> bytes, int& fd);

}  // namespace sweepd::protocol

// The fuzzed entry points of sweepd's parsers, one per untrusted input, each taking raw bytes:
//   fuzz_frames          protocol::FrameReader over the bytes (split where the first byte
//                        says), every whole frame decoded as the daemon would: a Pose validated
//                        and deformed, LoadModel and EditKeyEllipse read (the edit applied to a
//                        copy of the model), PositionMapRequest checked
//   fuzz_websocket       the same frames as the bytes of a --ws-listen connection: the HTTP
//                        upgrade and RFC 6455 frames read by a server WebSocketSession
//                        (websocketpp; split where the first byte says), the binary messages'
//                        payload read and decoded as fuzz_frames decodes the stream
//   fuzz_gltf            io::load_gltf, as an upload (self-contained: no file but itself)
//   fuzz_fbx             io::load_assimp over the bytes (FBX or COLLADA; assimp may open no
//                        other file)
//   fuzz_bvh             io::parse_bvh
//   fuzz_sweepbind       io::decode_sweepbind
//   fuzz_json            the first byte picks the JSON input: rig map, pose, key-ellipse edits,
//                        joint-name map, sweepd's config file
//   fuzz_vmc             one VMC datagram (--vmc-listen): server::read_osc_packet (liblo), its
//                        messages applied to a VMC stream, the pose it gives the mannequin
//                        validated and deformed as a subscriber's frame is
//   fuzz_http            the HTTP side port's request head (server/http/http_request_head.h),
//                        read again after each piece as the side port reads it (pieces cut
//                        where the first byte says), then answered as the side port answers
//                        from memory (server/http/side_port_answers.h, a two-file viewer)
// Each returns true when the input was accepted whole, false when it was refused cleanly (a
// std::exception naming the problem: the expected outcome for bad input); anything else — a
// crash, a sanitizer report, an exception the callers would not catch — is a finding.
// fuzz/<name>_fuzzer.cpp wraps each for libFuzzer; tests/fuzz/fuzz_inputs_test.cpp replays
// fuzz/seeds/ and fuzz/regressions/ through them in every test run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace sweepd::fuzz {

// Binds the small mannequin the frames and JSON entry points read against (seconds under
// ASan): libFuzzer calls it from LLVMFuzzerInitialize so that no input's time includes it.
void prepare();

// How fuzz_frames and fuzz_websocket cut an input of `input_bytes` (past its first byte) into
// reads: first_byte + 1 bytes at a time (1 to 256), but in at most kMostReads reads. Every read
// costs a WebSocket session about 0.4 us in a Release build and 15 us under ASan with coverage
// (websocketpp's iostream transport, per call), linear in the reads: 130 KB fed a byte at a time
// took 1.5-2.5 s, past libFuzzer's timeout on a loaded machine. Splits of one byte are still
// tried on every input up to 4 KiB, and frame boundaries in every piece size on longer ones.
inline constexpr std::size_t kMostReads = 4096;
std::size_t read_bytes(std::uint8_t first_byte, std::size_t input_bytes);

bool fuzz_frames(std::span<const std::uint8_t> bytes);
bool fuzz_websocket(std::span<const std::uint8_t> bytes);
bool fuzz_gltf(std::span<const std::uint8_t> bytes);
bool fuzz_fbx(std::span<const std::uint8_t> bytes);
bool fuzz_bvh(std::span<const std::uint8_t> bytes);
bool fuzz_sweepbind(std::span<const std::uint8_t> bytes);
bool fuzz_json(std::span<const std::uint8_t> bytes);
bool fuzz_vmc(std::span<const std::uint8_t> bytes);
bool fuzz_http(std::span<const std::uint8_t> bytes);

}  // namespace sweepd::fuzz

// .sweepbind files: a BoundModel on disk, so a server restarts without rebinding.
// The layout is specified in io/sweepbind/SWEEPBIND.md (versioned, CRC-checked, little-endian).
//
// save_sweepbind writes through io::write_file_durably (io/files/durable_file.h: FILE.tmp, fsync,
// rename, directory fsync), so a crash leaves either the old file or the new one.
// load_sweepbind refuses, with io::LoadError naming the file and the reason: a wrong magic, a
// newer version, truncation, a checksum mismatch, counts or indices out of range, non-finite
// values, and — when expected_model is given — a binding made for another model. A file read
// back equals what was written, bit for bit.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"
#include "io/files/load_error.h"

namespace sweepd::io {

inline constexpr std::uint32_t kSweepbindVersion = 9;  // reads 6 (as the linear Q(t)), 7 and 8 too

std::vector<std::uint8_t> encode_sweepbind(const deform::BoundModel& bound);
deform::BoundModel decode_sweepbind(std::span<const std::uint8_t> bytes,
                                    const std::filesystem::path& source,
                                    const deform::Model* expected_model = nullptr);

void save_sweepbind(const deform::BoundModel& bound, const std::filesystem::path& file);
deform::BoundModel load_sweepbind(const std::filesystem::path& file,
                                  const deform::Model* expected_model = nullptr);

// What a file's header records of its payload (io/sweepbind/SWEEPBIND.md): its CRC-32 and size, which
// name one binding. The server keys what it derives from a stored binding by them
// (server/models/self_check_sidecar.h). `bytes`: an encoded .sweepbind (encode_sweepbind's, or
// one decode_sweepbind accepted); shorter than a header throws std::invalid_argument.
struct SweepbindChecksum {
  std::uint32_t crc32 = 0;
  std::uint64_t payload_size = 0;
  bool operator==(const SweepbindChecksum&) const = default;
};
SweepbindChecksum sweepbind_checksum(std::span<const std::uint8_t> bytes);

// CRC-32 of a model's positions and triangle indices: which mesh a binding belongs to.
std::uint32_t model_fingerprint(const deform::Model& model);

}  // namespace sweepd::io

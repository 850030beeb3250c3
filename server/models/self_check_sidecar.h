// <cid>.selfcheck.json: a stored model's self-check verdicts (self_check.h), kept beside its
// .sweepbind so that a restore, an adoption or a reload reads them instead of checking the
// binding again (48 range-of-motion poses deformed three ways: 0.1–0.4 s a model).
//
// Why beside the binding and not in it (a .sweepbind version 10): the verdicts are derived, by
// the self-check of this build, from the binding; the binding is the user's file (`sweepctl
// bind -o`, read by `pose` and any server) and io/ does not know the self-check (it stands on
// metrics/). Derived data that a key names can be dropped or recomputed without touching what
// it derives from. The key: the binding's own checksum (its header's payload CRC-32 and size,
// io::sweepbind_checksum) and the self-check's revision (selfcheck::kSelfCheckRevision). A
// sidecar whose key does not match — the binding was edited (here or by another replica), the
// self-check changed, the file is absent, unreadable or torn — is not read: the binding is
// checked again. Written through io::write_file_durably after the binding, so a crash between
// the two leaves at worst a sidecar of the previous binding, which its key refuses.
//
// {"version":1, "self_check_revision":R, "binding":{"crc32":C,"payload_size":N}, "poses":P,
//  "warnings":[{"region","worse_poses","pose_count","sweep","baseline","baseline_name","pose",
//               "extra_flipped","flipped_pose","text"}, ...]}
// Doubles are written as the shortest text that reads back to the same value: a restored
// model's warnings equal the checked ones field for field.
#pragma once

#include <filesystem>
#include <optional>

#include "io/sweepbind/sweepbind.h"
#include "server/models/self_check.h"

namespace sweepd::server {

inline constexpr const char* kSelfCheckSuffix = ".selfcheck.json";

// Throws what io::write_file_durably throws.
void save_self_check(const std::filesystem::path& file, const SelfCheck& checked,
                     const io::SweepbindChecksum& binding);
// The verdicts stored for this binding; nullopt when there are none for it (see above).
std::optional<SelfCheck> load_self_check(const std::filesystem::path& file,
                                         const io::SweepbindChecksum& binding);

}  // namespace sweepd::server

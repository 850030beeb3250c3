// assimp_import_crash: whether libassimp's importer survives these bytes at all, tried in a
// forked child process first, so that a crash inside the importer kills the child and not the
// caller. Debian 12's assimp 5.2.5 frees memory twice on some malformed FBX files and fails an
// ai_assert (abort) on others (found by fuzz/fbx: fuzz/regressions/fbx/assimp_double_free.fbx
// and assimp_assert_out_idx.fbx, each of which kills any process that imports it); sweepd reads
// uploads from strangers, so every import (io/assimp/assimp_scene.h, under io::load_assimp and
// io::load_assimp_clip) tries the bytes here before reading them in its own process — the daemon's
// uploads, sweepctl's files and the fuzzers alike.
//
// Input:  bytes    the file's content (only these are read, as io::load_assimp reads them)
//         seconds  how long the child may take; past it the child is killed
// Output: "" when the child returned (the import may still have failed cleanly: the real read
//         says why), else the reason in words: "the importer crashed on this file (signal 6)"
//         (or "(exit status N)" where a sanitizer's handler ended the child),
//         "the importer took more than N s on this file", or that no child could be started.
// The child runs the import with animations read (a superset of a model's read), then exits
// without running the parent's exit handlers.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace sweepd::io {

std::string assimp_import_crash(std::span<const std::uint8_t> bytes, int seconds = 60);

}  // namespace sweepd::io

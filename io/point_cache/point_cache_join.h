// join_point_caches: several point caches of one model's consecutive frame ranges (the shards
// of a render farm, `render_frames --format pc2|mdd --shard I/N`) joined into one cache.
//
// Input:  inputs  PC2 or MDD files (io/point_cache/point_cache_header.h), all of the output's format, in
//                 any order: they are put in order of their first frame
//         output  FILE.pc2 or FILE.mdd
// Checks: every input reads as a complete cache; one point count; PC2: one sampling and each
//         input's start frame right after the previous one's last (start + count x sampling);
//         MDD (its frames carry times, not numbers): one frame interval, the interval of the
//         first input with two frames or more, and each input's first time one interval after
//         the previous one's last (to 0.1 % of the interval).
// Output: the joined cache: the first input's start frame (PC2), every input's frame times
//         (MDD), the frames' bytes as they are (axes and byte order unchanged), written as
//         PointCacheWriter writes (FILE.partial, then renamed). Memory: one frame.
// Returns what was joined. Throws std::invalid_argument naming the files and the problem (no
// inputs, formats that differ, point counts that differ, a gap or an overlap between two
// inputs with their frames, MDD inputs of one frame each whose interval cannot be told, the
// output among the inputs); io::LoadError for an input that is not a complete cache;
// std::runtime_error when the output cannot be written.
#pragma once

#include <filesystem>
#include <vector>

#include "io/point_cache/point_cache_header.h"

namespace sweepd::io {

struct JoinedPointCache {
  PointCacheHeader header;  // the output's
  int inputs = 0;
};

JoinedPointCache join_point_caches(const std::vector<std::filesystem::path>& inputs,
                                   const std::filesystem::path& output);

}  // namespace sweepd::io

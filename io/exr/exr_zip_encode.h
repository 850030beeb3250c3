// encode_zip_exr: the ZIP-compressed scan-line EXR of io::encode_exr (io/exr/exr_write.h), written
// here instead of by OpenEXR's OutputFile so that its deflate is libdeflate's: the same blocks,
// prepared the same way, in 0.52–0.63× the time of the zlib that OpenEXR 3.1 calls (docs/performance.md,
// "Position maps: where a frame's time goes"; OpenEXR 3.2 and later use libdeflate themselves).
//
// Input: layers and options that validate_exr accepts, ExrCompression::kZip.
// Output: into `bytes` (resized, capacity reused) a single-part scan-line OpenEXR 2 file as
// OpenEXR writes it: the header attributes encode_exr sets (channels A, N.X-N.Z, P.X-P.Z, sorted,
// FLOAT — N HALF with half_normals —, compression ZIP, data and display window (0,0)-(W-1,H-1),
// increasing y, pixel aspect 1, screen window (0,0) and 1, then model, frame, poseHash, space,
// units), the offset table, then one chunk per 16 lines: each line's channels one after the
// other, bytes split into halves and predicted as OpenEXR's ZIP does, zlib-wrapped deflate at
// options.zip_level (stored as they are where that is not smaller, as the format allows).
// Blocks are compressed on OpenEXR's global thread pool (io::set_exr_threads), one compressor
// per thread kept between frames.
#pragma once

#include <cstdint>
#include <vector>

#include "io/exr/exr_write.h"

namespace sweepd::io {

void encode_zip_exr(const ExrLayers& layers, const ExrOptions& options,
                    std::vector<std::uint8_t>& bytes);

}  // namespace sweepd::io

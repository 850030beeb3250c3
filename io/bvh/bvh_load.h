// BVH reading: a Biovision Hierarchy motion clip (text) into a motion::Clip.
//
// Inputs:  a .bvh file (or its text), LF or CRLF line endings, spaces or tabs.
// Output:  motion::Clip with joints in file order, offsets and position channels multiplied by
//          options.length_scale, rotations kept in degrees, and every data row present; Y-up:
//          a Z-up clip (options.up, else motion::detect_up_axis) is turned by
//          motion::turn_z_up_to_y_up.
// A malformed file throws io::LoadError naming the file, the line and the reason. Problems that
// leave the data usable (a "Frames:" count that disagrees with the rows present, duplicate joint
// names) become motion::Clip::warnings instead.
#pragma once

#include <filesystem>
#include <optional>
#include <string_view>

#include "motion/clip.h"
#include "motion/clip_up_axis.h"

namespace sweepd::io {

struct BvhOptions {
  // Multiplies offsets, End Site offsets and position channels; must be finite and > 0.
  // 0.056444 turns CMU BVH units into metres.
  float length_scale = 1.0f;
  // The file's up axis; nothing: detected from its skeleton (motion/clip_up_axis.h).
  std::optional<motion::UpAxis> up = std::nullopt;
};

motion::Clip load_bvh(const std::filesystem::path& file, const BvhOptions& options = {});

// The same from text already in memory; source only names the text in error messages.
motion::Clip parse_bvh(std::string_view text, const std::filesystem::path& source,
                       const BvhOptions& options = {});

}  // namespace sweepd::io

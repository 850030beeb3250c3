// choose_animation: which of a file's animations a user's `--clip NAME|INDEX` means, for every
// reader of animations in files (io/gltf/gltf_clip_load.h, io/assimp/assimp_clip_load.h): the first
// animation with that exact name, else, when the text is a decimal index (at most 9 digits),
// the animation at that index.
// Input:  names  the file's animations in file order ("" for one without a name)
//         clip   the user's text
//         file   names the file in messages
// Output: the index. Throws LoadError naming the file: no animations at all, or no animation of
//         that name or index (listing the file's animations as `0 'walk', 1 'run'`).
//
// every_animation(names, read): all of a file's animations from one parse, for listing them
// (sweepctl inspect): read(index) makes animation `index`'s clip from the parsed file; one that
// cannot play keeps the LoadError's message instead of a clip.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "io/files/load_error.h"
#include "motion/clip.h"

namespace sweepd::io {

int choose_animation(std::span<const std::string> names, const std::string& clip,
                     const std::filesystem::path& file);

struct FileAnimation {
  std::string name;                  // "" for one without a name
  std::optional<motion::Clip> clip;  // empty when it cannot play
  std::string error;                 // why not (the LoadError's message)
};

std::vector<FileAnimation> every_animation(std::span<const std::string> names,
                                           const std::function<motion::Clip(int index)>& read);

}  // namespace sweepd::io

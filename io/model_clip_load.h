// load_model_clip / load_model_animations: an animation of any model file sweepctl takes —
// glTF 2.0 (io/gltf/gltf_clip_load.h), FBX or COLLADA (io/assimp/assimp_clip_load.h) — with the reader chosen
// from the file's first bytes, as io::load_model chooses the model reader, so the clip's joints
// are those of the model load_model reads from the same file.
//
// Input:  file   the model file (a glTF may use files in its own directory, as load_model's);
//                or its bytes (a client's upload) with a label naming them in messages: then
//                self-contained, a glTF's GLB chunk and data: URIs only, as for model uploads
//         clip   the animation's name, or its index ("0", "1", ...) (io/animation_choice.h)
// Output: the clip; load_model_animations: every animation from one parse of the file, each with
//         its name (file order, "" for one without) and its clip or why it cannot play.
// Throws io::LoadError naming the file and the problem.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "io/animation_choice.h"
#include "io/files/load_error.h"
#include "motion/clip.h"

namespace sweepd::io {

motion::Clip load_model_clip(const std::filesystem::path& file, const std::string& clip);
motion::Clip load_model_clip(std::span<const std::uint8_t> bytes,
                             const std::filesystem::path& label, const std::string& clip);
std::vector<FileAnimation> load_model_animations(const std::filesystem::path& file);

}  // namespace sweepd::io

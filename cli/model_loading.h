// Loading what sweepctl's model commands share: a rigged model (glTF, FBX or COLLADA:
// io/model_load.h) and its rig map (from a JSON override file, or detected from the joint names).
#pragma once

#include <filesystem>

#include "deform/model/model.h"
#include "deform/rig/rig_map.h"

namespace sweepd::cli {

struct LoadedModel {
  deform::Model model;
  deform::RigMap rig;
};

// rig_file empty: detect, printing the map's warnings (parts not found, left to skinning) to
// stderr. Throws io::LoadError / std::invalid_argument with the reason.
LoadedModel load_model_and_rig(const std::filesystem::path& model_file,
                               const std::filesystem::path& rig_file);

}  // namespace sweepd::cli

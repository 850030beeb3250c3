// load_model: reads a skinned human from any model file sweepctl takes — glTF 2.0 (.glb, .gltf),
// FBX (binary or ASCII) or COLLADA (.dae) — choosing the reader from the file's first bytes, not
// its name: io/assimp/assimp_load.h for FBX and COLLADA, io/gltf/gltf_load.h (its own directory's files only)
// for everything else.
//
// Input:  file    the model file
//         report  optional; what the reader lost or changed (io/load_report.h)
// Output: a deform::Model that satisfies Model::validate(). Throws io::LoadError with the reason.
#pragma once

#include <filesystem>

#include "deform/model/model.h"
#include "io/files/load_error.h"
#include "io/load_report.h"

namespace sweepd::io {

deform::Model load_model(const std::filesystem::path& file, LoadReport* report = nullptr);

// Whether load_model reads `file` through libassimp (FBX or COLLADA by its first KiB) rather than
// as glTF. LoadError when the file cannot be opened.
bool is_assimp_file(const std::filesystem::path& file);

}  // namespace sweepd::io

// convert_with_assimp: a glTF file rewritten as ASCII FBX or COLLADA by libassimp's exporters —
// how sweepd's tests and fuzz seeds make such files from the shared and the procedural glTF
// models (sweepd itself writes neither). FBX is ASCII because Debian's assimp 5.2.5 writes binary
// FBX that its own importer refuses ("FBX-Tokenize ... block offset is out of range").
//
// Input:  gltf    a .glb/.gltf file
//         target  kFbxMetres: FBX declaring metres (UnitScaleFactor 100), as the glTF's numbers
//                 are; kFbxCentimetres: assimp's own UnitScaleFactor 1, whatever the numbers;
//                 kCollada: COLLADA 1.4.1
//         edit    optional: changes the scene assimp read before it is written (a test scales it
//                 to centimetres, or removes the bones)
// Output: the file's bytes. Throws std::runtime_error with assimp's reason.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

struct aiScene;

namespace sweepd::io {

enum class AssimpExport { kFbxMetres, kFbxCentimetres, kCollada };

std::vector<std::uint8_t> convert_with_assimp(const std::filesystem::path& gltf,
                                              AssimpExport target,
                                              const std::function<void(aiScene&)>& edit = {});

}  // namespace sweepd::io

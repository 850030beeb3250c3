// load_assimp: reads a skinned human from an FBX (binary or ASCII) or COLLADA (.dae) file through
// Debian's libassimp into the same deform::Model as io::load_gltf: world-space rest pose, metres,
// skin with at most 4 influences per vertex, skeleton parents-first with rest local transforms.
//
// Input:  file    path to a .fbx or .dae (for messages and the model's name; also the bytes'
//                 source in the first overload)
//         bytes   the file's content (an upload): assimp reads these and no other file — every
//                 other path it asks for (textures, .mtl) is refused, also in the path overload,
//                 which reads the file's bytes itself first
//         report  optional; receives what the importer lost or changed (io/load_report.h)
// Output: a Model that satisfies Model::validate():
//         - every mesh of the character (io/assimp/assimp_scene.h find_character): the skinned node
//           with the most vertices, every other node skinned to the same skeleton, and every
//           node with meshes but no bones under one of its joints (rigid: weight 1 on that
//           joint); other mesh nodes are ignored, each named in a warning and in report.meshes
//           with the reason. One assimp mesh (assimp splits a node's mesh per material) loads as
//           before, with no parts; several give a deform::MeshPart each: the node's name, the
//           material's name, which loaded node it is (MeshPart::mesh) and its rigid joint;
//         - joints: the nodes the bones name plus the nodes between them and their root bone,
//           parents-first; FBX transform parts that assimp keeps as "<joint>_$AssimpFbx$_<part>"
//           helper nodes (PreRotation, RotationPivot, ...) are collapsed into their joint's rest
//           transform and reported per part; nodes above the root are folded into it;
//         - positions/normals are the file's vertices skinned with world_rest * offset (assimp's
//           inverse bind), so the skeleton's world rest matrices are the bind matrices;
//         - units: FBX declares UnitScaleFactor (centimetres per file unit); positions and joint
//           translations are scaled by UnitScaleFactor / 100 to metres, reported when not 1; an
//           FBX up axis other than +Y is reported, not converted;
//         - polygons with more than 3 corners are triangulated (assimp's Triangulate), points and
//           lines dropped, both reported; identical vertices are joined (FBX stores one per
//           corner);
//         - more than 4 influences: the 4 largest kept, renormalised; the count and the largest
//           weight dropped are reported.
// Throws io::LoadError naming the file and the problem: not an FBX/COLLADA file, a corrupt file
// (assimp's reason), no mesh, no skin (meshes but no bones), no triangles, a bone naming no node,
// a degenerate or non-finite rest transform, an invalid result.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

#include "deform/model/model.h"
#include "io/files/load_error.h"
#include "io/load_report.h"

namespace sweepd::io {

deform::Model load_assimp(const std::filesystem::path& file, LoadReport* report = nullptr);
deform::Model load_assimp(std::span<const std::uint8_t> bytes, const std::filesystem::path& file,
                          LoadReport* report = nullptr);

// What the bytes start like, as a file suffix: ".fbx" for binary FBX ("Kaydara FBX Binary") or
// ASCII FBX ("; FBX" comment header), ".dae" for COLLADA XML (a <COLLADA element in the first
// 1 KiB); "" for anything load_assimp does not read.
std::string_view assimp_model_suffix(std::span<const std::uint8_t> bytes);

}  // namespace sweepd::io

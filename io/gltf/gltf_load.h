// load_gltf: reads a skinned human from a glTF 2.0 file (.glb, or .gltf with external .bin or
// embedded base64 data URIs) into a deform::Model in world-space rest pose.
//
// Input:  file    path to a .glb or .gltf (the format is sniffed from the bytes, not the name)
//         uris    which files its external buffer/image URIs may name (io/gltf/gltf_uri_policy.h);
//                 without it: files inside the glTF's own directory only (relative paths that
//                 stay there after `..` and symlinks; no absolute path, no file:, and unlike
//                 tinygltf alone, no second look in the working directory). sweepd gives
//                 uploads GltfUriPolicy::self_contained() and --model-dir files
//                 GltfUriPolicy::within(model dir).
//         report  optional; receives warnings and source counts (see io/load_report.h)
// Output: a Model that satisfies Model::validate():
//         - the character's skin is the skin of the node with both mesh and skin (the one with
//           most vertices when several); every mesh node is then, in file order, skinned (it
//           uses that skin), rigid (no skin, and a joint of the skin among its ancestors: its
//           vertices are placed by the node's world matrix and get weight 1 on the nearest such
//           joint), or ignored (another skin; no skin and no joint above it; no triangles),
//           which report.meshes lists and a warning names. Each loaded triangle primitive is
//           one Model::parts entry (name, material name, vertex and index range), appended to
//           one vertex/index list;
//         - skin.joints become the Skeleton, reordered parents-first (JOINTS_0 remapped);
//           unnamed joints are called joint_<node index>, repeated names get _2, _3, ...;
//           non-joint ancestors of root joints are folded into the root's rest transform;
//         - positions/normals are the file's vertices skinned with world_rest * inverseBind,
//           so the skeleton's world rest matrices are the bind matrices;
//         - influences from every JOINTS_n/WEIGHTS_n set are merged per joint and the 4 largest
//           kept; weights are renormalised to sum 1 (both counted in the report); vertices
//           with no weight are bound to the mesh node's nearest ancestor joint, else joint 0.
//         A file with one skinned mesh of one primitive loads as before, with one part.
// Throws io::LoadError (naming the file and the reason) for any unusable input: unreadable or
// truncated file, a URI the policy refuses (checked before any file is opened; the message
// names the URI and nothing about the file it would have named), invalid JSON, missing buffers, no
// skinned mesh, non-triangle primitives, out-of-range indices or joint indices, non-finite
// attributes, malformed accessors.
#pragma once

#include <filesystem>

#include "deform/model/model.h"
#include "io/files/load_error.h"
#include "io/gltf/gltf_uri_policy.h"
#include "io/load_report.h"

namespace sweepd::io {

deform::Model load_gltf(const std::filesystem::path& file, LoadReport* report = nullptr);
deform::Model load_gltf(const std::filesystem::path& file, const GltfUriPolicy& uris,
                        LoadReport* report = nullptr);

}  // namespace sweepd::io

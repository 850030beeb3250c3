// LoadReport: what a model loader noticed while reading a file that was usable but not clean
// (renormalised skin weights, computed normals, ignored data), plus a few source counts that
// `sweepctl inspect` shows. Loaders fill it when the caller passes one; it never holds errors
// (those are thrown as io::LoadError).
#pragma once

#include <string>
#include <vector>

namespace sweepd::io {

// One mesh node of the file and what the loader did with it.
struct MeshHandling {
  std::string name;          // as MeshPart::name
  std::size_t vertex_count;  // its triangle primitives' vertices (the file's, before any skip)
  int part = -1;             // its first part in Model::parts; -1 when it was not loaded
  std::string ignored;       // why it was not loaded; empty when it was
};

struct LoadReport {
  std::vector<std::string> warnings;  // one line each, in the order they were noticed
  int renormalised_weight_count = 0;  // vertices whose weights did not sum to 1
  int zero_weight_vertex_count = 0;   // vertices with no weight, bound rigidly to one joint
  int trimmed_influence_count = 0;    // vertices with more than 4 influences (JOINTS_1...)
  int computed_normal_count = 0;      // vertices whose normals the file lacked
  int source_joint_count = 0;         // joints of the chosen skin
  int source_primitive_count = 0;     // triangle primitives merged into the model
  int skinned_mesh_count = 0;         // nodes with both a mesh and a skin in the file
  std::vector<MeshHandling> meshes;   // every mesh node, in file order (glTF; empty otherwise)
  std::string format;                 // "glTF", "FBX" or "COLLADA"
  std::string generator;              // the file's generator (asset.generator), empty when absent
};

}  // namespace sweepd::io

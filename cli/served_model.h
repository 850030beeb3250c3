// served_model: a served model rebuilt on the client — its rest skeleton from ModelInfo and
// its rest mesh from one MeshRequest → Mesh exchange (protocol 1.1) — so a client can write
// posed vertices as a .glb, measure them, or rasterise them without the model's file.
//
//   deform::Model model = served_model(connection, info);
//
// Input: a connection after Hello and the model's ModelInfo (read before the call: the
// exchange receives a new frame, after which `info` is no longer valid).
// Output: a deform::Model named as the server names it, with the server's vertex order,
// triangles, UVs (when the model has them), skin, skeleton and meshes (1.6); normals are the rest
// normals computed from the mesh. Throws ServerError (e.g. UnknownModel) or std::runtime_error when
// the Mesh does not match the ModelInfo, naming the array and its size.
#pragma once

#include "client/connection.h"
#include "deform/model/model.h"

namespace sweepd::cli {

deform::Model served_model(client::Connection& connection, const protocol::ModelInfo& info);

}  // namespace sweepd::cli

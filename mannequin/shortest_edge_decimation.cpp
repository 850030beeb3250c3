#include "mannequin/shortest_edge_decimation.h"

#include <queue>

#include "deform/mesh/mesh_topology.h"

namespace sweepd::mannequin {

using deform::to_tri_mesh;
using deform::TriMesh;

namespace {

glm::vec3 to_glm(const TriMesh::Point& p) { return {p[0], p[1], p[2]}; }

// The mesh's points read through one pointer: OpenMesh's mesh.point(v) checks the property's
// type name in a Debug build (a std::string made and compared per call), which made the
// decimation most of a small mannequin's build under the sanitizers. Collapses move no point
// but the survivor, which set_point writes through the same array.
struct Points {
  const TriMesh::Point* data;
  glm::vec3 operator()(TriMesh::VertexHandle v) const { return to_glm(data[v.idx()]); }
};

float squared_length(const TriMesh& mesh, const Points& point, TriMesh::EdgeHandle e) {
  const TriMesh::HalfedgeHandle h = mesh.halfedge_handle(e, 0);
  const glm::vec3 d = point(mesh.to_vertex_handle(h)) - point(mesh.from_vertex_handle(h));
  return glm::dot(d, d);
}

// True when moving the vertices `from` and `to` of a collapse to `target` keeps every
// remaining triangle around them facing (roughly) the way it did.
bool keeps_orientation(const TriMesh& mesh, const Points& point, TriMesh::HalfedgeHandle h,
                       const glm::vec3& target) {
  const TriMesh::VertexHandle from = mesh.from_vertex_handle(h), to = mesh.to_vertex_handle(h);
  for (TriMesh::VertexHandle moved : {from, to}) {
    for (TriMesh::ConstVertexFaceIter f = mesh.cvf_iter(moved); f.is_valid(); ++f) {
      glm::vec3 corner[3];
      bool touches_both = false;
      int k = 0;
      for (TriMesh::ConstFaceVertexIter v = mesh.cfv_iter(*f); v.is_valid(); ++v, ++k) {
        corner[k] = point(*v);
        if (*v == (moved == from ? to : from)) touches_both = true;
      }
      if (touches_both) continue;  // the two triangles on the edge disappear
      const glm::vec3 before = glm::cross(corner[1] - corner[0], corner[2] - corner[0]);
      k = 0;
      for (TriMesh::ConstFaceVertexIter v = mesh.cfv_iter(*f); v.is_valid(); ++v, ++k)
        if (*v == moved) corner[k] = target;
      const glm::vec3 after = glm::cross(corner[1] - corner[0], corner[2] - corner[0]);
      const float lengths = glm::length(before) * glm::length(after);
      if (!(lengths > 0.0f) || glm::dot(before, after) < 0.2f * lengths) return false;
    }
  }
  return true;
}

}  // namespace

void decimate_shortest_edges(std::vector<glm::vec3>& positions, std::vector<std::uint32_t>& indices,
                             std::size_t target_vertices,
                             const std::function<glm::vec3(const glm::vec3&)>& place) {
  if (positions.size() <= target_vertices) return;
  TriMesh mesh = to_tri_mesh(positions, indices);
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  mesh.request_halfedge_status();

  const Points point{mesh.points()};

  using Entry = std::pair<float, int>;  // (squared length, edge index), smallest first
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (TriMesh::EdgeHandle e : mesh.edges()) queue.emplace(squared_length(mesh, point, e), e.idx());

  std::size_t vertices = mesh.n_vertices();
  while (vertices > target_vertices && !queue.empty()) {
    const auto [length2, index] = queue.top();
    queue.pop();
    const TriMesh::EdgeHandle e(index);
    if (mesh.status(e).deleted() || squared_length(mesh, point, e) != length2) continue;  // stale
    TriMesh::HalfedgeHandle h = mesh.halfedge_handle(e, 0);
    const glm::vec3 midpoint =
        0.5f * (point(mesh.from_vertex_handle(h)) + point(mesh.to_vertex_handle(h)));
    const glm::vec3 target = place(midpoint);
    if (!mesh.is_collapse_ok(h)) {
      h = mesh.opposite_halfedge_handle(h);
      if (!mesh.is_collapse_ok(h)) continue;
    }
    if (!keeps_orientation(mesh, point, h, target)) continue;
    const TriMesh::VertexHandle survivor = mesh.to_vertex_handle(h);
    mesh.collapse(h);
    mesh.set_point(survivor, TriMesh::Point(target.x, target.y, target.z));
    --vertices;
    for (TriMesh::VertexEdgeIter around = mesh.ve_iter(survivor); around.is_valid(); ++around)
      queue.emplace(squared_length(mesh, point, *around), around->idx());
  }
  mesh.garbage_collection();

  positions.resize(mesh.n_vertices());
  for (TriMesh::VertexHandle v : mesh.vertices()) positions[v.idx()] = to_glm(mesh.point(v));
  indices.clear();
  indices.reserve(mesh.n_faces() * 3);
  for (TriMesh::FaceHandle f : mesh.faces())
    for (TriMesh::FaceVertexIter v = mesh.fv_iter(f); v.is_valid(); ++v)
      indices.push_back(static_cast<std::uint32_t>(v->idx()));
}

}  // namespace sweepd::mannequin

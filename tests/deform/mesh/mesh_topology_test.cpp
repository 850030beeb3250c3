// Tests of analyze_topology / to_tri_mesh on small meshes whose topology is known by hand.
#include "deform/mesh/mesh_topology.h"

#include <gtest/gtest.h>

#include <vector>

namespace sweepd::deform {
namespace {

struct Soup {
  std::vector<glm::vec3> positions;
  std::vector<std::uint32_t> indices;
};

// Unit cube as glTF would store it: 4 own vertices per face (24 positions, 8 distinct), 12
// outward-facing triangles.
Soup cube_with_face_duplicates(glm::vec3 offset = glm::vec3(0.0f)) {
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  Soup soup;
  for (const auto& face : faces) {
    const auto base = static_cast<std::uint32_t>(soup.positions.size());
    for (int corner : face)
      soup.positions.push_back(offset +
                               glm::vec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1));
    for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) soup.indices.push_back(base + k);
  }
  return soup;
}

Soup tetrahedron(glm::vec3 offset) {
  Soup soup;
  soup.positions = {offset, offset + glm::vec3(1, 0, 0), offset + glm::vec3(0, 1, 0),
                    offset + glm::vec3(0, 0, 1)};
  soup.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  return soup;
}

void append(Soup& to, const Soup& from) {
  const auto base = static_cast<std::uint32_t>(to.positions.size());
  to.positions.insert(to.positions.end(), from.positions.begin(), from.positions.end());
  for (std::uint32_t i : from.indices) to.indices.push_back(base + i);
}

TEST(MeshTopology, CubeWithSeamDuplicatesWeldsToClosedSphere) {
  const Soup cube = cube_with_face_duplicates();
  const MeshTopology topology = analyze_topology(cube.positions, cube.indices);
  EXPECT_EQ(topology.welded_vertices, 8u);
  EXPECT_EQ(topology.edges, 18u);
  EXPECT_EQ(topology.triangles, 12u);
  EXPECT_EQ(topology.boundary_edges, 0u);
  EXPECT_EQ(topology.components, 1u);
  EXPECT_EQ(topology.euler_characteristic, 2);  // a sphere
  EXPECT_TRUE(topology.closed_manifold());

  const TriMesh mesh = to_tri_mesh(cube.positions, cube.indices);
  EXPECT_EQ(mesh.n_vertices(), 8u);
  EXPECT_EQ(mesh.n_faces(), 12u);
  for (auto vh : mesh.vertices()) EXPECT_FALSE(mesh.is_boundary(vh));
}

TEST(MeshTopology, FlippedTriangleIsReportedAsInconsistent) {
  Soup cube = cube_with_face_duplicates();
  std::swap(cube.indices[1], cube.indices[2]);
  const MeshTopology topology = analyze_topology(cube.positions, cube.indices);
  EXPECT_EQ(topology.boundary_edges, 0u);
  EXPECT_EQ(topology.inconsistent_edges, 3u);  // all three edges of the flipped triangle
  EXPECT_FALSE(topology.closed_manifold());
}

TEST(MeshTopology, OpenSquareHasFourBoundaryEdges) {
  const std::vector<glm::vec3> positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<std::uint32_t> indices = {0, 1, 2, 0, 2, 3};
  const MeshTopology topology = analyze_topology(positions, indices);
  EXPECT_EQ(topology.boundary_edges, 4u);
  EXPECT_EQ(topology.non_manifold_edges, 0u);
  EXPECT_EQ(topology.non_manifold_vertices, 0u);
  EXPECT_EQ(topology.euler_characteristic, 1);  // a disc
  EXPECT_FALSE(topology.closed_manifold());
}

TEST(MeshTopology, BowTieVertexIsNonManifold) {
  // Two triangles touching only at the origin.
  const std::vector<glm::vec3> positions = {
      {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  const std::vector<std::uint32_t> indices = {0, 1, 2, 0, 3, 4};
  const MeshTopology topology = analyze_topology(positions, indices);
  EXPECT_EQ(topology.non_manifold_vertices, 1u);
  EXPECT_EQ(topology.non_manifold_edges, 0u);
  EXPECT_EQ(topology.boundary_edges, 6u);
  EXPECT_EQ(topology.components, 1u);
  EXPECT_FALSE(topology.closed_manifold());
}

TEST(MeshTopology, EdgeSharedByThreeTrianglesIsNonManifold) {
  // A "book" of three pages on the edge (0,0,0)-(0,0,1).
  const std::vector<glm::vec3> positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
  const std::vector<std::uint32_t> indices = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  const MeshTopology topology = analyze_topology(positions, indices);
  EXPECT_EQ(topology.non_manifold_edges, 1u);
  EXPECT_EQ(topology.boundary_edges, 6u);
  // OpenMesh cannot hold the third page: it is counted, not silently lost.
  EXPECT_EQ(topology.faces_rejected_by_openmesh, 1u);
  EXPECT_FALSE(topology.closed_manifold());
}

TEST(MeshTopology, TwoDisjointTetrahedraAreTwoClosedComponents) {
  Soup soup = tetrahedron(glm::vec3(0.0f));
  append(soup, tetrahedron(glm::vec3(5.0f, 0.0f, 0.0f)));
  const MeshTopology topology = analyze_topology(soup.positions, soup.indices);
  EXPECT_EQ(topology.welded_vertices, 8u);
  EXPECT_EQ(topology.components, 2u);
  EXPECT_EQ(topology.euler_characteristic, 4);  // two spheres
  EXPECT_TRUE(topology.closed_manifold());
}

TEST(MeshTopology, DegenerateTriangleIsCountedAndLeftOut) {
  Soup soup = tetrahedron(glm::vec3(0.0f));
  soup.positions.push_back(soup.positions[0]);  // a duplicate that welds onto vertex 0
  soup.indices.insert(soup.indices.end(), {0, 4, 1});
  const MeshTopology topology = analyze_topology(soup.positions, soup.indices);
  EXPECT_EQ(topology.degenerate_triangles, 1u);
  EXPECT_EQ(topology.triangles, 4u);
  EXPECT_FALSE(topology.closed_manifold());
}

}  // namespace
}  // namespace sweepd::deform

// Topology of face lists: edges, components, boundary loops (mesh/topology.hpp).
#include <catch2/catch.hpp>

#include "spinmotor/mesh/topology.hpp"

namespace test_topology {

using namespace spinmotor;

TEST_CASE("tetrahedron: 6 edges of valence 2, one component, no boundary", "[topology]") {
  Eigen::MatrixXi F(4, 3);
  F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  const EdgeTopology t = edge_topology(F);
  REQUIRE(t.num_edges() == 6);
  for (Eigen::Index e = 0; e < 6; ++e) CHECK(t.valence(e) == 2);
  for (Eigen::Index f = 0; f < 4; ++f)
    for (int c = 0; c < 3; ++c) {  // FE(f,c) is the edge opposite corner c
      const int a = F(f, (c + 1) % 3), b = F(f, (c + 2) % 3);
      CHECK(t.E(t.FE(f, c), 0) == std::min(a, b));
      CHECK(t.E(t.FE(f, c), 1) == std::max(a, b));
    }
  int nc = 0;
  vertex_components(F, 4, &nc);
  CHECK(nc == 1);
  CHECK(boundary_loops(F).empty());
  CHECK(boundary_vertices(F, 4).size() == 0);
  CHECK(interior_vertices(F, 4).size() == 4);
}

TEST_CASE("two separate quads: two components, two boundary loops of 4", "[topology]") {
  Eigen::MatrixXi F(4, 3);
  F << 0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7;
  int nc = 0;
  const Eigen::VectorXi vl = vertex_components(F, 9, &nc);
  CHECK(nc == 3);  // vertex 8 is unreferenced: a component of its own
  CHECK(vl[8] == 2);
  int nf = 0;
  const Eigen::VectorXi fl = face_components(F, &nf);
  CHECK(nf == 2);
  CHECK(fl[1] == 0);
  CHECK(fl[3] == 1);
  const auto loops = boundary_loops(F);
  REQUIRE(loops.size() == 2);
  CHECK(loops[0] == std::vector<int>{0, 1, 2, 3});  // the surface lies to the left
  CHECK(loops[1].size() == 4);
  CHECK(interior_vertices(F, 9).size() == 0);
}

TEST_CASE("a non-manifold edge has valence 3", "[topology]") {
  Eigen::MatrixXi F(3, 3);
  F << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  const EdgeTopology t = edge_topology(F);
  int max_valence = 0;
  for (Eigen::Index e = 0; e < t.num_edges(); ++e) max_valence = std::max(max_valence, t.valence(e));
  CHECK(max_valence == 3);
  CHECK(t.num_edges() == 7);
}

}  // namespace test_topology

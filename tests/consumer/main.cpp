// Uses the installed headers and libraries: builds a mesh, reads its topology, checks a number.
#include <iostream>
#include <spinmotor/core/error.hpp>
#include <spinmotor/mesh/mesh.hpp>
#include <spinmotor/mesh/topology.hpp>

int main() {
  spinmotor::Mesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.F.resize(4, 3);
  m.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;  // a closed tetrahedron
  const auto t = spinmotor::edge_topology(m.F);
  const long chi = m.num_vertices() - t.num_edges() + m.num_faces();
  std::cout << "consumer: tetrahedron V-E+F = " << chi << '\n';
  return chi == 2 ? 0 : 1;
}

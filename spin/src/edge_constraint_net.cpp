#include "spinmotor/spin/edge_constraint_net.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "spinmotor/mesh/validate.hpp"

namespace spinmotor {

Eigen::Vector4d EdgeConstraintNet::hyperedge(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                             Eigen::Index f, int c) const {
  const Eigen::RowVector3d e = V.row(F(f, (c + 2) % 3)) - V.row(F(f, (c + 1) % 3));
  return {2.0 * edge_H(f, c), e.x(), e.y(), e.z()};  // eq. 12
}

EdgeConstraintNet edge_constraint_net(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  require(Mesh{V, F, {}, {}}, {.manifold = true, .oriented = true, .no_degenerate = true},
          "edge_constraint_net");
  const Eigen::Index m = F.rows();
  EdgeConstraintNet net;
  net.area = face_areas(V, F);
  net.normal = face_normals(V, F);
  const EdgeTopology topo = edge_topology(F);
  net.adjacent.setConstant(m, 3, -1);
  net.edge_length.resize(m, 3);
  net.theta.setZero(m, 3);
  net.edge_H.setZero(m, 3);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) {
      const int e = topo.FE(f, c);
      for (int k = topo.EF_offset[e]; k < topo.EF_offset[e + 1]; ++k)
        if (topo.EF_face[k] != f) net.adjacent(f, c) = topo.EF_face[k];
      const Eigen::Vector3d ev = (V.row(F(f, (c + 2) % 3)) - V.row(F(f, (c + 1) % 3))).transpose();
      const double len = ev.norm();
      net.edge_length(f, c) = len;
      const int g = net.adjacent(f, c);
      if (g < 0) continue;
      const Eigen::Vector3d ni = net.normal.row(f).transpose(), nj = net.normal.row(g).transpose();
      // Signed angle from n_i to n_j about e_ij (traversed counter-clockwise by f): positive when convex.
      const double theta = std::atan2(ni.cross(nj).dot(ev) / len, ni.dot(nj));
      if (std::abs(theta) > M_PI - 1e-12) {
        std::ostringstream s;
        s << "edge_constraint_net: faces " << f << " and " << g << " fold onto each other along edge ("
          << F(f, (c + 1) % 3) << ", " << F(f, (c + 2) % 3) << ")";
        throw Error(s.str());
      }
      net.theta(f, c) = theta;
      net.edge_H(f, c) = 0.5 * len * std::tan(0.5 * theta);  // §4.1, H_ij = ½|e| tan(θ/2)
    }
  net.H = net.edge_H.rowwise().sum();               // eq. 9
  net.h = net.H.array() / net.area.array().sqrt();  // eq. 10
  net.willmore = net.h.squaredNorm();               // eq. 11
  return net;
}

double face_willmore_energy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  return edge_constraint_net(V, F).willmore;
}

}  // namespace spinmotor

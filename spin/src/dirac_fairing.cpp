#include "spinmotor/spin/dirac_fairing.hpp"

#include <cmath>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/spin/dirac_spectrum.hpp"
#include "spinmotor/spin/edge_constraint_net.hpp"
#include "spinmotor/spin/face_dirac_operator.hpp"
#include "spinmotor/spin/quaternion_matrix.hpp"

namespace spinmotor {

DiracImmersion dirac_immersion(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int which) {
  require(Mesh{V, F, {}, {}},
          {.manifold = true,
           .oriented = true,
           .no_degenerate = true,
           .closed = true,
           .genus0 = true,
           .single_component = true,
           .no_unreferenced = true},
          "dirac_immersion");
  if (which < 0 || which > 64) {
    std::ostringstream s;
    s << "dirac_immersion: eigenfunction index " << which << " outside [0, 64]";
    throw Error(s.str());
  }
  DiracSpectrumOptions o;
  o.count = 4 * (which / 4 + 1);  // whole quaternionic multiplets
  o.eigenvectors = true;
  const DiracSpectrum sp = face_dirac_spectrum(V, F, FaceDiracKind::Intrinsic, {}, o);
  // §4.3: vertex eigenfunction → faces by the averaging matrix, then eq. 21 and least squares.
  const Eigen::VectorXd pf = face_vertex_averaging(F, V.rows()) * sp.eigenvectors.col(which);
  DiracImmersion out;
  out.eigenvalue = sp.eigenvalues[which];
  out.V = face_spin_transform(V, F, unflatten_quaternions(pf), FaceDiracKind::Intrinsic, &out.residual);
  const double a0 = face_areas(V, F).sum(), a1 = face_areas(out.V, F).sum();
  if (!(a1 > 0)) throw numerical_error("dirac_immersion: the immersion collapsed to zero area");
  const Eigen::RowVector3d c0 = V.colwise().mean(), c1 = out.V.colwise().mean();
  out.V = ((out.V.rowwise() - c1) * std::sqrt(a0 / a1)).rowwise() + c0;
  return out;
}

DiracFairing dirac_fairing(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int steps) {
  if (steps < 0) throw Error("dirac_fairing: steps must be >= 0, got " + std::to_string(steps));
  DiracFairing out;
  out.V = V;
  out.willmore.push_back(face_willmore_energy(V, F));
  for (int k = 0; k < steps; ++k) {  // §5.3: repeat the first Dirac immersion, recomputing the operator
    const DiracImmersion d = dirac_immersion(out.V, F, 0);
    out.V = d.V;
    out.residual.push_back(d.residual);
    out.willmore.push_back(face_willmore_energy(out.V, F));
  }
  return out;
}

}  // namespace spinmotor

#pragma once
// Dirac immersions and fast fairing (Ye et al. 2018, §5.3).
//
// The first Dirac immersion of a simply connected closed surface is the spin transformation (eq. 21)
// by the intrinsic eigenfunction of smallest |λ| (problem 26, spinor averaged from vertices to faces,
// vertices recovered by least squares, §4.3). Its Willmore energy is lower (Thm. 5.1, continuous case);
// fast fairing repeats it, recomputing the operator on each new surface, and reaches a round sphere in
// a few steps (Fig. 15).
#include <Eigen/Core>
#include <vector>

namespace spinmotor {

struct DiracImmersion {
  Eigen::MatrixXd V;        ///< n×3 new positions, rescaled to the input's total area and centroid
  double eigenvalue = 0.0;  ///< λ of problem 26 (1/length)
  double residual = 0.0;    ///< RMS edge misfit of the least-squares recovery / RMS edge (0: exact)
};

/// Inputs: V (n×3), F (m×3, counter-clockwise; closed, genus 0, connected manifold), which (0-based
/// index into the eigenvalues sorted by |λ|; 0 = the first immersion). Output: the immersion.
/// Error naming the defect on bad input; numerical Error if the eigen solve fails.
DiracImmersion dirac_immersion(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int which = 0);

struct DiracFairing {
  Eigen::MatrixXd V;             ///< n×3 after the last step
  std::vector<double> willmore;  ///< steps + 1 face Willmore energies (Ye eq. 11), the input's first
  std::vector<double> residual;  ///< per step recovery residual
};

/// Inputs: V, F as above, steps ≥ 0. Output: the faired surface and the energies along the way.
DiracFairing dirac_fairing(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int steps);

}  // namespace spinmotor

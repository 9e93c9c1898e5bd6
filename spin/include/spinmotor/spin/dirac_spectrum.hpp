#pragma once
// Eigenvalues of the generalized problem A*A λ = γ B*A λ (Crane et al. 2011, eq. 6) nearest zero, the
// discrete spectrum of the Dirac operator D − ρ (§6.2): on the unit sphere with ρ = 0 the smooth
// operator has eigenvalues n ∈ ℤ \ {−1}; counted as real multiplicities (×4 per quaternionic one) and
// with faces counter-clockwise seen from outside, eq. 6 gives 0 ×4 (the constants), +1 ×8, −2 ×4,
// +2 ×12, ... Eigenvalues scale as 1/length.
//
// Method. With ρ ≡ 0 the constant quaternions are in the kernel of BOTH sides (D·1 = 0), so the pencil
// is singular; the pencil is well defined on the quotient by the constants, and restricting it to
// the complement {λ_p = 0} for one vertex p represents that quotient exactly (A*A and B*A annihilate
// the constants, so the dropped rows of p follow from the others). On that complement A*A is
// positive definite, and Spectra's Lanczos solver in Cholesky mode computes the eigenvalues μ = 1/γ of
// largest magnitude of B*A x = μ A*A x, i.e. of the symmetric L⁻¹(B*A)L⁻ᵀ with A*A = LLᵀ (CHOLMOD),
// each product costing one pair of triangular solves. The constants are reported separately (constant_kernel
// = 4, γ = 0). With ρ ≢ 0 nothing is removed.
#include <Eigen/Core>

#include "spinmotor/spin/face_dirac_operator.hpp"

namespace spinmotor {

struct DiracSpectrumOptions {
  int count = 20;  ///< number of eigenvalues nearest 0 (real multiplicities, constants excluded)
  int ncv = 0;     ///< Lanczos basis size; 0 means min(N, max(2·count + 1, count + 40))
  double tolerance =
      1e-8;  ///< Spectra's relative tolerance on the Ritz values (then refined by Rayleigh–Ritz)
  int max_iterations = 1000;  ///< Spectra restarts
  bool eigenvectors = false;  ///< also return the eigenvectors
};

struct DiracSpectrum {
  Eigen::VectorXd eigenvalues;   ///< `count` values γ, by increasing |γ| (ties: negative first)
  Eigen::MatrixXd eigenvectors;  ///< 4n×count quaternion fields (rows of the n×4 field concatenated),
                                 ///< constant part removed (M_V-orthogonal to the constants); empty
                                 ///< unless requested
  int constant_kernel = 0;       ///< 4 when ρ ≡ 0: the constants (γ = 0), not among `eigenvalues`
  long iterations = 0;           ///< Spectra restarts
  long operations = 0;           ///< products with (A*A)⁻¹ B*A
};

/// Inputs: V (n×3), F (m×3, counter-clockwise), rho (m, or empty for ρ ≡ 0), options. Output: the
/// spectrum above. The mesh must be a closed, oriented, connected manifold without degenerate faces
/// or unreferenced vertices (B*A is Hermitian only on closed meshes); otherwise Error naming the
/// defect. Error (numerical) if Spectra does not converge.
DiracSpectrum dirac_spectrum(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                             const Eigen::VectorXd& rho = {}, const DiracSpectrumOptions& options = {});

/// Face-based operators (Ye et al. 2018, §4.3): the eigenvalues λ nearest zero of the generalized
/// problem (26), Aᵀ D̂ M⁻¹ D̂ A φ = λ Aᵀ D̂ A φ, with D̂ = D − diag(ρ) the intrinsic (eq. 19) or extrinsic
/// (eq. 13) operator of face_dirac_operator.hpp, A the 4m×4n face-from-vertex averaging and M the face
/// areas; φ lives on vertices (4n). λ approximates the eigenvalues of the smooth operator: on the unit
/// sphere the intrinsic one gives ±1 (×4 real), ±2 (×8), ±3 (×12), ... (§5.1). Same method and output as
/// dirac_spectrum (eigenvectors: 4n×count vertex spinors; map them to faces with face_vertex_averaging).
/// For the extrinsic operator with ρ ≡ 0 the constants (λ = 0) are removed and reported in
/// constant_kernel. Inputs: V (n×3), F (m×3, counter-clockwise, manifold, oriented, connected; the
/// left-hand side must be positive definite, else numerical Error), kind, rho (m or empty), options.
DiracSpectrum face_dirac_spectrum(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, FaceDiracKind kind,
                                  const Eigen::VectorXd& rho = {}, const DiracSpectrumOptions& options = {});

}  // namespace spinmotor

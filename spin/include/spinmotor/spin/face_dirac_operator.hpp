#pragma once
// Face-based Dirac operators on edge-constraint nets (Ye et al. 2018, §4.2) and their spin
// transformations (eq. 15/21) with least-squares vertex recovery (§4.3).
//
// Quaternion fields on faces are m×4 (real part first); operators are real 4m×4m matrices of
// quaternionic blocks (quaternion_matrix.hpp: left multiplication, the real transpose is the
// quaternionic conjugate transpose), symmetric, units of length (integrated: divide by the face-area
// mass M to compare with smooth eigenvalues, eq. 26):
//   Extrinsic (eq. 13):  (D_f φ)_i = ½ Σ_j E_ij (φ_j − φ_i) = ½ Σ_j E_ij φ_j − H_i φ_i;
//                        constant φ in the kernel; covariant under rigid motions (Thm. 4.3).
//   Intrinsic (eq. 19):  (D φ)_i = ½ Σ_j cos(θ_ij/2) E_ij φ_j;  depends on edge lengths and the spin
//                        structure only: covariant under isometric bending (Thm. 4.3); on the unit sphere
//                        M⁻¹D has eigenvalues ±1 (×4 real), ±2 (×8), ±3 (×12), ... (§5.1).
// The sums run over the faces j adjacent to i (a boundary edge contributes nothing).
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "spinmotor/spin/edge_constraint_net.hpp"

namespace spinmotor {

enum class FaceDiracKind { Extrinsic, Intrinsic };

/// Inputs: V (n×3), F (m×3, counter-clockwise), kind; optionally the net of (V, F). Output: the 4m×4m
/// operator above (full storage, symmetric). Requirements as edge_constraint_net().
Eigen::SparseMatrix<double> face_dirac_operator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                FaceDiracKind kind);
Eigen::SparseMatrix<double> face_dirac_operator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                const EdgeConstraintNet& net, FaceDiracKind kind);

/// Inputs: F (m×3), n. Output: the 4m×4n face-from-vertex averaging matrix A of §4.3 (each face value
/// the mean of its three corner values, per quaternion component).
Eigen::SparseMatrix<double> face_vertex_averaging(const Eigen::MatrixXi& F, Eigen::Index n);

/// Inputs: V (n×3), F (m×3), phi (m×4 face spinor), kind. Output: n×3 positions of the transformed net:
/// every hyperedge becomes Ẽ_ij = φ̄_i E_ij φ_j (extrinsic, eq. 15) or cos(θ_ij/2) φ̄_i E_ij φ_j
/// (intrinsic, eq. 21), and the vertices are the least-squares solution of v_b − v_a = Im Ẽ_ij over
/// all edges (§4.3), centred at the original centroid. Exact (zero residual) when D φ = ρ φ for real ρ
/// and the surface is simply connected. `residual`, if given, receives the RMS of the edge misfit
/// relative to the RMS transformed edge length. Error naming the face if φ is not finite or zero.
Eigen::MatrixXd face_spin_transform(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                    const Eigen::MatrixXd& phi, FaceDiracKind kind,
                                    double* residual = nullptr);

}  // namespace spinmotor

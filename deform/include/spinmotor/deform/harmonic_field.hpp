#pragma once
// Discrete harmonic scalar fields on a surface mesh (CGA paper §VIII, eq. 14): L λ = 0 at the free
// vertices, λ prescribed on Dirichlet sets.
//
// Weights:
//   MeanValue  (default) Floater's mean-value Laplacian (mean_value_laplacian.hpp): positive weights on
//              any triangulation, so the discrete maximum principle holds (every free λ_i is a convex
//              combination of its neighbours); L is not symmetric: the free block is factorized by
//              SuperLU (LUSolver, minimum degree on Aᵀ + A: the pattern is symmetric). (The paper
//              states w_ij = w_ji; mean-value weights are not symmetric.)
//   Cotangent  the cotangent Laplacian (cotangent_laplacian.hpp): symmetric positive definite free
//              block, CHOLMOD (CholeskySolver); the maximum principle needs non-obtuse (Delaunay)
//              triangles.
// Both Laplacians have rows summing to 0 (L·1 = 0), so with Dirichlet values that sum to 1 at every
// constrained vertex the fields of harmonic_coordinates() sum to 1 everywhere (partition of unity):
// Σ_j λ_j solves the same system as the constant 1, whose solution is unique.
//
// Every connected component of the mesh must contain a constrained vertex, otherwise its values are
// undetermined: Error "... connected component c (s vertices, e.g. vertex i) ... has no constrained
// vertex" (numbered as vertex_components numbers them). Constrained values are exact (0 and 1 are
// stored, not solved for).
#include <Eigen/Core>
#include <span>

#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/deformer.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

enum class HarmonicWeights { MeanValue, Cotangent };
inline constexpr OptionNames<HarmonicWeights, 2> kHarmonicWeightsNames{
    "weights", {{{HarmonicWeights::MeanValue, "mean-value"}, {HarmonicWeights::Cotangent, "cotan"}}}};
constexpr const auto& option_names(HarmonicWeights) { return kHarmonicWeightsNames; }

/// "mean-value" / "cotan".
const char* to_string(HarmonicWeights w);

/// Inputs: V (n×3), F (m×3), handles (k ≥ 1 disjoint vertex sets, see check_handles), weights.
/// Output: n×k matrix Λ, column j the harmonic field that is 1 on handle j and 0 on every other
/// handle (§IV). One factorization of the free block and k − 1 right-hand sides: the last column is
/// 1 minus the others (the partition of unity above). Rows sum to 1 and, with mean-value weights,
/// 0 ≤ Λ ≤ 1 (to rounding).
/// Throws Error for a bad handle (check_handles), a degenerate face (naming it), or a connected
/// component without any handle vertex (naming the component).
Eigen::MatrixXd harmonic_coordinates(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                     std::span<const Handle> handles,
                                     HarmonicWeights weights = HarmonicWeights::MeanValue);

/// Inputs: V (n×3), F (m×3), `zero` and `one` (disjoint non-empty vertex sets: the paper's fixed
/// sets F_i and handle sets H_j merged), weights. Output: n values, λ = 0 on `zero`, 1 on `one`,
/// harmonic elsewhere (§III: the parameter of the spline-aligned deformation). Same errors as above.
Eigen::VectorXd harmonic_field(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Handle& zero,
                               const Handle& one, HarmonicWeights weights = HarmonicWeights::MeanValue);

}  // namespace spinmotor

#pragma once
// Minimal surface in one step (Crane, Pinkall & Schröder 2011, §7.3, Fig. 16 top): the spin
// transformation with ρ = −H removes all of the mean curvature half-density of a disk (possibly
// punctured: an annulus works too, up to the harmonic part removed by the Poisson step, §4.2), since
// H̃|df̃| = (H + ρ)|df| = 0. It is willmore_flow_step with τ = 1; H is face_mean_curvature
// (willmore_flow.hpp). On a closed surface no minimal immersion exists and the step is not meaningful.
#include "spinmotor/spin/willmore_flow.hpp"

namespace spinmotor {

/// Inputs: mesh (V n×3, F m×3, a connected oriented manifold, normally with boundary), spin options
/// (boundary tangents, if set, are prescribed as well: §7.4 with ρ = −H). Output: the spin result
/// (V: n×3 positions, normalised by options.scale). Throws as willmore_flow_step.
inline SpinTransformResult minimal_surface(const Mesh& mesh, const SpinTransformOptions& options = {}) {
  return willmore_flow_step(mesh, 1.0, options);
}

}  // namespace spinmotor

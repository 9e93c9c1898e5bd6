#include "spinmotor/deform/surface_harmonic.hpp"

namespace spinmotor {

SurfaceHarmonicDeformer SurfaceHarmonicDeformer::bind(const Mesh& rest, std::span<const Handle> handles,
                                                      const Options& options) {
  SurfaceHarmonicDeformer d;
  d.options_ = options;
  // §IV: λ_j harmonic, 1 on H_j and 0 on the other handles; M_i = blend(R; λ_i).
  MotorBlendField::Weights W = harmonic_coordinates(rest.V, rest.F, handles, options.weights);
  d.field_ = MotorBlendField::bind(rest.V, std::move(W), options.blend, options.rest_motors);
  d.controls_ = handle_controls(rest.V, handles);
  return d;
}

SurfaceHarmonicDeformer SurfaceHarmonicDeformer::bind(const Mesh& rest, std::span<const Handle> handles) {
  return bind(rest, handles, Options{});
}

}  // namespace spinmotor

#include "spinmotor/deform/spline_deformer.hpp"

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"

namespace spinmotor {

SplineDeformer SplineDeformer::bind(const Mesh& rest, std::span<const Handle> handles,
                                    const Options& options) {
  check_spline(options.basis, options.keys, options.degree);
  if (handles.size() != 2)
    throw Error("SplineDeformer: needs exactly two handles {from, to}, got " +
                std::to_string(handles.size()));
  SplineDeformer d;
  d.options_ = options;
  // §III: the parameter λ is harmonic, 0 on `from` and 1 on `to` (§VIII).
  d.lambda_ = harmonic_field(rest.V, rest.F, handles[0], handles[1], options.weights);
  const Eigen::Index n = rest.V.rows();
  MotorBlendField::Weights W(n, options.keys);
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend))
  for (Eigen::Index i = 0; i < n; ++i)
    spline_weights(options.basis, options.keys, options.degree, d.lambda_[i], W.row(i).data());  // W_j(λ_i)
  d.field_ = MotorBlendField::bind(rest.V, std::move(W), ga::Blend::Log, options.rest_keys);
  if (!options.key_names.empty() && static_cast<int>(options.key_names.size()) != options.keys)
    throw Error("SplineDeformer: " + std::to_string(options.key_names.size()) + " key names for " +
                std::to_string(options.keys) + " keys");
  const Eigen::Vector3d c0 = handle_centroid(rest.V, handles[0]), c1 = handle_centroid(rest.V, handles[1]);
  for (int k = 0; k < options.keys; ++k) {
    const double t = options.keys > 1 ? double(k) / double(options.keys - 1) : 0.0;
    d.controls_.push_back({options.key_names.empty() ? "key" + std::to_string(k) : options.key_names[k],
                           (1 - t) * c0 + t * c1});
  }
  return d;
}

}  // namespace spinmotor

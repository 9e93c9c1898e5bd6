#include "spinmotor/deform/cage_deformer.hpp"

#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/cage_coordinates.hpp"

namespace spinmotor {

CageDeformer CageDeformer::bind(const Mesh& rest, const Mesh& cage, const Options& options) {
  CageDeformer d;
  d.options_ = options;
  d.C_ = cage.V;
  try {
    check_cage(cage.V, cage.F);
    Eigen::MatrixXd W = options.coordinates == Coordinates::Harmonic
                            ? harmonic_cage_coordinates(cage.V, cage.F, rest.V, options.grid)
                            : mean_value_coordinates(cage.V, cage.F, rest.V);
    d.W_ = W;
  } catch (const Error& e) {
    std::string what = e.what();
    if (what.rfind("point ", 0) == 0)
      what = "mesh vertex " + what.substr(6);  // the points are the mesh vertices
    throw Error("CageDeformer: " + what, e.kind());
  }
  d.bound_ =
      options.coordinates == Coordinates::Harmonic ? harmonic_interpolation_bound(cage.V, options.grid) : 0.0;
  if (options.mode == Mode::Motor) d.field_ = MotorBlendField::bind(rest.V, d.W_, options.blend);
  for (Eigen::Index k = 0; k < d.C_.rows(); ++k)
    d.controls_.push_back({"cage[" + std::to_string(k) + "]", d.C_.row(k).transpose()});
  return d;
}

CageDeformer CageDeformer::bind(const Mesh& rest, const Rig& rig, const Options& options) {
  if (!rig.cage) throw Error("CageDeformer: the rig has no cage");
  return bind(rest, *rig.cage, options);
}

void CageDeformer::pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out) {
  if (options_.mode == Mode::Motor) return field_.pose(motors, V_out);  // M_i = blend(R; λ_i) (§VI)
  const Eigen::Index k = C_.rows();
  if (static_cast<Eigen::Index>(motors.size()) != k)
    throw Error("CageDeformer: " + std::to_string(motors.size()) + " motors for " + std::to_string(k) +
                " cage vertices");
  if (moved_.rows() != k) moved_.resize(k, 3);
  for (Eigen::Index j = 0; j < k; ++j)
    moved_.row(j) =
        ga::transform(checked_unit_motor(motors[j], "cage motor " + std::to_string(j)), C_.row(j).transpose())
            .transpose();
  pose_points(moved_, V_out);
}

void CageDeformer::pose_points(const Eigen::MatrixXd& P, Eigen::MatrixXd& V_out) {
  if (options_.mode != Mode::Position) throw Error("CageDeformer::pose_points needs the position mode");
  if (P.rows() != C_.rows() || P.cols() != 3 || !P.allFinite())
    throw Error("CageDeformer: cage points must be a finite " + std::to_string(C_.rows()) + "×3 matrix");
  if (V_out.rows() != vertices() || V_out.cols() != 3) V_out.resize(vertices(), 3);
  V_out.noalias() = W_ * P;  // p = Σ λ_j P_j
}

}  // namespace spinmotor

#pragma once
// CageDeformer: a closed triangle cage around the mesh drives it through cage coordinates (CGA paper
// §VI; cage_coordinates.hpp). Follows the bind/pose contract of deformer.hpp; the controls are the k
// cage vertices, control j = cage vertex j.
//
// bind: check_cage, every mesh vertex inside the cage (else Error naming the vertex), then the n×k
//   coordinates λ: Harmonic (Joshi et al. 2007, `grid` cells along the cage's largest extent; one
//   CHOLMOD factorization, k right-hand sides) or MeanValue (Ju et al. 2005, closed form).
// pose, k unit motors R_j:
//   Position  p_i' = Σ_j λ_ij R_j C_j ~R_j (the classic cage deformation of the moved cage vertices);
//             pose_points() takes the cage vertices directly.
//   Motor     M_i = blend(R; λ_i) (Log = the paper's exp(Σ λ_j log R_j), PivotLog, Linear),
//             p_i' = M_i p_i ~M_i with the rest points bound at bind (MotorBlendField): rotating cage
//             vertices bends and twists the mesh; a rigid motion of all of them moves it rigidly.
//   Mean value coordinates can be negative for a non-convex cage: Linear may then cancel (Error).
#include <Eigen/Core>
#include <span>

#include "spinmotor/deform/deformer.hpp"
#include "spinmotor/deform/motor_blend_field.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

class CageDeformer {
 public:
  enum class Coordinates { Harmonic, MeanValue };
  using Mode = ControlMode;

  struct Options {
    Coordinates coordinates = Coordinates::Harmonic;
    int grid = 64;  ///< Harmonic: cells along the cage's largest extent
    Mode mode = Mode::Motor;
    ga::Blend blend = ga::Blend::Log;
  };

  CageDeformer() = default;

  /// Inputs: rest mesh (V read), cage (V, F: closed, consistently and outward oriented). Throws Error
  /// (check_cage; "mesh vertex i is outside the cage"; grid out of range).
  static CageDeformer bind(const Mesh& rest, const Mesh& cage, const Options& options);
  /// The deformer shape (deformer.hpp): rig.cage. Throws Error when the rig has no cage.
  static CageDeformer bind(const Mesh& rest, const Rig& rig, const Options& options);

  /// k unit motors, one per cage vertex. Output: V_out (n×3).
  void pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out);
  /// Position mode: k×3 cage vertices. Output: V_out = λ · cage (n×3).
  void pose_points(const Eigen::MatrixXd& cage_points, Eigen::MatrixXd& V_out);

  Eigen::Index vertices() const { return W_.rows(); }
  /// One control per cage vertex, named "cage[j]", anchored at it.
  const std::vector<Control>& controls() const { return controls_; }
  /// n×k coordinates (row i: vertex i).
  const MotorBlendField::Weights& coordinates() const { return W_; }
  /// Rest cage vertices (k×3).
  const Eigen::MatrixXd& cage_points() const { return C_; }
  /// |Σ λ_j C_j − x| bound: √3 h for harmonic coordinates, 0 (rounding) for mean value coordinates.
  double interpolation_bound() const { return bound_; }
  const Options& options() const { return options_; }

 private:
  Options options_;
  std::vector<Control> controls_;
  Eigen::MatrixXd C_;
  MotorBlendField::Weights W_;
  MotorBlendField field_;  // Motor mode
  Eigen::MatrixXd moved_;  // Position mode scratch (k×3)
  double bound_ = 0.0;
};

inline constexpr OptionNames<CageDeformer::Coordinates, 2> kCageCoordinatesNames{
    "coordinates",
    {{{CageDeformer::Coordinates::Harmonic, "harmonic"},
      {CageDeformer::Coordinates::MeanValue, "mean-value"}}}};
constexpr const auto& option_names(CageDeformer::Coordinates) { return kCageCoordinatesNames; }

}  // namespace spinmotor

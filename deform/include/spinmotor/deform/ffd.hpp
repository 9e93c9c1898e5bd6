#pragma once
// FfdDeformer: free-form deformation with a lattice of l×m×n controls over a box (CGA paper §V,
// eqs 6–8; Sederberg & Parry 1986). Follows the bind/pose contract of deformer.hpp; the controls are
// the lattice points, not handles.
//
// Lattice: control (a, b, c), a < l, b < m, c < n, has index (a m + b) n + c. Its rest position is
//   box.min + (ξ_a, ξ_b, ξ_c) ∘ box.sizes(), ξ the Greville abscissae of the axis' knot vector, so the
//   undeformed lattice reproduces every point inside the box (linear precision).
// Basis, per axis, of the local coordinate s = (x − box.min) / box.size ∈ [0, 1]:
//   Bezier   Bernstein polynomials of degree l − 1 (eq. 7: every control acts on every vertex),
//            ξ_a = a/(l − 1).
//   BSpline  clamped uniform B-spline of degree d = min(degree, l − 1): d+1 zero knots, interior knots
//            i/(l − d), d+1 one knots; at most d+1 non-zero functions per axis (local support).
//            Bezier is the B-spline with d = l − 1, and both are evaluated by the same Cox–de Boor code.
//   The trivariate weight of control (a, b, c) at a vertex is B_a(s) B_b(t) B_c(u) (eq. 6). Only the
//   non-zero factors are stored: per vertex and axis the first non-zero index and d+1 values (the
//   tensor-product form of a CSR row: (d_l+1)(d_m+1)(d_n+1) weights from (d_l+1)+(d_m+1)+(d_n+1)
//   numbers); weights() expands them into an n×L sparse matrix.
// Modes:
//   Position  (classic FFD, eq. 8) p' = Σ w_c P'_c. pose(motors) moves each control point,
//             P'_c = M_c P_c ~M_c; pose_points() takes the control points directly. An affine map of
//             the controls maps the points by the same affine map (Σ w_c = 1 and linear precision).
//   Motor     M_i = blend(R_c; w_i) (Log: exp(Σ w_c log R_c), the paper's; DLB: with signs
//             relative to the heaviest control), p' = M_i p ~M_i: rotating controls bends and twists
//             instead of shearing. A rigid motion on every control moves the mesh rigidly. PivotLog is
//             not offered (it needs a relative logarithm per pair of controls in a vertex's support).
// Vertices outside the box are left unchanged (weight rows empty) and counted: outside().
// pose(): per frame L logarithms (Log), L motors (DLB) or L control points (Position); then per
//   vertex the tensor contraction over the (d+1)³ supporting controls (the log sums in 8-lane
//   registers), one exponential and one point transform, parallel over vertices, no allocation.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <array>
#include <optional>
#include <span>
#include <vector>

#include "spinmotor/deform/deformer.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

class FfdDeformer {
 public:
  enum class Basis { Bezier, BSpline };
  using Mode = ControlMode;

  struct Options {
    std::array<int, 3> lattice{4, 4, 4};  ///< controls per axis, each ≥ 2
    Basis basis = Basis::Bezier;
    int degree = 3;  ///< BSpline degree (≥ 1; capped at lattice − 1 per axis); ignored for Bezier
    Mode mode = Mode::Motor;
    ga::Blend blend = ga::Blend::Log;  ///< Motor mode: Log or DLB
    /// Lattice box; default: the bounding box of the mesh grown by `margin` × its size on every side
    /// (a flat axis gets margin × the largest size).
    std::optional<Eigen::AlignedBox3d> box;
    double margin = 0.05;
  };

  FfdDeformer() = default;

  /// Inputs: the rest mesh (only V is read; n ≥ 1 finite vertices). Throws Error for a lattice size
  /// < 2 or above 256 per axis, a degree < 1, an empty, inverted or non-finite box, PivotLog, or a
  /// DLB blend with more than 2048 controls (its sign table is L² doubles).
  static FfdDeformer bind(const Mesh& rest, const Options& options);
  static FfdDeformer bind(const Eigen::MatrixXd& V_rest, const Options& options);
  /// The deformer shape (deformer.hpp): the lattice is an option, the rig is not read.
  static FfdDeformer bind(const Mesh& rest, const Rig& /*rig*/, const Options& options) {
    return bind(rest, options);
  }

  /// One unit motor per control, in control order (see above). Output: V_out (n×3).
  void pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out);
  /// Position mode only: L×3 control points (rest: control_points()). Output: V_out (n×3).
  void pose_points(const Eigen::MatrixXd& controls, Eigen::MatrixXd& V_out);

  Eigen::Index vertices() const { return P_.rows(); }
  /// One control per lattice point, named "ffd[a,b,c]", anchored at its rest position, in index() order.
  const std::vector<Control>& controls() const { return controls_; }
  const std::array<int, 3>& lattice() const { return dims_; }
  Eigen::Index index(int a, int b, int c) const {
    return (static_cast<Eigen::Index>(a) * dims_[1] + b) * dims_[2] + c;
  }
  /// L×3 rest positions of the controls.
  const Eigen::MatrixXd& control_points() const { return C_; }
  const Eigen::AlignedBox3d& box() const { return box_; }
  /// Number of rest vertices outside the box (left unchanged by pose()).
  Eigen::Index outside() const { return outside_; }
  bool inside(Eigen::Index i) const { return inside_[i] != 0; }
  /// n×L trivariate weights (rows of outside vertices are empty; rows of inside ones sum to 1).
  Eigen::SparseMatrix<double, Eigen::RowMajor> weights() const;
  /// The motor of vertex i in Motor mode, ga::blend over its supporting controls (reference path).
  ga::Mot vertex_motor(Eigen::Index i, std::span<const ga::Mot> motors) const;
  const Options& options() const { return options_; }

 private:
  void check_motors(std::span<const ga::Mot> motors);

  Options options_;
  std::vector<Control> controls_;
  std::array<int, 3> dims_{0, 0, 0};
  std::array<int, 3> order_{0, 0, 0};  // d + 1 per axis
  Eigen::AlignedBox3d box_;
  Eigen::MatrixXd P_;                      // n×3 rest positions
  Eigen::MatrixXd C_;                      // L×3 rest control points
  std::vector<std::array<int, 3>> start_;  // first non-zero basis index per axis
  std::vector<double> basis_;              // per vertex: order_[0] + order_[1] + order_[2] values
  std::vector<unsigned char> inside_;
  std::vector<int> pivot_;  // DLB: heaviest control
  Eigen::Index outside_ = 0;
  // per-pose scratch
  std::vector<Eigen::Array<double, 8, 1>> lanes_;  // Log: logs (6 + 2 zero pads); DLB: motors
  std::vector<Eigen::Array4d> points4_;            // Position: control points (x, y, z, 0)
  std::vector<double> signs_;                      // DLB: L², sign <R_c ~R_p>_0
  std::vector<ga::Mot> motors_;
  Eigen::MatrixXd points_;
};

inline constexpr OptionNames<FfdDeformer::Basis, 2> kFfdBasisNames{
    "basis", {{{FfdDeformer::Basis::Bezier, "bezier"}, {FfdDeformer::Basis::BSpline, "bspline"}}}};
constexpr const auto& option_names(FfdDeformer::Basis) { return kFfdBasisNames; }

}  // namespace spinmotor

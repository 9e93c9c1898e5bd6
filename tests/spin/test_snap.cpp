// Conformal snap (spin/conformal_snap.hpp, Crane et al. 2011 §7.2, Fig. 21): similarities are
// returned exactly, exact spin transformations are recovered (with their ρ up to a constant), the
// q/−q sign of per-face similarities does not matter, non-conformal edits (twist, bend, a
// surface-harmonic pose) snap to Q ≈ 1, and eq. 6 against eq. 7 on an exact spin transformation.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <random>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/surface_harmonic.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/spin/curvature_change.hpp"
#include "spinmotor/spin/spin_transform.hpp"

namespace test_snap {

using namespace spinmotor;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

namespace {

double diag(const MatrixXd& V) { return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm(); }
double q_mean(const Mesh& rest, const MatrixXd& V) {
  return quasi_conformal_summary(rest.V, rest.F, V).q_mean;
}
/// RMS vertex distance / rest diagonal after the best similarity of V onto ref.
double rms_similarity(const MatrixXd& ref, const MatrixXd& V) {
  return vertex_distances(ref, V, Alignment::Similarity).rms;
}

/// The sausage of the issue: unit icosphere, level 4, z scaled by 3 (z ∈ [−3, 3]).
Mesh sausage() {
  Mesh m = icosphere(4);
  m.V.col(2) *= 3.0;
  return m;
}

/// Twist by `degrees` in total about the z axis, linear in z over [−3, 3].
MatrixXd twist(const MatrixXd& V, double degrees) {
  MatrixXd out = V;
  for (Index i = 0; i < V.rows(); ++i) {
    const double a = degrees * M_PI / 180.0 * (V(i, 2) + 3.0) / 6.0;
    out(i, 0) = std::cos(a) * V(i, 0) - std::sin(a) * V(i, 1);
    out(i, 1) = std::sin(a) * V(i, 0) + std::cos(a) * V(i, 1);
  }
  return out;
}

/// Closed-form bend: the axis z ∈ [−3, 3] is laid on a circular arc of `degrees` (length kept, radius
/// R = 6/Θ) in the xz plane, the cross-section (x, y) carried along its normal frame:
/// p = c(φ) + x (cos φ, 0, −sin φ) + y e_y, c(φ) = (R(1 − cos φ), 0, R sin φ), φ = z/R.
MatrixXd bend(const MatrixXd& V, double degrees) {
  const double R = 6.0 / (degrees * M_PI / 180.0);
  MatrixXd out = V;
  for (Index i = 0; i < V.rows(); ++i) {
    const double phi = V(i, 2) / R, x = V(i, 0);
    out(i, 0) = R * (1.0 - std::cos(phi)) + x * std::cos(phi);
    out(i, 2) = R * std::sin(phi) - x * std::sin(phi);
  }
  return out;
}

/// Angle (degrees) between the end axes of the sausage: at each end, the direction between the
/// centroids of the rest slabs z ∈ [±2, ±3] and z ∈ [±1, ±2] (pointing outwards).
double bend_angle(const MatrixXd& rest, const MatrixXd& V) {
  Vector3d c[4] = {Vector3d::Zero(), Vector3d::Zero(), Vector3d::Zero(), Vector3d::Zero()};
  int k[4] = {0, 0, 0, 0};
  for (Index i = 0; i < rest.rows(); ++i) {
    const double z = rest(i, 2);
    const int s = z <= -2 ? 0 : z <= -1 ? 1 : z >= 2 ? 3 : z >= 1 ? 2 : -1;
    if (s >= 0) c[s] += V.row(i).transpose(), ++k[s];
  }
  for (int s = 0; s < 4; ++s) c[s] /= k[s];
  const Vector3d a = (c[0] - c[1]).normalized(), b = (c[3] - c[2]).normalized();
  return 180.0 - std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / M_PI;
}

/// Smooth ρ of amplitude `amp` at the face barycentres.
VectorXd smooth_rho(const Mesh& m, double amp) {
  VectorXd rho(m.F.rows());
  for (Index f = 0; f < m.F.rows(); ++f) {
    const Vector3d b = (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))).transpose() / 3.0;
    rho[f] = amp * std::sin(2.0 * b.x() + 0.5) * std::cos(1.5 * b.y()) + 0.5 * amp * b.z() * b.z();
  }
  return rho;
}

}  // namespace

TEST_CASE("snapping a similarity-transformed mesh returns it", "[snap]") {
  const Mesh m = icosphere(3);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  const MatrixXd edit = ((1.7 * m.V * R.transpose()).rowwise() + Eigen::RowVector3d(0.3, -2.0, 5.0)).eval();
  for (SpinEigenProblem p : {SpinEigenProblem::Standard, SpinEigenProblem::Generalized}) {
    const ConformalSnapResult r = conformal_snap(m, edit, {.problem = p});
    const double err = (r.V - edit).cwiseAbs().maxCoeff() / diag(edit);
    std::printf("similarity: max error %.3g of the diagonal (%s)\n", err,
                p == SpinEigenProblem::Standard ? "eq. 7" : "eq. 6");
    CHECK(err < 1e-8);
    CHECK(r.rho.cwiseAbs().maxCoeff() < 1e-8);
    // μ is the constant similarity: |μ|² = scale 1.7.
    CHECK((r.mu.rowwise().squaredNorm().array() - 1.7).abs().maxCoeff() < 1e-9);
  }
  // Translation alignment: λ aligned with μ carries the rotation and scale.
  const ConformalSnapResult rt = conformal_snap(m, edit, {.alignment = SnapAlignment::Translation});
  CHECK((rt.V - edit).cwiseAbs().maxCoeff() / diag(edit) < 1e-8);
}

TEST_CASE("an exact spin transformation is recovered, with rho up to a constant, eq. 6 against eq. 7",
          "[snap]") {
  const Mesh m = icosphere(3);  // unit size
  const VectorXd rho = smooth_rho(m, 0.1);
  const SpinTransformResult ex = spin_transform(m, rho);
  const double d = diag(ex.V);
  const VectorXd A = face_areas(m.V, m.F);
  double err7 = 0, err6 = 0;
  for (SpinEigenProblem p : {SpinEigenProblem::Standard, SpinEigenProblem::Generalized}) {
    const ConformalSnapResult r = conformal_snap(m, ex.V, {.problem = p});
    const double err = std::sqrt((r.V - ex.V).rowwise().squaredNorm().mean()) / d;
    const double emax = (r.V - ex.V).rowwise().norm().maxCoeff() / d;
    (p == SpinEigenProblem::Standard ? err7 : err6) = err;
    // ρ recovered up to a constant γ: remove the area-weighted mean of the difference.
    const VectorXd diff = r.rho - rho;
    const double gamma = A.dot(diff) / A.sum();
    const double rho_err = std::sqrt(A.dot((diff.array() - gamma).square().matrix()) / A.sum());
    std::printf(
        "exact spin transformation (%s): RMS %.3g, max %.3g of the diagonal; rho - rho_true = gamma %.3g "
        "+ RMS %.3g (amplitude 0.1); Q_mean edit %.6f snap %.6f; eigenvalue %.3g\n",
        p == SpinEigenProblem::Standard ? "eq. 7" : "eq. 6", err, emax, gamma, rho_err, q_mean(m, ex.V),
        q_mean(m, r.V), r.eigenvalue);
    if (p == SpinEigenProblem::Standard) {
      CHECK(emax < 1e-3);
      CHECK(rho_err < 0.1 * 0.1);
    }
  }
  // Eq. 6 cannot select μ's neighbourhood (μ*(B*A)μ = 0 for the optimal ρ): it is the worse one.
  CHECK(err6 > 10 * err7);
}

TEST_CASE("the optimal rho makes mu orthogonal to B*A mu", "[snap]") {
  const Mesh m = icosphere(2);
  const MatrixXd edit = twist(m.V * 1.0, 40.0);
  const MatrixXd mu =
      vertex_similarities(m.F, m.V.rows(), best_fit_similarities(m.V, m.F, edit), face_areas(m.V, m.F));
  const VectorXd rho = nearest_rho(m.V, m.F, mu);
  // Σ_f A_f Re(conj(Bμ)_f ((D − ρB)μ)_f) = 0 face by face: recompute with the closed form.
  double worst = 0;
  for (Index f = 0; f < m.F.rows(); ++f) {
    ga::Quat Dmu(0, 0, 0, 0), Bmu(0, 0, 0, 0);
    const double a = face_areas(m.V, m.F)[f];
    for (int c = 0; c < 3; ++c) {
      const ga::Quat q(mu(m.F(f, c), 0), mu(m.F(f, c), 1), mu(m.F(f, c), 2), mu(m.F(f, c), 3));
      const Vector3d e = (m.V.row(m.F(f, (c + 2) % 3)) - m.V.row(m.F(f, (c + 1) % 3))).transpose();
      Dmu += (-1.0 / (2 * a)) * (ga::imaginary(e) * q);
      Bmu += (1.0 / 3.0) * q;
    }
    const ga::Quat res = Dmu - rho[f] * Bmu;
    worst = std::max(
        worst, std::abs((ga::conj(Bmu) * res).w()) / std::sqrt(ga::norm2(Bmu) * ga::norm2(Dmu) + 1e-300));
  }
  CHECK(worst < 1e-12);
}

TEST_CASE("q and -q per face give the same snap", "[snap]") {
  const Mesh m = sausage();
  const MatrixXd edit = twist(m.V, 60.0);
  const MatrixXd Sf = best_fit_similarities(m.V, m.F, edit);
  MatrixXd flipped = Sf;
  std::mt19937 rng(7);
  std::bernoulli_distribution coin(0.5);
  Index flips = 0;
  for (Index f = 0; f < Sf.rows(); ++f)
    if (coin(rng) || f == 0) flipped.row(f) *= -1.0, ++flips;
  REQUIRE(flips > Sf.rows() / 3);
  ConformalSnap cs(m);
  const ConformalSnapResult a = cs.snap_face_similarities(Sf, edit);
  const ConformalSnapResult b = cs.snap_face_similarities(flipped, edit);
  CHECK((a.mu - b.mu).cwiseAbs().maxCoeff() < 1e-14);
  CHECK((a.rho - b.rho).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((a.V - b.V).cwiseAbs().maxCoeff() < 1e-12 * diag(m.V));
  // And the snap() path agrees with the explicit one.
  const ConformalSnapResult c = cs.snap(edit);
  CHECK((a.V - c.V).cwiseAbs().maxCoeff() < 1e-12 * diag(m.V));
}

TEST_CASE("a twisted sausage snaps back to the untwisted one (Fig. 21)", "[snap]") {
  const Mesh m = sausage();
  const MatrixXd edit = twist(m.V, 90.0);
  const double q0 = q_mean(m, edit);
  ConformalSnap cs(m);
  const ConformalSnapResult r = cs.snap(edit);
  const double q1 = q_mean(m, r.V), to_rest = rms_similarity(m.V, r.V);
  const double max_rest = vertex_distances(m.V, r.V, Alignment::Similarity).max;
  std::printf(
      "sausage twist 90: Q_mean before %.4f after %.5f; distance to rest RMS %.3g max %.3g of diag; to edit "
      "%.3g; "
      "times (ms) fit %.1f eigen %.1f poisson %.1f\n",
      q0, q1, to_rest, max_rest, vertex_distances(edit, r.V).rms, r.timings.similarity_fit, r.timings.eigen,
      r.timings.poisson);
  CHECK(q0 == Approx(1.238).margin(0.002));
  CHECK(q1 <= 1.01);
  CHECK(max_rest <= 0.005);
}

TEST_CASE("a bent sausage snaps to a near-conformal shape, the tradeoff interpolates", "[snap]") {
  const Mesh m = sausage();
  const MatrixXd edit = bend(m.V, 90.0);
  const double q0 = q_mean(m, edit), a_edit = bend_angle(m.V, edit);
  ConformalSnap cs(m);
  double prev_q = 0, prev_rms = 1e9;
  for (double t : {0.0, 0.5, 1.0}) {
    cs.set_tradeoff(t);
    const ConformalSnapResult r = cs.snap(edit);
    const double q1 = q_mean(m, r.V), rms = vertex_distances(edit, r.V).rms;
    std::printf(
        "sausage bend 90, t = %.2f: Q_mean before %.4f after %.5f; RMS to edit %.4f of diag; bend angle edit "
        "%.1f snap %.1f deg\n",
        t, q0, q1, rms, a_edit, bend_angle(m.V, r.V));
    if (t == 0.0) {
      CHECK(rms < 0.01);  // μ integrated back: the edit up to the Poisson fit
    } else {
      CHECK(q1 < prev_q);     // more conformal ...
      CHECK(rms > prev_rms);  // ... and farther from the edit as t grows
    }
    if (t == 1.0) CHECK(q1 <= 1.02);
    prev_q = t == 0.0 ? q0 + 1 : q1;
    prev_rms = rms;
  }
  CHECK(q0 == Approx(1.149).margin(0.01));
}

TEST_CASE("a tube bent by the surface-harmonic deformer snaps to Q near 1", "[snap][deform]") {
  const int rings = 40, sides = 24;
  for (bool capped : {true, false}) {
    const Mesh m = tube(0.5, 4.0, rings, sides, capped);
    Handle base{"base", Eigen::VectorXi(sides)}, tip{"tip", Eigen::VectorXi(sides)};
    for (int j = 0; j < sides; ++j) base.vertices[j] = j, tip.vertices[j] = (rings - 1) * sides + j;
    const std::vector<Handle> handles{base, tip};
    auto d = SurfaceHarmonicDeformer::bind(m, handles);
    ConformalSnap cs(m);
    for (double degrees : {45.0, 60.0, 90.0}) {
      // The tip ring turned about y through its centre and moved sideways and down: a bend.
      const ga::Rot r = ga::rotor(Vector3d(0, 1, 0), degrees * M_PI / 180.0);
      const double s = degrees / 90.0;
      const Vector3d about(0, 0, 4), t(1.5 * s, 0, -1.5 * s);
      const std::vector<ga::Mot> motors{ga::Mot(1, 0, 0, 0, 0, 0, 0, 0),
                                        ga::motor(r, ga::translator(about + t - ga::rotate(r, about)))};
      MatrixXd edit;
      d.pose(motors, edit);
      const double q0 = q_mean(m, edit);
      const ConformalSnapResult res = cs.snap(edit);
      const double q1 = q_mean(m, res.V);
      // Q_mean over the side faces only (the caps are fans of needle triangles).
      const Index side = 2 * (rings - 1) * sides;
      const Mesh sm{m.V, m.F.topRows(side), {}, {}};
      std::printf(
          "surface-harmonic %s tube bent %.0f deg: Q_mean before %.4f after %.5f (side faces %.4f -> %.5f); "
          "RMS to edit %.4f of diag\n",
          capped ? "capped" : "open", degrees, q0, q1, q_mean(sm, edit), q_mean(sm, res.V),
          vertex_distances(edit, res.V).rms);
      CHECK(q1 < q0);
      if (degrees == 45.0) CHECK(q1 <= 1.02);
    }
  }
}

TEST_CASE("open surfaces take the edit's boundary tangents (5.7)", "[snap]") {
  // A grid bent into a cylinder arc is an isometry (conformal): the snap keeps it.
  const Mesh g = grid(Eigen::Vector2d(2.0, 1.0), Eigen::Vector2i(24, 12));
  MatrixXd edit = g.V;
  const double R = 2.0 / (M_PI / 2);
  for (Index i = 0; i < g.V.rows(); ++i) {
    const double phi = g.V(i, 0) / R;
    edit(i, 0) = R * std::sin(phi), edit(i, 2) = R * (1 - std::cos(phi));
  }
  const ConformalSnapResult r = conformal_snap(g, edit);
  const double rms = vertex_distances(edit, r.V).rms;
  std::printf("grid rolled 90 deg: Q_mean before %.5f after %.5f; RMS to edit %.3g of diag\n",
              q_mean(g, edit), q_mean(g, r.V), rms);
  CHECK(rms < 2e-3);
  CHECK(q_mean(g, r.V) < 1.01);
}

TEST_CASE("rho smoothing tames a creased edit", "[snap]") {
  // A sausage folded sharply at its middle by a two-bone linear blend (no transition): a crease.
  const Mesh m = sausage();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()).toRotationMatrix();
  MatrixXd edit = m.V;
  for (Index i = 0; i < m.V.rows(); ++i)
    if (m.V(i, 2) > 0) edit.row(i) = (R * m.V.row(i).transpose()).transpose();
  const double q0 = q_mean(m, edit);
  const ConformalSnapResult raw = conformal_snap(m, edit),
                            smooth = conformal_snap(m, edit, {.rho_smoothing = 20});
  const double q_raw = q_mean(m, raw.V), q_smooth = q_mean(m, smooth.V);
  std::printf(
      "creased sausage: Q_mean edit %.4f, snap %.4f (max |rho| %.3g), with 20 smoothing passes %.4f (max "
      "|rho| "
      "%.3g)\n",
      q0, q_raw, raw.rho.cwiseAbs().maxCoeff(), q_smooth, smooth.rho.cwiseAbs().maxCoeff());
  CHECK(smooth.rho.cwiseAbs().maxCoeff() < raw.rho.cwiseAbs().maxCoeff());
  CHECK(q_smooth < q_raw);
  CHECK_THROWS_AS(ConformalSnap(m, {.rho_smoothing = -1}), Error);
}

TEST_CASE("conformal snap rejects bad input", "[snap]") {
  const Mesh m = icosphere(1);
  ConformalSnap cs(m);
  CHECK_THROWS_AS(cs.snap(MatrixXd::Zero(m.V.rows() + 1, 3)), Error);
  MatrixXd bad = m.V;
  bad(5, 1) = std::nan("");
  CHECK_THROWS_WITH(cs.snap(bad), Catch::Contains("vertex 5"));
  CHECK_THROWS_AS(cs.set_tradeoff(1.5), Error);
  CHECK_THROWS_AS(ConformalSnap(m, {.tradeoff = -0.1}), Error);
  CHECK_THROWS_AS(ConformalSnap(m, {.problem = SpinEigenProblem::Unweighted}), Error);
  const Mesh g = grid(Eigen::Vector2d(1.0, 1.0), Eigen::Vector2i(4, 4));
  CHECK_THROWS_WITH(ConformalSnap(g, {.problem = SpinEigenProblem::Generalized}), Catch::Contains("closed"));
}

}  // namespace test_snap

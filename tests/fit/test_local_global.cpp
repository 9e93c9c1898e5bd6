// The local/global layer (fit/local_global.hpp, fit/cells.hpp) on its own: the global step against a
// dense KKT solve written here, the attraction's closed form, the stopping rule on prescribed energies,
// Anderson acceleration on a linear fixed point, and the cells' fits on exact rigid and similar motions.
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "spinmotor/fit/cells.hpp"
#include "spinmotor/fit/local_global.hpp"
#include "spinmotor/linalg/dirichlet_solver.hpp"
#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace test_local_global {

using namespace spinmotor;
using fit::RowMatrix3;

namespace {

/// A problem without cells: the right-hand side is L_FF Y_F + L_FC Y_C (the global step alone would
/// return Y), its energy the prescribed sequence (or |X − Y|² when none is given).
struct Fixed final : fit::Problem {
  Eigen::SparseMatrix<double> L;
  RowMatrix3 Y;
  std::vector<double> energies;
  int fits = 0;
  double fit(const RowMatrix3& X, int it, fit::SolveReport&) override {
    ++fits;
    if (!energies.empty()) return energies[std::min<size_t>(static_cast<size_t>(it), energies.size() - 1)];
    return (X - Y).squaredNorm();
  }
  void rhs(int, const fit::LocalGlobal& solver, RowMatrix3& B) override {
    const RowMatrix3 LY = L * Y;
    for (Eigen::Index r = 0; r < solver.free().size(); ++r) B.row(r) = LY.row(solver.free()[r]);
  }
  double energy_scale() const override { return 1.0; }
};

double volume(const Eigen::MatrixXi& F, const RowMatrix3& X) {
  double v = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    v += Eigen::Vector3d(X.row(F(f, 0)))
             .dot(Eigen::Vector3d(X.row(F(f, 1))).cross(Eigen::Vector3d(X.row(F(f, 2)))));
  return v / 6;
}

}  // namespace

TEST_CASE("global step with a volume row: one step is the dense KKT solution", "[fit]") {
  const Mesh m = icosphere(2);
  const Eigen::Index n = m.V.rows();
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(m.V, m.F);
  fit::LocalGlobal lg;
  fit::LocalGlobal::Bind b;
  b.L = L;
  b.constrained = Eigen::VectorXi::LinSpaced(5, 0, 4);
  b.measure = fit::MeasureKind::Volume;
  b.F = m.F;
  lg.bind(b);
  Fixed p;
  p.L = L;
  p.Y = RowMatrix3(m.V) * 1.3;  // the cells ask for a larger sphere; the row keeps the rest volume
  RowMatrix3 X = m.V, values(5, 3);
  for (int k = 0; k < 5; ++k) values.row(k) = p.Y.row(k);
  const double target = volume(m.F, RowMatrix3(m.V));
  fit::SolveOptions o;
  o.max_iterations = 1;
  const fit::SolveReport r = lg.solve(p, X, values, nullptr, target, o);
  CHECK(r.iterations == 1);
  // Independent: minimise ½ xᵀ L_FF x − bᵀ x subject to g·(x − x0) = target − vol(x0) (the volume
  // linearised at the start x0 = rest with the constrained rows placed), as one dense KKT system.
  RowMatrix3 X0 = m.V;
  for (int k = 0; k < 5; ++k) X0.row(k) = values.row(k);
  const Eigen::Index nf = n - 5;
  const Eigen::MatrixXd Ld = Eigen::MatrixXd(L);
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * nf + 1, 3 * nf + 1);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(3 * nf + 1);
  const RowMatrix3 LY = L * p.Y;
  double gx0 = 0;
  for (Eigen::Index i = 0; i < nf; ++i) {
    for (Eigen::Index j = 0; j < nf; ++j)
      for (int d = 0; d < 3; ++d) K(3 * i + d, 3 * j + d) = Ld(5 + i, 5 + j);
    for (int d = 0; d < 3; ++d) {
      double s = LY(5 + i, d);
      for (int c = 0; c < 5; ++c) s -= Ld(5 + i, c) * values(c, d);
      rhs(3 * i + d) = s;
    }
  }
  // g = ∂vol/∂x_i = Σ_{f ∋ i} x_j × x_k / 6 by finite differences' closed form, written face by face.
  Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * nf);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int i = m.F(f, c);
      if (i < 5) continue;
      const Eigen::Vector3d xj = X0.row(m.F(f, (c + 1) % 3)), xk = X0.row(m.F(f, (c + 2) % 3));
      g.segment<3>(3 * (i - 5)) += xj.cross(xk) / 6;
    }
  for (Eigen::Index i = 0; i < nf; ++i) gx0 += g.segment<3>(3 * i).dot(X0.row(5 + i).transpose());
  K.block(0, 3 * nf, 3 * nf, 1) = g;
  K.block(3 * nf, 0, 1, 3 * nf) = g.transpose();
  rhs(3 * nf) = target - volume(m.F, X0) + gx0;
  const Eigen::VectorXd x = K.fullPivLu().solve(rhs);
  double err = 0;
  for (Eigen::Index i = 0; i < nf; ++i)
    err = std::max(err, (X.row(5 + i) - x.segment<3>(3 * i).transpose()).norm());
  CHECK(err <= 1e-10);
  for (int k = 0; k < 5; ++k) CHECK(X.row(k) == values.row(k));  // the constrained rows bit for bit
}

TEST_CASE("attraction: the step solves (L + C)_FF x = B + C Y - (L + C)_FC x_C", "[fit]") {
  const Mesh m = icosphere(1);
  const Eigen::Index n = m.V.rows();
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(m.V, m.F);
  Eigen::VectorXd c = Eigen::VectorXd::LinSpaced(n, 0.0, 2.0);
  c[3] = 0;
  fit::LocalGlobal lg;
  fit::LocalGlobal::Bind b;
  b.L = L;
  b.attraction = c;  // no constrained vertex: the attraction anchors the sphere
  lg.bind(b);
  Fixed p;
  p.L = Eigen::SparseMatrix<double>(n, n);  // B = 0
  p.Y = RowMatrix3::Zero(n, 3);
  RowMatrix3 X = m.V, Ytarget = RowMatrix3(m.V) * 2.0 + RowMatrix3::Constant(n, 3, 0.5);
  fit::SolveOptions o;
  o.max_iterations = 1;
  lg.solve(p, X, RowMatrix3(0, 3), &Ytarget, 0.0, o);
  const Eigen::MatrixXd A = Eigen::MatrixXd(L) + Eigen::MatrixXd(c.asDiagonal());
  const Eigen::MatrixXd expect = A.ldlt().solve(c.asDiagonal() * Eigen::MatrixXd(Ytarget));
  CHECK((Eigen::MatrixXd(X) - expect).cwiseAbs().maxCoeff() <= 1e-10);
  // Nothing anchors a component: the solver names it.
  fit::LocalGlobal bad;
  fit::LocalGlobal::Bind nb;
  nb.L = L;
  CHECK_THROWS_AS(bad.bind(nb), FloatingComponentError);
}

TEST_CASE("stopping rule: relative energy change, zero energy, max_iterations", "[fit]") {
  const Mesh m = icosphere(0);
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(m.V, m.F);
  fit::LocalGlobal lg;
  fit::LocalGlobal::Bind b;
  b.L = L;
  b.constrained = Eigen::VectorXi::LinSpaced(2, 0, 1);
  lg.bind(b);
  RowMatrix3 values = RowMatrix3(m.V).topRows(2);
  auto run = [&](std::vector<double> e, int max_it, double tol) {
    Fixed p;
    p.L = L;
    p.Y = m.V;
    p.energies = std::move(e);
    RowMatrix3 X = m.V;
    fit::SolveOptions o;
    o.max_iterations = max_it;
    o.tolerance = tol;
    return lg.solve(p, X, values, nullptr, 0.0, o);
  };
  // |E_2 − E_1| = 4e-5 ≤ 1e-4 · max(E_2, E_1) = 5e-5: stops after the local step of iteration 2.
  fit::SolveReport r = run({1.0, 0.5, 0.49996, 0.2}, 50, 1e-4);
  CHECK(r.iterations == 2);
  CHECK(r.converged);
  CHECK(r.energy.size() == 3);
  // A rise is a change like any other: 0.5 → 0.6 does not stop at 1e-4.
  r = run({1.0, 0.5, 0.6, 0.6}, 50, 1e-4);
  CHECK(r.iterations == 3);
  // A zero-energy start stops at once, without a step.
  r = run({1e-30}, 50, 1e-4);
  CHECK(r.iterations == 0);
  CHECK(r.converged);
  // max_iterations: not converged.
  r = run({8, 4, 2, 1, 0.5, 0.25}, 3, 1e-4);
  CHECK(r.iterations == 3);
  CHECK_FALSE(r.converged);
}

TEST_CASE("rigid cells: handles moved by one rigid motion give that motion, E = 0", "[fit]") {
  const Mesh m = tube(0.5, 3.0, 16, 12, true);
  const Eigen::Index n = m.V.rows();
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(m.V, m.F);
  fit::RigidCells cells =
      fit::RigidCells::bind(m.V, m.F, L, Eigen::MatrixXd(), fit::RigidCells::Kind::Spokes, false);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::RowVector3d t(0.3, -2, 1);
  RowMatrix3 moved = (RowMatrix3(m.V) * R.transpose()).rowwise() + t;
  // The rigid motion has zero energy and every cell's rotor is R.
  Eigen::Index fb = 0;
  CHECK(cells.fit(moved, fb) <= 1e-20 * cells.energy_scale());
  for (const ga::Rot& q : cells.rotors()) CHECK((ga::rotation_matrix(q) - R).cwiseAbs().maxCoeff() <= 1e-12);
  CHECK(cells.energy(moved) <= 1e-20 * cells.energy_scale());
  // A non-rigid state has positive energy, the same through fit() and energy().
  RowMatrix3 bent = moved;
  bent.col(0) += 0.1 * bent.col(2).cwiseAbs2();
  cells.reset_rotors();
  const double e_fit = cells.fit(bent, fb), e = cells.energy(bent);
  CHECK(e > 1e-4 * cells.energy_scale());
  CHECK(e_fit == Approx(e).epsilon(1e-10));
  (void)n;
}

TEST_CASE("similarity cells: an exact similarity has zero energy and is recovered", "[fit]") {
  const Mesh m = icosphere(2);
  const Eigen::Index n = m.V.rows();
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(m.V, m.F);
  const Eigen::VectorXi free = Eigen::VectorXi::LinSpaced(n - 3, 3, static_cast<int>(n) - 1);
  std::vector<char> fixed(static_cast<size_t>(n), 0);
  fixed[0] = fixed[1] = fixed[2] = 1;
  const double s = 1.7;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2.0, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
  const RowMatrix3 X = (s * RowMatrix3(m.V) * R.transpose()).rowwise() + Eigen::RowVector3d(1, 2, 3);
  fit::SimilarityOneRings rings = fit::SimilarityOneRings::bind(m.V, L, free);
  REQUIRE(rings.ok());
  Eigen::Index fb = 0;
  CHECK(std::abs(rings.fit(X, fb)) <= 1e-12 * s * s * rings.rest_scale());
  for (Eigen::Index k = 0; k < free.size(); ++k) {
    const ga::Similarity& sim = rings.similarity(rings.cell_of(free[k]));
    CHECK(sim.scale == Approx(s).epsilon(1e-12));
    CHECK((ga::rotation_matrix(sim.rotor) - R).cwiseAbs().maxCoeff() <= 1e-10);
  }
  fit::SimilarityFaces faces = fit::SimilarityFaces::bind(m.V, m.F, fixed, free);
  CHECK(faces.fit(X, fb) <= 1e-20 * s * s * faces.area());
  CHECK(fb == 0);
  // A shear has positive face energy: ½ |J − T|² per unit area for J = [[1, k], [0, 1]] in-plane is k²/2,
  // on average over orientations positive; here simply > 0.
  RowMatrix3 sheared = m.V;
  sheared.col(0) += 0.3 * sheared.col(1);
  CHECK(faces.fit(sheared, fb) > 1e-3 * faces.area());
}

namespace {

/// A linear contraction x → G(x): the right-hand side L (0.9 X Qᵀ) makes the global step
/// G(X)_F = 0.9 (X Qᵀ)_F + (a constant of the constrained rows); energy |X − X*|².
struct Contraction final : fit::Problem {
  Eigen::SparseMatrix<double> L;
  Eigen::Matrix3d Q;
  RowMatrix3 X, Xstar;
  double fit(const RowMatrix3& x, int it, fit::SolveReport&) override {
    X = x;
    return Xstar.rows() ? (X - Xstar).squaredNorm() : 1.0 / (1.0 + it);  // before X* is known: never stops
  }
  void rhs(int, const fit::LocalGlobal& solver, RowMatrix3& B) override {
    const RowMatrix3 LY = L * RowMatrix3(0.9 * X * Q.transpose());
    for (Eigen::Index r = 0; r < solver.free().size(); ++r) B.row(r) = LY.row(solver.free()[r]);
  }
  double energy_scale() const override { return 1.0; }
};

}  // namespace

TEST_CASE("Anderson acceleration reaches the fixed point of a linear contraction in far fewer steps",
          "[fit]") {
  const Mesh m = icosphere(2);
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(m.V, m.F);
  fit::LocalGlobal lg;
  fit::LocalGlobal::Bind b;
  b.L = L;
  b.constrained = Eigen::VectorXi::LinSpaced(3, 0, 2);
  lg.bind(b);
  const RowMatrix3 values = RowMatrix3(m.V).topRows(3);
  Contraction p;
  p.L = L;
  p.Q = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  // X* by the plain iteration run long (rate 0.9: 600 steps leave 0.9^600 ≈ 2e-28).
  RowMatrix3 X = m.V;
  fit::SolveOptions o;
  o.max_iterations = 600;
  o.tolerance = 0;
  lg.solve(p, X, values, nullptr, 0.0, o);
  p.Xstar = X;
  auto run = [&](int depth) {
    RowMatrix3 Y = m.V;
    fit::SolveOptions so;
    so.max_iterations = 1000;
    so.tolerance = 0;  // stop by E ≤ 1e-24 only
    so.anderson = depth;
    const fit::SolveReport r = lg.solve(p, Y, values, nullptr, 0.0, so);
    CHECK(r.converged);
    CHECK((Y - p.Xstar).cwiseAbs().maxCoeff() <= 1e-11);
    return r.iterations;
  };
  const int plain = run(0), accelerated = run(6);
  INFO("plain " << plain << " steps, Anderson(6) " << accelerated);
  CHECK(plain > 200);  // 0.81^k |X0 − X*|² ≤ 1e-24
  CHECK(accelerated * 5 < plain);
}

}  // namespace test_local_global

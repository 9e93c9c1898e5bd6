// Sparse solvers (linalg/cholesky_solver.hpp, lu_solver.hpp, dirichlet_solver.hpp): exact discrete
// harmonic functions, agreement with Eigen's own factorizations, many right-hand sides, refactoring,
// and the errors for singular, indefinite and under-constrained systems.
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/linalg/dirichlet_solver.hpp"
#include "spinmotor/linalg/lu_solver.hpp"
#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/mass_matrix.hpp"
#include "spinmotor/mesh/mean_value_laplacian.hpp"
#include "spinmotor/mesh/topology.hpp"

namespace test_solvers {

using namespace spinmotor;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using Eigen::VectorXi;
using SpMat = Eigen::SparseMatrix<double>;

namespace {

Mesh perturbed_grid(int nx, int ny, double amount, unsigned seed = 3) {
  Mesh g = grid(Eigen::Vector2d(2.0, 1.5), Eigen::Vector2i(nx, ny));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  const VectorXi in = interior_vertices(g.F, g.V.rows());
  for (Eigen::Index k = 0; k < in.size(); ++k) {
    g.V(in[k], 0) += u(rng) * 2.0 / (nx - 1);
    g.V(in[k], 1) += u(rng) * 1.5 / (ny - 1);
  }
  return g;
}

MatrixXd values_at(const MatrixXd& U, const VectorXi& idx) {
  MatrixXd r(idx.size(), U.cols());
  for (Eigen::Index k = 0; k < idx.size(); ++k) r.row(k) = U.row(idx[k]);
  return r;
}

// L + s·M on an icosphere: symmetric positive definite.
SpMat shifted_laplacian(const Mesh& s, double shift) {
  return SpMat(cotangent_laplacian(s.V, s.F) + shift * mass_matrix(s.V, s.F));
}

}  // namespace

TEST_CASE("Dirichlet: Re(z³) and x²−y² are exactly discrete-harmonic on a uniform grid", "[solvers]") {
  // On this triangulated rectangular grid the cotangent Laplacian is the 5-point stencil (the diagonal
  // edges face right angles, weight 0), which annihilates harmonic polynomials of degree ≤ 3 for any
  // cell aspect ratio: the solution must match at every interior vertex to roundoff.
  const Mesh g = grid(Eigen::Vector2d(2.0, 1.5), Eigen::Vector2i(21, 13));
  const SpMat L = cotangent_laplacian(g.V, g.F);
  const VectorXi bd = boundary_vertices(g.F, g.V.rows());
  MatrixXd U(g.V.rows(), 2);
  const auto x = g.V.col(0).array(), y = g.V.col(1).array();
  U.col(0) = (x * x * x - 3 * x * y * y).matrix();
  U.col(1) = (x * x - y * y).matrix();
  for (DirichletSolver::Kind kind : {DirichletSolver::Kind::SPD, DirichletSolver::Kind::LU}) {
    DirichletSolver d;
    d.bind(L, bd, kind);
    const MatrixXd X = d.solve(values_at(U, bd));
    CHECK((X - U).cwiseAbs().maxCoeff() < 1e-13);
  }
}

TEST_CASE("Dirichlet: linear functions are reproduced on a perturbed grid (cotangent and mean-value)",
          "[solvers]") {
  const Mesh g = perturbed_grid(17, 14, 0.3);
  const VectorXi bd = boundary_vertices(g.F, g.V.rows());
  const MatrixXd U =
      g.V.leftCols(2) * Eigen::Matrix2d{{0.5, -1.0}, {2.0, 0.25}} + MatrixXd::Constant(g.V.rows(), 2, 0.3);
  DirichletSolver cot;
  cot.bind(cotangent_laplacian(g.V, g.F), bd, DirichletSolver::Kind::SPD);
  CHECK((cot.solve(values_at(U, bd)) - U).cwiseAbs().maxCoeff() < 1e-13);
  DirichletSolver mv;  // Floater's weights: linear precision, non-symmetric → LU
  mv.bind(mean_value_laplacian(g.V, g.F), bd, DirichletSolver::Kind::LU);
  CHECK((mv.solve(values_at(U, bd)) - U).cwiseAbs().maxCoeff() < 1e-13);
}

TEST_CASE("Dirichlet: e^x cos y converges with order 2 (mass-weighted L2) on perturbed grids", "[solvers]") {
  double err[3];
  for (int k = 0; k < 3; ++k) {
    const int nx = 16 * (1 << k) + 1, ny = 12 * (1 << k) + 1;
    const Mesh g = perturbed_grid(nx, ny, 0.2, 11);  // perturbation scales with h: same mesh family
    const VectorXd u = (g.V.col(0).array().exp() * g.V.col(1).array().cos()).matrix();
    const VectorXi bd = boundary_vertices(g.F, g.V.rows());
    DirichletSolver d;
    d.bind(cotangent_laplacian(g.V, g.F), bd);
    const VectorXd e = d.solve(values_at(u, bd)) - u;
    err[k] = std::sqrt(e.cwiseProduct(e).dot(vertex_areas(g.V, g.F)));
  }
  // Observed 8.3e-4, 2.3e-4, 5.7e-5 (orders 1.86, 1.98). The max error is pre-asymptotic on random
  // meshes at these sizes (orders ≈ 1.3–1.8), so the test uses the L2 norm.
  INFO("L2 errors " << err[0] << ", " << err[1] << ", " << err[2]);
  CHECK(std::log2(err[0] / err[1]) > 1.75);
  CHECK(std::log2(err[1] / err[2]) > 1.75);
}

TEST_CASE("Dirichlet: several right-hand sides at once equal single solves, new values reuse the factor",
          "[solvers]") {
  const Mesh g = perturbed_grid(15, 11, 0.25);
  const SpMat L = cotangent_laplacian(g.V, g.F);
  const SpMat M = mass_matrix(g.V, g.F);
  const VectorXi bd = boundary_vertices(g.F, g.V.rows());
  std::mt19937 rng(5);
  std::normal_distribution<double> nd;
  MatrixXd values(bd.size(), 3), F(g.V.rows(), 3);
  for (auto* A : {&values, &F})
    for (Eigen::Index i = 0; i < A->size(); ++i) A->data()[i] = nd(rng);
  const MatrixXd B = M * F;  // Poisson right-hand side
  DirichletSolver d;
  d.bind(L, bd);
  const MatrixXd X = d.solve(B, values);
  for (int c = 0; c < 3; ++c) {
    const MatrixXd xc = d.solve(B.col(c), values.col(c));
    CHECK((X.col(c) - xc).cwiseAbs().maxCoeff() < 1e-14 * (1 + xc.cwiseAbs().maxCoeff()));
  }
  // Constrained rows equal the values exactly; free rows satisfy the equations.
  CHECK(values_at(X, bd) == values);
  const MatrixXd R = L * X - B;
  for (Eigen::Index r = 0; r < d.free().size(); ++r) CHECK(R.row(d.free()[r]).norm() < 1e-12);
  // Other values, same factorization: equal to a freshly bound solver.
  const MatrixXd values2 = 2.0 * values.array() - 1.0;
  DirichletSolver fresh;
  fresh.bind(L, bd);
  CHECK((d.solve(B, values2) - fresh.solve(B, values2)).cwiseAbs().maxCoeff() == 0.0);
  // Empty right-hand side means B = 0.
  CHECK((d.solve(values) - d.solve(MatrixXd::Zero(g.V.rows(), 3), values)).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("Dirichlet: a component without a constrained vertex is named", "[solvers]") {
  // Two grids side by side: 4×4 (vertices 0..15) and 5×3 (vertices 16..30); only the first is pinned.
  const Mesh a = grid(Eigen::Vector2d(1, 1), Eigen::Vector2i(4, 4));
  Mesh b = grid(Eigen::Vector2d(1, 1), Eigen::Vector2i(5, 3));
  b.V.col(0).array() += 3.0;
  MatrixXd V(a.V.rows() + b.V.rows(), 3);
  V << a.V, b.V;
  Eigen::MatrixXi F(a.F.rows() + b.F.rows(), 3);
  F << a.F, (b.F.array() + 16).matrix();
  const SpMat L = cotangent_laplacian(V, F);
  VectorXi pins(2);
  pins << 0, 15;
  DirichletSolver d;
  CHECK_THROWS_WITH(d.bind(L, pins), Catch::Contains("connected component 1 (15 vertices, e.g. vertex 16)") &&
                                         Catch::Contains("no constrained vertex"));
  try {
    d.bind(L, pins);
    FAIL("a floating component was accepted");
  } catch (const FloatingComponentError& e) {  // an Error, with every floating component
    CHECK(e.kind() == Error::Kind::BadInput);
    CHECK(e.count() == 2);
    REQUIRE(e.floating().size() == 1);
    CHECK(e.floating()[0].id == 1);
    CHECK(e.floating()[0].size == 15);
    CHECK(e.floating()[0].first == 16);
  }
  CHECK_FALSE(d.bound());
  pins << 0, 20;  // one pin in each component: fine
  CHECK_NOTHROW(d.bind(L, pins));
  CHECK(d.solve(MatrixXd::Ones(2, 1)).isApproxToConstant(1.0, 1e-12));  // constants are harmonic
  // Bad indices are named.
  pins << 0, 31;
  CHECK_THROWS_WITH(d.bind(L, pins), Catch::Contains("constrained index 1 is 31, out of range"));
  pins << 20, 20;
  CHECK_THROWS_WITH(d.bind(L, pins), Catch::Contains("vertex 20 is constrained twice"));
  CHECK_THROWS_WITH(DirichletSolver().solve(MatrixXd::Ones(2, 1)),
                    Catch::Contains("before a successful bind"));
}

TEST_CASE("CholeskySolver: agrees with Eigen's SimplicialLDLT for every ordering, supernodal and simplicial",
          "[solvers]") {
  const Mesh s = icosphere(3);
  const SpMat A = shifted_laplacian(s, 0.1);
  MatrixXd B(s.V.rows(), 4);
  B << s.V, VectorXd::Ones(s.V.rows());
  Eigen::SimplicialLDLT<SpMat> ref(A);
  REQUIRE(ref.info() == Eigen::Success);
  const MatrixXd Xref = ref.solve(B);
  using O = CholeskySolver::Ordering;
  for (O o : {O::Auto, O::Natural, O::AMD, O::METIS, O::NESDIS})
    for (bool super : {true, false}) {
      CholeskySolver c({o, super});
      c.compute(A);
      const MatrixXd X = c.solve(B);
      CHECK((X - Xref).cwiseAbs().maxCoeff() < 1e-11 * Xref.cwiseAbs().maxCoeff());
      CHECK(c.factor_nonzeros() > A.nonZeros() / 2);
      // Many right-hand sides at once equal one at a time.
      for (int k = 0; k < 4; ++k)
        CHECK((c.solve(B.col(k)) - X.col(k)).cwiseAbs().maxCoeff() < 1e-13 * X.col(k).cwiseAbs().maxCoeff());
    }
  // Fill-reducing orderings beat the natural one.
  CholeskySolver nat({O::Natural, true}), amd({O::AMD, true});
  nat.analyze(A);
  amd.analyze(A);
  CHECK(amd.factor_nonzeros() < nat.factor_nonzeros());
}

TEST_CASE("CholeskySolver: factorize reuses the analysis, pattern changes are rejected", "[solvers]") {
  const Mesh s = icosphere(2);
  CholeskySolver c;
  c.analyze(shifted_laplacian(s, 1.0));
  for (double shift : {1.0, 0.01, 100.0}) {
    const SpMat A = shifted_laplacian(s, shift);
    c.factorize(A);
    const MatrixXd X = c.solve(s.V);
    CHECK((A * X - s.V).cwiseAbs().maxCoeff() < 1e-12);
  }
  SpMat other = shifted_laplacian(icosphere(1), 1.0);
  CHECK_THROWS_WITH(c.factorize(other), Catch::Contains("pattern differs"));
  CHECK_THROWS_WITH(c.solve(MatrixXd::Ones(3, 1)), Catch::Contains("right-hand side has 3 rows"));
  CHECK_THROWS_WITH(CholeskySolver().solve(MatrixXd::Ones(3, 1)),
                    Catch::Contains("before a successful factorize"));
  SpMat bad = shifted_laplacian(s, 1.0);
  bad.valuePtr()[5] = std::nan("");
  CHECK_THROWS_WITH(c.factorize(bad), Catch::Contains("not finite"));
}

TEST_CASE("CholeskySolver: indefinite and singular matrices raise numerical errors", "[solvers]") {
  const Mesh s = icosphere(2);
  const SpMat L = cotangent_laplacian(s.V, s.F);
  const SpMat M = mass_matrix(s.V, s.F);
  using O = CholeskySolver::Ordering;
  for (bool super : {true, false}) {
    // Indefinite: L − 10 M has the eigenvalues 2, 6, ... (times the mass) below 10.
    CholeskySolver c({O::AMD, super});
    const SpMat indefinite = L - 10.0 * M;
    CHECK_THROWS_WITH(c.compute(indefinite), Catch::Contains("not positive definite") &&
                                                 Catch::Contains("CHOLMOD") &&
                                                 Catch::Contains("connected component 0"));
    try {
      c.compute(indefinite);
    } catch (const Error& e) {
      CHECK(e.kind() == Error::Kind::Numerical);
    }
    CHECK_FALSE(c.factorized());
    // Singular: the pure Neumann Laplacian (constants in the kernel); the last pivot is roundoff.
    CHECK_THROWS_WITH(c.compute(L), Catch::Contains("not positive definite"));
  }
  // A singular matrix with two components names the failing one: here the floating second component.
  Eigen::MatrixXi F2(s.F.rows() * 2, 3);
  F2 << s.F, (s.F.array() + static_cast<int>(s.V.rows())).matrix();
  MatrixXd V2(2 * s.V.rows(), 3);
  V2 << s.V, s.V.rowwise() + Eigen::RowVector3d(3, 0, 0);
  SpMat A2 = cotangent_laplacian(V2, F2);
  A2.coeffRef(0, 0) += 1.0;  // pins the first sphere only
  CholeskySolver c2;
  CHECK_THROWS_WITH(c2.compute(A2), Catch::Contains("connected component 1 (162 rows, e.g. row 162)"));
}

TEST_CASE("LUSolver: agrees with Eigen's SparseLU on the mean-value Laplacian, reports singular columns",
          "[solvers]") {
  const Mesh g = perturbed_grid(13, 10, 0.3);
  const SpMat L = mean_value_laplacian(g.V, g.F);
  const SpMat A = SpMat(L + 0.5 * mass_matrix(g.V, g.F));
  MatrixXd B = g.V;
  B.col(2).setOnes();
  Eigen::SparseLU<SpMat> ref(A);
  REQUIRE(ref.info() == Eigen::Success);
  const MatrixXd Xref = ref.solve(B);
  using O = LUSolver::Ordering;
  for (O o : {O::COLAMD, O::Natural, O::MMD_AtA, O::MMD_AtPlusA})
    for (double thresh : {1.0, 0.1}) {
      LUSolver lu({o, thresh});
      lu.compute(A);
      const MatrixXd X = lu.solve(B);
      CHECK((X - Xref).cwiseAbs().maxCoeff() < 1e-11 * Xref.cwiseAbs().maxCoeff());
      CHECK(lu.rcond() > 1e-6);
      for (int k = 0; k < 3; ++k)
        CHECK((lu.solve(B.col(k)) - X.col(k)).cwiseAbs().maxCoeff() < 1e-13 * X.col(k).cwiseAbs().maxCoeff());
    }
  // Refactorization with new values, same pattern.
  LUSolver lu;
  lu.analyze(A);
  const SpMat A2 = SpMat(L + 2.0 * mass_matrix(g.V, g.F));
  lu.factorize(A2);
  CHECK((A2 * lu.solve(B) - B).cwiseAbs().maxCoeff() < 1e-12);
  // Numerically singular: rows of L sum to zero (constants in the kernel).
  CHECK_THROWS_WITH(lu.compute(L), Catch::Contains("singular") && Catch::Contains("connected component 0"));
  // Structurally singular: an empty column (SuperLU itself would read out of bounds on it).
  SpMat Z = A;
  Z.prune([](Eigen::Index r, Eigen::Index c, double) { return c != 7; });
  Z.makeCompressed();
  CHECK_THROWS_WITH(lu.compute(Z), Catch::Contains("structurally singular, column 7 is empty"));
  // Structurally singular with no empty column: columns 3 and 4 share their only row.
  SpMat S(5, 5);
  std::vector<Eigen::Triplet<double>> t{{0, 0, 1}, {1, 1, 1}, {2, 2, 1}, {1, 3, 1}, {1, 4, 2}, {0, 4, 1}};
  t.emplace_back(0, 3, 3.0);
  S.setFromTriplets(t.begin(), t.end());
  CHECK_THROWS_WITH(lu.compute(S), Catch::Contains("structurally singular") && Catch::Contains("pivot row"));
  // Exactly singular numerically: two equal columns.
  SpMat E(3, 3);
  std::vector<Eigen::Triplet<double>> te{{0, 0, 1}, {1, 0, 2}, {0, 1, 1}, {1, 1, 2},
                                         {2, 2, 1}, {2, 0, 1}, {2, 1, 1}};
  E.setFromTriplets(te.begin(), te.end());
  CHECK_THROWS_WITH(lu.compute(E), Catch::Contains("singular"));
  try {
    lu.compute(Z);
  } catch (const Error& e) {
    CHECK(e.kind() == Error::Kind::Numerical);
  }
  CHECK_THROWS_WITH(LUSolver({O::COLAMD, 1.5}), Catch::Contains("pivot_threshold"));
}

TEST_CASE("solvers accept an empty system", "[solvers]") {
  const SpMat A(0, 0);
  CholeskySolver c;
  LUSolver lu;
  CHECK_NOTHROW(c.compute(A));
  CHECK_NOTHROW(lu.compute(A));
  CHECK(c.solve(MatrixXd(0, 2)).cols() == 2);
  CHECK(lu.solve(MatrixXd(0, 2)).cols() == 2);
}

TEST_CASE("Ordering: one name table, each solver accepts its subset and names the others", "[solvers]") {
  CHECK(option_values<Ordering>() == std::vector<std::string>{"auto", "natural", "amd", "metis", "nesdis",
                                                              "nested-dissection", "colamd", "mmd-ata",
                                                              "mmd-at-plus-a"});
  for (const std::string& name : option_values<Ordering>())
    CHECK(option_name(parse_option<Ordering>(name)) == name);
  CHECK_THROWS_WITH(parse_option<Ordering>("mmd_ata"), Catch::Contains("unknown ordering 'mmd_ata'"));
  // CholeskySolver: auto, natural, amd, metis, nesdis; LUSolver: natural, colamd, mmd-ata, mmd-at-plus-a.
  for (Ordering o : CholeskySolver::kOrderings) CHECK_NOTHROW(CholeskySolver({o, true}));
  for (Ordering o : LUSolver::kOrderings) CHECK_NOTHROW(LUSolver({o, 1.0}));
  try {
    CholeskySolver({Ordering::COLAMD, true});
    FAIL("CholeskySolver accepted colamd");
  } catch (const Error& e) {
    CHECK(e.kind() == Error::Kind::BadInput);
    CHECK(std::string(e.what()) ==
          "CholeskySolver: ordering 'colamd' is not supported here (one of: auto, natural, amd, metis, "
          "nesdis)");
  }
  CHECK_THROWS_WITH(ComplexCholeskySolver({Ordering::NestedDissection, true}),
                    Catch::Contains("ordering 'nested-dissection' is not supported"));
  CHECK_THROWS_WITH(
      LUSolver({Ordering::AMD, 1.0}),
      Catch::Contains("LUSolver: ordering 'amd' is not supported here (one of: natural, colamd, "
                      "mmd-ata, mmd-at-plus-a)"));
  CHECK(ordering_values(LUSolver::kOrderings) ==
        std::vector<std::string>{"natural", "colamd", "mmd-ata", "mmd-at-plus-a"});
  // parse_ordering: a subset's names parse; a name of the table outside the subset is refused like an
  // unknown one, and the message lists the subset only.
  for (Ordering o : LUSolver::kOrderings)
    CHECK(parse_ordering(option_name(o), LUSolver::kOrderings, "lu") == o);
  for (const char* bad : {"amd", "no-such"}) {
    try {
      (void)parse_ordering(bad, LUSolver::kOrderings, "lu");
      FAIL("parse_ordering accepted " << bad);
    } catch (const Error& e) {
      CHECK(e.kind() == Error::Kind::BadInput);
      CHECK(std::string(e.what()) == std::string("lu: unknown ordering '") + bad +
                                         "' (one of: natural, colamd, mmd-ata, mmd-at-plus-a)");
    }
  }
}

TEST_CASE("Dirichlet: a given free order gives the same solution, solve_free and A_FC are its parts",
          "[solvers]") {
  const Mesh g = perturbed_grid(12, 9, 0.3);
  const SpMat L = cotangent_laplacian(g.V, g.F);
  const VectorXi b = boundary_vertices(g.F, g.V.rows());
  const MatrixXd values = values_at(g.V, b);
  DirichletSolver plain;
  plain.bind(L, b);
  const MatrixXd X = plain.solve(values);
  // The free vertices in reverse order.
  VectorXi order = plain.free().reverse();
  for (bool try_natural : {false, true}) {
    DirichletSolver::Options o;
    o.cholesky.try_natural = try_natural;
    DirichletSolver d(o);
    d.bind(L, b, order);
    CHECK(d.free() == order);
    CHECK((d.solve(values) - X).cwiseAbs().maxCoeff() < 1e-12);
    // solve_free on −A_FC X_C is the free part of solve().
    const MatrixXd XF = d.solve_free(-(d.free_constrained_block() * values));
    for (Eigen::Index r = 0; r < order.size(); ++r) CHECK((XF.row(r) - X.row(order[r])).norm() < 1e-12);
    CHECK(d.free_constrained_block().rows() == order.size());
    CHECK(d.free_constrained_block().cols() == b.size());
    CHECK(d.cholesky().factorized());
  }
  // try_natural keeps the ordering with fewer flops: AMD beats the reversed natural order here.
  DirichletSolver::Options o;
  o.cholesky.ordering = Ordering::AMD;
  o.cholesky.try_natural = true;
  DirichletSolver d(o);
  d.bind(L, b, order);
  CholeskySolver amd({Ordering::AMD, true}), nat({Ordering::Natural, true});
  const SpMat A_FF = [&] {
    SpMat P(order.size(), L.rows());
    std::vector<Eigen::Triplet<double>> t;
    for (Eigen::Index r = 0; r < order.size(); ++r) t.emplace_back(static_cast<int>(r), order[r], 1.0);
    P.setFromTriplets(t.begin(), t.end());
    SpMat A = P * L * SpMat(P.transpose());
    A.makeCompressed();
    return A;
  }();
  amd.analyze(A_FF);
  nat.analyze(A_FF);
  CHECK(d.cholesky().ordering_used() ==
        (nat.factor_flops() < amd.factor_flops() ? Ordering::Natural : Ordering::AMD));
  CHECK(d.cholesky().factor_flops() == std::min(nat.factor_flops(), amd.factor_flops()));
  // A bad free order is named.
  VectorXi bad = order;
  bad[0] = b[0];
  CHECK_THROWS_WITH(d.bind(L, b, bad),
                    Catch::Contains("free order index 0") && Catch::Contains("constrained"));
  CHECK_THROWS_WITH(d.bind(L, b, VectorXi(order.head(3))), Catch::Contains("free order has 3 indices"));
  CHECK_THROWS_WITH(DirichletSolver().solve_free(MatrixXd(0, 3)),
                    Catch::Contains("before a successful bind"));
  DirichletSolver lu;
  lu.bind(L, b, DirichletSolver::Kind::LU);
  CHECK_THROWS_WITH(lu.cholesky(), Catch::Contains("Kind::SPD"));
}

}  // namespace test_solvers

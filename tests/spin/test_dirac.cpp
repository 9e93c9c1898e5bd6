// Discrete Dirac operator of Crane, Pinkall & Schröder 2011 (§5): explicit operators against closed
// forms, the direct 4×4-block assembly against the explicit products, and the spectrum on the sphere
// (§6.2).
#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/mass_matrix.hpp"
#include "spinmotor/spin/dirac_assembly.hpp"
#include "spinmotor/spin/dirac_operator.hpp"
#include "spinmotor/spin/dirac_spectrum.hpp"
#include "spinmotor/spin/quaternion_matrix.hpp"

namespace test_dirac {

using namespace spinmotor;

namespace {

// A small closed mesh with a bumpy, non-uniform geometry (so no accidental symmetry hides a sign).
Mesh bumpy_icosphere(int level) {
  Mesh m = icosphere(level);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    const Eigen::Vector3d p = m.V.row(i);
    m.V.row(i) *= 1.0 + 0.2 * std::sin(3 * p.x()) * std::cos(2 * p.y()) + 0.1 * p.z();
  }
  return m;
}

Eigen::VectorXd some_rho(const Mesh& m) {
  Eigen::VectorXd rho(m.F.rows());
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) rho[f] = std::sin(0.7 * f) * 3.0;
  return rho;
}

Eigen::MatrixXd dense_lower_sym(const Eigen::SparseMatrix<double>& L) {
  Eigen::MatrixXd A = Eigen::MatrixXd(L);
  Eigen::MatrixXd S = A.triangularView<Eigen::Lower>();
  S += A.triangularView<Eigen::StrictlyLower>().transpose();
  return S;
}

}  // namespace

TEST_CASE("quaternion blocks represent the Hamilton product and conjugate transpose", "[dirac]") {
  const ga::Quat p(0.3, -1.2, 0.5, 2.0), q(-0.7, 0.4, 1.1, -0.2);
  const Eigen::Vector4d pq = quaternion_block(p) * q.coeffs();
  CHECK((pq - (p * q).coeffs()).norm() < 1e-14);
  CHECK((quaternion_block(p).transpose() - quaternion_block(ga::conj(p))).norm() < 1e-15);
  CHECK((quaternion_block(p) * quaternion_block(q) - quaternion_block(p * q)).norm() < 1e-14);
}

TEST_CASE("D annihilates constants and maps the immersion to -2N (eq. 5)", "[dirac]") {
  const Mesh m = bumpy_icosphere(2);
  const Eigen::SparseMatrix<double> D = dirac_operator(m.V, m.F);
  REQUIRE(D.rows() == 4 * m.F.rows());
  REQUIRE(D.cols() == 4 * m.V.rows());
  for (int k = 0; k < 4; ++k) {
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(m.V.rows(), 4);
    c.col(k).setOnes();
    CHECK((D * flatten_quaternions(c)).cwiseAbs().maxCoeff() < 1e-12);
  }
  // f as an imaginary quaternion field: D f = -(1/2A) Σ e_j f_j = -2 N exactly on every face.
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(m.V.rows(), 4);
  f.rightCols(3) = m.V;
  const Eigen::MatrixXd Df = unflatten_quaternions(D * flatten_quaternions(f));
  const Eigen::MatrixXd N = face_normals(m.V, m.F);
  CHECK(Df.col(0).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((Df.rightCols(3) + 2.0 * N).cwiseAbs().maxCoeff() < 1e-11);
}

TEST_CASE("the direct assembly equals the explicit products A*A and B*A (§5.4, §5.5)", "[dirac]") {
  const Mesh m = bumpy_icosphere(1);
  const Eigen::VectorXd rho = some_rho(m);
  const Eigen::VectorXd area = face_areas(m.V, m.F);
  const Eigen::SparseMatrix<double> A = dirac_minus_rho(m.V, m.F, rho);
  const Eigen::SparseMatrix<double> B = face_vertex_average(m.F, m.V.rows());
  const Eigen::MatrixXd AtA = Eigen::MatrixXd(dirac_adjoint(A, area) * A);
  const Eigen::MatrixXd BtA = Eigen::MatrixXd(dirac_adjoint(B, area) * A);
  // Both are symmetric on a closed mesh.
  CHECK((AtA - AtA.transpose()).cwiseAbs().maxCoeff() < 1e-12 * AtA.cwiseAbs().maxCoeff());
  CHECK((BtA - BtA.transpose()).cwiseAbs().maxCoeff() < 1e-12 * BtA.cwiseAbs().maxCoeff());
  // Mass matrices: B*B 1 = M_V 1 (B*B has row sums ⅓ Σ A_f).
  const Eigen::VectorXd Mv = vertex_areas(m.V, m.F, MassType::Barycentric);

  SECTION("orderings of the vertex graph: natural, amd, metis; others are rejected by name") {
    CHECK(vertex_ordering_values() == std::vector<std::string>{"natural", "amd", "metis"});
    CHECK_THROWS_WITH(
        DiracAssembly(m.V, m.F, Ordering::COLAMD),
        Catch::Contains("DiracAssembly: ordering 'colamd' is not supported here (one of: natural, "
                        "amd, metis)"));
  }
  SECTION("natural order, no scaling") {
    const DiracAssembly as(m.V, m.F, Ordering::Natural);
    CHECK((as.vertex_areas() - Mv).cwiseAbs().maxCoeff() < 1e-14);
    Eigen::SparseMatrix<double> K = as.pattern(), G = as.pattern();
    as.normal_matrix(rho, {}, K);
    as.mixed_matrix(rho, {}, G);
    CHECK((dense_lower_sym(K) - AtA).cwiseAbs().maxCoeff() < 1e-12 * AtA.cwiseAbs().maxCoeff());
    CHECK((dense_lower_sym(G) - BtA).cwiseAbs().maxCoeff() < 1e-12 * BtA.cwiseAbs().maxCoeff());
  }
  SECTION("AMD order with a vertex scaling") {
    const DiracAssembly as(m.V, m.F, Ordering::AMD);
    Eigen::VectorXd s(m.V.rows());
    for (Eigen::Index i = 0; i < s.size(); ++i) s[i] = 0.5 + 0.01 * i;
    Eigen::SparseMatrix<double> K = as.pattern();
    as.normal_matrix(rho, s, K);
    // P permutes (new unknown k) <- (old unknown): K = Pᵀ S AtA S P.
    const Eigen::Index N = 4 * m.V.rows();
    Eigen::MatrixXd P = Eigen::MatrixXd::Zero(N, N);
    for (Eigen::Index k = 0; k < m.V.rows(); ++k)
      for (int c = 0; c < 4; ++c) P(4 * as.order()[k] + c, 4 * k + c) = 1.0;
    Eigen::VectorXd s4(N);
    for (Eigen::Index i = 0; i < N; ++i) s4[i] = s[i / 4];
    const Eigen::MatrixXd expect = P.transpose() * s4.asDiagonal() * AtA * s4.asDiagonal() * P;
    CHECK((dense_lower_sym(K) - expect).cwiseAbs().maxCoeff() < 1e-12 * expect.cwiseAbs().maxCoeff());
    // expand() undoes the permutation and applies the scaling.
    Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(N, -1.0, 2.0);
    const Eigen::MatrixXd lam = as.expand(x, s);
    const Eigen::VectorXd back = s4.asDiagonal() * P * x;
    CHECK((flatten_quaternions(lam) - back).cwiseAbs().maxCoeff() < 1e-14);
  }
}

TEST_CASE("spectrum of the unit icosphere: 0 x4, +1 x8, -2 x4, +2 x12 (eq. 6, §6.2)", "[dirac][spectrum]") {
  const Mesh m = icosphere(4);  // 2562 vertices
  DiracSpectrumOptions opt;
  opt.count = 24;
  const DiracSpectrum s = dirac_spectrum(m.V, m.F, {}, opt);
  REQUIRE(s.constant_kernel == 4);
  REQUIRE(s.eigenvalues.size() == 24);
  WARN("unit icosphere (2562 vertices), eigenvalues of eq. 6 nearest 0: " << s.eigenvalues.transpose());
  for (int t = 0; t < 8; ++t) CHECK(s.eigenvalues[t] == Approx(1.0).epsilon(0.01));
  for (int t = 8; t < 12; ++t) CHECK(s.eigenvalues[t] == Approx(-2.0).epsilon(0.01));
  for (int t = 12; t < 24; ++t) CHECK(s.eigenvalues[t] == Approx(2.0).epsilon(0.01));
}

TEST_CASE("Dirac eigenvalues scale as 1/radius, eigenvectors solve eq. 6", "[dirac][spectrum]") {
  DiracSpectrumOptions opt;
  opt.count = 8;
  opt.eigenvectors = true;
  const Mesh m1 = icosphere(3), m2 = icosphere(3, 2.5);
  const DiracSpectrum s1 = dirac_spectrum(m1.V, m1.F, {}, opt), s2 = dirac_spectrum(m2.V, m2.F, {}, opt);
  for (int t = 0; t < 8; ++t) CHECK(s2.eigenvalues[t] * 2.5 == Approx(s1.eigenvalues[t]).epsilon(1e-7));
  // A*A λ = γ B*A λ with the explicit operators, constants removed from λ.
  const Eigen::VectorXd area = face_areas(m1.V, m1.F);
  const Eigen::SparseMatrix<double> D = dirac_operator(m1.V, m1.F);
  const Eigen::SparseMatrix<double> B = face_vertex_average(m1.F, m1.V.rows());
  const Eigen::SparseMatrix<double> K = dirac_adjoint(D, area) * D, G = dirac_adjoint(B, area) * D;
  for (int t = 0; t < 8; ++t) {
    const Eigen::VectorXd x = s1.eigenvectors.col(t);
    const Eigen::VectorXd Kx = K * x;
    CHECK((Kx - s1.eigenvalues[t] * (G * x)).norm() < 1e-6 * Kx.norm());
  }
}

}  // namespace test_dirac

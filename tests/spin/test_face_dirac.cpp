// Face-based Dirac operators (Ye et al. 2018, §4.2–§4.3, §5.1): spectrum of the unit sphere (problem 26),
// invariance of the intrinsic operator under isometric bending and of the extrinsic one under rigid
// motions, and the spin transformation (eq. 15/21) with least-squares vertex recovery.
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/spin/dirac_spectrum.hpp"
#include "spinmotor/spin/face_dirac_operator.hpp"
#include "spinmotor/spin/quaternion_matrix.hpp"

namespace test_face_dirac {

using namespace spinmotor;

namespace {

// Eigenvalues of M^-1/2 D M^-1/2 (dense; small meshes only), sorted ascending.
Eigen::VectorXd dense_spectrum(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, FaceDiracKind kind) {
  const EdgeConstraintNet net = edge_constraint_net(V, F);
  const Eigen::MatrixXd D = face_dirac_operator(V, F, net, kind);
  Eigen::VectorXd s(4 * F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) s.segment<4>(4 * f).setConstant(1.0 / std::sqrt(net.area[f]));
  const Eigen::MatrixXd Dn = s.asDiagonal() * D * s.asDiagonal();
  REQUIRE((Dn - Dn.transpose()).cwiseAbs().maxCoeff() < 1e-12);
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Dn, Eigen::EigenvaluesOnly).eigenvalues();
}

}  // namespace

TEST_CASE("intrinsic spectrum of the unit icosphere (problem 26): +-1 x4, +-2 x8, +-3 x12 within 0.5%",
          "[ye][dirac]") {
  const Mesh s = icosphere(4);
  REQUIRE(s.V.rows() == 2562);
  DiracSpectrumOptions o;
  o.count = 48;
  const DiracSpectrum sp = face_dirac_spectrum(s.V, s.F, FaceDiracKind::Intrinsic, {}, o);
  CHECK(sp.constant_kernel == 0);
  // Compare sorted by value (within a ±k pair the two |λ| differ by ~1e-3, so the |λ| order interleaves).
  Eigen::VectorXd got = sp.eigenvalues;
  std::sort(got.data(), got.data() + got.size());
  Eigen::VectorXd expected(48);
  int t = 0;
  for (int k = 3; k >= 1; --k)
    for (int r = 0; r < 4 * k; ++r) expected[t++] = -k;
  for (int k = 1; k <= 3; ++k)
    for (int r = 0; r < 4 * k; ++r) expected[t++] = k;
  double worst = 0;
  for (int i = 0; i < 48; ++i) {
    INFO("eigenvalue " << i << ": " << got[i] << " expected " << expected[i]);
    worst = std::max(worst, std::abs(got[i] / expected[i] - 1));
    CHECK(std::abs(got[i] / expected[i] - 1) < 0.005);
  }
  WARN("icosphere 4 intrinsic spectrum: worst relative error " << worst << " (first " << sp.eigenvalues[0]
                                                               << ", last " << sp.eigenvalues[47] << ")");
}

TEST_CASE("extrinsic spectrum of the unit icosphere: constants removed, shifted by -H = -1", "[ye][dirac]") {
  const Mesh s = icosphere(3);
  DiracSpectrumOptions o;
  o.count = 4;
  const DiracSpectrum sp = face_dirac_spectrum(s.V, s.F, FaceDiracKind::Extrinsic, {}, o);
  CHECK(sp.constant_kernel == 4);
  // D_f = D − H on a sphere (eq. 5): the intrinsic ±1 become 0 (the constants) and −2 ... and +1 stays
  // nearest zero after the constants: expect |λ| near 1 or 2 only.
  for (int i = 0; i < 4; ++i)
    CHECK(std::abs(std::abs(sp.eigenvalues[i]) - std::round(std::abs(sp.eigenvalues[i]))) < 0.03);
}

TEST_CASE("intrinsic eigenvalues unchanged under an isometric fold of a flat grid, extrinsic ones change",
          "[ye][dirac]") {
  const Mesh g = grid({2.0, 1.0}, {9, 5});
  const Eigen::VectorXd flat_i = dense_spectrum(g.V, g.F, FaceDiracKind::Intrinsic);
  const Eigen::VectorXd flat_e = dense_spectrum(g.V, g.F, FaceDiracKind::Extrinsic);
  for (const double angle : {0.3, 1.2, 2.5}) {
    Mesh f = g;
    for (Eigen::Index v = 0; v < f.V.rows(); ++v)
      if (f.V(v, 0) > 0) {  // rotate the half x > 0 about the y axis (a line of edges): isometric
        const double x = f.V(v, 0);
        f.V(v, 0) = x * std::cos(angle);
        f.V(v, 2) = x * std::sin(angle);
      }
    const Eigen::VectorXd fold_i = dense_spectrum(f.V, f.F, FaceDiracKind::Intrinsic);
    const Eigen::VectorXd fold_e = dense_spectrum(f.V, f.F, FaceDiracKind::Extrinsic);
    INFO("fold " << angle << ": intrinsic max change " << (fold_i - flat_i).cwiseAbs().maxCoeff()
                 << ", extrinsic " << (fold_e - flat_e).cwiseAbs().maxCoeff());
    CHECK((fold_i - flat_i).cwiseAbs().maxCoeff() < 1e-9);
    CHECK((fold_e - flat_e).cwiseAbs().maxCoeff() > 1e-3);
  }
}

TEST_CASE("extrinsic and intrinsic eigenvalues unchanged under rigid motions, scaled by 1/s", "[ye][dirac]") {
  Mesh e = icosphere(1);
  e.V.col(0) *= 1.7;
  e.V.col(2) *= 0.6;
  const Eigen::VectorXd ref_e = dense_spectrum(e.V, e.F, FaceDiracKind::Extrinsic);
  const Eigen::VectorXd ref_i = dense_spectrum(e.V, e.F, FaceDiracKind::Intrinsic);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.83, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::MatrixXd Vr = (e.V * R.transpose()).rowwise() + Eigen::RowVector3d(0.3, -4.0, 2.2);
  CHECK((dense_spectrum(Vr, e.F, FaceDiracKind::Extrinsic) - ref_e).cwiseAbs().maxCoeff() < 1e-9);
  CHECK((dense_spectrum(Vr, e.F, FaceDiracKind::Intrinsic) - ref_i).cwiseAbs().maxCoeff() < 1e-9);
  CHECK((dense_spectrum(2.5 * e.V, e.F, FaceDiracKind::Extrinsic) - ref_e / 2.5).cwiseAbs().maxCoeff() <
        1e-9);
  // Constant spinors span the kernel of the extrinsic operator (4 zero eigenvalues).
  CHECK((ref_e.array().abs() < 1e-9).count() == 4);
  CHECK((ref_i.array().abs() < 1e-6).count() == 0);
}

TEST_CASE("face spin transformation: constants are similarities, eigenfunctions integrate", "[ye][dirac]") {
  const Mesh s = icosphere(2);
  const Eigen::Index m = s.F.rows();
  // φ ≡ q: every edge maps to q̄ e q (a rotation scaled by |q|², eq. 15), recovered exactly.
  const Eigen::Vector4d q(0.9, 0.2, -0.4, 0.3);
  const Eigen::MatrixXd phi = Eigen::MatrixXd(q.transpose().replicate(m, 1));
  double res = 1;
  const Eigen::MatrixXd X = face_spin_transform(s.V, s.F, phi, FaceDiracKind::Extrinsic, &res);
  const Eigen::Quaterniond Q(q[0], q[1], q[2], q[3]);
  const Eigen::Matrix3d Rq = Q.normalized().conjugate().toRotationMatrix();  // v ↦ q̄ v q for unit q
  Eigen::MatrixXd expected = s.V * Rq.transpose() * q.squaredNorm();
  const Eigen::RowVector3d shift = s.V.colwise().mean() - expected.colwise().mean();
  expected.rowwise() += shift;
  CHECK((X - expected).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(res < 1e-12);
  // The first intrinsic eigenfunction closes up: small least-squares residual.
  DiracSpectrumOptions o;
  o.count = 4;
  o.eigenvectors = true;
  const DiracSpectrum sp = face_dirac_spectrum(s.V, s.F, FaceDiracKind::Intrinsic, {}, o);
  const Eigen::VectorXd pf = face_vertex_averaging(s.F, s.V.rows()) * sp.eigenvectors.col(0);
  const Eigen::MatrixXd Y =
      face_spin_transform(s.V, s.F, unflatten_quaternions(pf), FaceDiracKind::Intrinsic, &res);
  WARN("icosphere 2, first intrinsic eigenfunction: lambda " << sp.eigenvalues[0] << ", edge residual "
                                                             << res);
  CHECK(res < 0.05);
  CHECK(Y.allFinite());
}

TEST_CASE("face Dirac operators reject bad input", "[ye][dirac]") {
  const Mesh s = icosphere(1);
  CHECK_THROWS_AS(face_dirac_spectrum(s.V, s.F, FaceDiracKind::Intrinsic, Eigen::VectorXd::Zero(3)), Error);
  CHECK_THROWS_AS(
      face_spin_transform(s.V, s.F, Eigen::MatrixXd::Zero(s.F.rows(), 4), FaceDiracKind::Intrinsic), Error);
  CHECK_THROWS_AS(face_spin_transform(s.V, s.F, Eigen::MatrixXd::Ones(3, 4), FaceDiracKind::Intrinsic),
                  Error);
}

}  // namespace test_face_dirac

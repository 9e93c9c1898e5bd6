// Horn's best rotation (ga/rotor_fit.hpp) against the SVD/polar answer R = V diag(1,1,det(VUᵀ)) Uᵀ.
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <catch2/catch.hpp>
#include <random>
#include <vector>

#include "spinmotor/ga/rotor_fit.hpp"

namespace test_rotor_fit {

using namespace spinmotor;
using namespace spinmotor::ga;

namespace {

struct SvdAnswer {
  Eigen::Matrix3d R;
  double trace;  // max tr(R S)
  double gap;    // top eigen-gap of Horn's N: 2 (σ2 + d σ3); the rotation is unique iff > 0
};

// The closest proper rotation maximising tr(R S), S = U Σ Vᵀ (Kabsch / Sorkine–Alexa).
SvdAnswer svd_rotation(const Eigen::Matrix3d& S) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
  const double d = (V * U.transpose()).determinant() > 0 ? 1.0 : -1.0;
  const Eigen::Vector3d s = svd.singularValues();
  SvdAnswer a;
  a.R = V * Eigen::Vector3d(1, 1, d).asDiagonal() * U.transpose();
  a.trace = s[0] + s[1] + d * s[2];
  a.gap = 2.0 * (s[1] + d * s[2]);
  return a;
}

ga::Rot random_rotor(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Eigen::Vector4d q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  return ga::Rot(q[0], q[1], q[2], q[3]);
}

Eigen::Matrix3d random_matrix(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Eigen::Matrix3d S;
  for (int i = 0; i < 9; ++i) S.data()[i] = g(rng);
  return S;
}

Eigen::Matrix3d random_rotation(std::mt19937& rng) { return rotation_matrix(random_rotor(rng)); }

double max_abs(const Eigen::Matrix3d& A) { return A.cwiseAbs().maxCoeff(); }

}  // namespace

TEST_CASE("Horn's matrix: q^T N(S) q = tr(R(q) S) and rotation_matrix is q v q-bar", "[ga][rotation]") {
  std::mt19937 rng(1);
  for (int t = 0; t < 200; ++t) {
    const Eigen::Matrix3d S = random_matrix(rng);
    const ga::Rot q = random_rotor(rng);
    const Eigen::Vector4d qv(q.w(), q.x(), q.y(), q.z());
    const Eigen::Matrix3d R = rotation_matrix(q);
    CHECK(qv.dot(horn_matrix(S) * qv) == Approx((R * S).trace()).margin(1e-12));
    CHECK(max_abs(R - ga::to_quaterniond(q).toRotationMatrix()) < 1e-14);
    const Eigen::Vector3d v(0.3, -1.2, 0.7);
    CHECK((R * v - ga::rotate(q, v)).norm() < 1e-14);
  }
}

TEST_CASE("Horn's rotor equals the SVD rotation on 10^4 random covariances (reflections included)",
          "[ga][rotation]") {
  std::mt19937 rng(7);
  int reflections = 0, fast = 0, compared = 0;
  double worst_R = 0, worst_trace = 0;
  for (int t = 0; t < 10000; ++t) {
    Eigen::Matrix3d S = random_matrix(rng);
    if (t % 4 == 3) S *= 1e-6;  // scale invariance
    const SvdAnswer ref = svd_rotation(S);
    if (S.determinant() < 0) ++reflections;
    // Alternate cold starts (identity) and random warm starts.
    const ga::Rot warm = t % 2 ? random_rotor(rng) : ga::Rot(1, 0, 0, 0);
    RotationInfo info;
    const ga::Rot q = best_rotation(S, warm, &info);
    const Eigen::Matrix3d R = rotation_matrix(q);
    fast += info.fast;
    const double scale = S.norm();
    worst_trace = std::max(worst_trace, std::abs((R * S).trace() - ref.trace) / scale);
    CHECK(std::abs(info.trace - ref.trace) <= 1e-12 * scale);
    CHECK(std::abs(R.determinant() - 1.0) < 1e-14);
    if (ref.gap > 1e-5 * scale) {  // unique and well conditioned: the rotations agree
      ++compared;
      worst_R = std::max(worst_R, max_abs(R - ref.R));
    }
  }
  INFO("reflections " << reflections << ", compared " << compared << ", fast path " << fast);
  CHECK(reflections > 4000);  // about half the Gaussian matrices have det < 0
  CHECK(compared > 9900);
  CHECK(worst_R < 1e-10);
  CHECK(worst_trace < 1e-13);
}

TEST_CASE("Horn's rotor on rank-deficient covariances: flat (rank 2) unique, collinear (rank 1) a family",
          "[ga][rotation]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.01, 2.0);
  double worst_flat = 0, worst_collinear_trace = 0, worst_family = 0;
  for (int t = 0; t < 2500; ++t) {
    const Eigen::Matrix3d U = random_rotation(rng), V = random_rotation(rng);
    // Rank 2 (a flat cell): unique best rotation, gap 2 σ2 > 0.
    {
      const Eigen::Matrix3d S = U * Eigen::Vector3d(u(rng) + 1.0, u(rng), 0.0).asDiagonal() * V.transpose();
      const SvdAnswer ref = svd_rotation(S);
      const ga::Rot warm = t % 2 ? random_rotor(rng) : ga::Rot(1, 0, 0, 0);
      RotationInfo info;
      const Eigen::Matrix3d R = rotation_matrix(best_rotation(S, warm, &info));
      CHECK(info.unique);
      worst_flat = std::max(worst_flat, max_abs(R - ref.R));
    }
    // A planar ARAP cell: rest edges in a plane, deformed by a rotation Q: exactly Q comes back.
    {
      const Eigen::Matrix3d Q = random_rotation(rng);
      Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
      for (int j = 0; j < 6; ++j) {
        const double phi = 2 * M_PI * j / 6 + 0.1 * u(rng);
        const Eigen::Vector3d v = U * Eigen::Vector3d(std::cos(phi), std::sin(phi), 0.0);
        S += u(rng) * v * (Q * v).transpose();
      }
      const Eigen::Matrix3d R = rotation_matrix(best_rotation(S));
      worst_flat = std::max(worst_flat, max_abs(R - Q));
    }
    // Rank 1 (collinear cell): every rotation taking a to the direction of b is optimal; the one
    // nearest to the warm rotor is returned — from the identity, the minimal rotation a -> b.
    {
      const Eigen::Vector3d a = U.col(0) * u(rng), b = V.col(0) * u(rng);
      const Eigen::Matrix3d S = a * b.transpose();
      RotationInfo info;
      const ga::Rot q = best_rotation(S, ga::Rot(1, 0, 0, 0), &info);
      const Eigen::Matrix3d R = rotation_matrix(q);
      CHECK_FALSE(info.unique);
      worst_collinear_trace =
          std::max(worst_collinear_trace, std::abs((R * S).trace() - svd_rotation(S).trace) / S.norm());
      const Eigen::Matrix3d minimal = Eigen::Quaterniond::FromTwoVectors(a, b).toRotationMatrix();
      worst_family = std::max(worst_family, max_abs(R - minimal));
      // From another warm rotor: still optimal, and no farther from the warm rotor than the
      // member obtained by composing the warm rotor's own residual (optimality of the projection).
      const ga::Rot w = random_rotor(rng);
      const ga::Rot qw = best_rotation(S, w);
      CHECK(std::abs((rotation_matrix(qw) * S).trace() - S.norm()) <= 1e-12 * S.norm());
      const double cw = std::abs(qw.w() * w.w() + qw.x() * w.x() + qw.y() * w.y() + qw.z() * w.z());
      CHECK(cw >= std::abs(q.w() * w.w() + q.x() * w.x() + q.y() * w.y() + q.z() * w.z()) - 1e-12);
    }
  }
  CHECK(worst_flat < 1e-10);
  CHECK(worst_collinear_trace < 1e-13);
  CHECK(worst_family < 1e-10);
}

TEST_CASE("Horn's rotor: reflection ties, zero covariance, and warm-started exact rotations",
          "[ga][rotation]") {
  std::mt19937 rng(5);
  // S = U diag(2, 1, −1)ᵀ-like with det < 0 and σ2 = σ3: a one-parameter family, energy still optimal.
  for (int t = 0; t < 200; ++t) {
    const Eigen::Matrix3d U = random_rotation(rng), V = random_rotation(rng);
    const Eigen::Matrix3d S = U * Eigen::Vector3d(2.0, 1.0, 1.0).asDiagonal() *
                              Eigen::Vector3d(1, 1, -1).asDiagonal() * V.transpose();
    const SvdAnswer ref = svd_rotation(S);
    const Eigen::Matrix3d R = rotation_matrix(best_rotation(S, random_rotor(rng)));
    CHECK(ref.gap < 1e-12);
    CHECK(std::abs((R * S).trace() - ref.trace) <= 1e-12 * S.norm());
  }
  // S = 0: every rotation is optimal; the warm rotor comes back.
  const ga::Rot w = random_rotor(rng);
  const ga::Rot q = best_rotation(Eigen::Matrix3d::Zero(), w);
  CHECK(std::abs(q.w() - w.w()) + std::abs(q.x() - w.x()) + std::abs(q.y() - w.y()) +
            std::abs(q.z() - w.z()) ==
        0.0);
  // Warm start at (near) the answer: the fast path answers in ≤ 3 Newton steps and agrees with a cold start.
  int fast = 0;
  for (int t = 0; t < 1000; ++t) {
    const Eigen::Matrix3d Q = random_rotation(rng);
    Eigen::Matrix3d P = random_matrix(rng);
    const Eigen::Matrix3d S = (P * P.transpose() + 0.5 * Eigen::Matrix3d::Identity()) * Q.transpose();
    const ga::Rot cold = best_rotation(S);
    const ga::Rot near = ga::exp(ga::Biv(1e-3, -2e-3, 1e-3)) * cold;
    RotationInfo info;
    const ga::Rot warm = best_rotation(S, near, &info);
    fast += info.fast && info.steps <= 3;
    CHECK(max_abs(rotation_matrix(warm) - rotation_matrix(cold)) < 1e-12);
    CHECK(max_abs(rotation_matrix(cold) - Q) < 1e-10);
  }
  CHECK(fast == 1000);
}

TEST_CASE("closest_rotation is the rotation of the polar decomposition M = R P", "[ga][rotation]") {
  std::mt19937 rng(17);
  for (int t = 0; t < 500; ++t) {
    const Eigen::Matrix3d M = random_matrix(rng);
    // Independent: R = U diag(1, 1, det(U Vᵀ)) Vᵀ from M = U Σ Vᵀ, the proper rotation nearest to M.
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
    const double d = (U * V.transpose()).determinant() > 0 ? 1.0 : -1.0;
    const Eigen::Matrix3d R_svd = U * Eigen::Vector3d(1, 1, d).asDiagonal() * V.transpose();
    const Eigen::Matrix3d R = closest_rotation(M);
    INFO("trial " << t << ", det M = " << M.determinant());
    CHECK(max_abs(R - R_svd) <= 1e-9);
    CHECK(std::abs(R.determinant() - 1.0) <= 1e-12);
    if (d > 0) {  // P = Rᵀ M is symmetric positive definite for det M > 0
      const Eigen::Matrix3d P = R.transpose() * M;
      CHECK(max_abs(P - P.transpose()) <= 1e-9 * M.norm());
      CHECK(
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(0.5 * (P + P.transpose())).eigenvalues().minCoeff() >
          0);
    }
  }
}

TEST_CASE("best_similarity: scale tr(R S) / sum w|v|^2 recovers s R from exact data", "[ga][rotation]") {
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0.2, 3.0);
  for (int t = 0; t < 200; ++t) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const double s = u(rng);
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    double rest = 0;
    for (int j = 0; j < 5; ++j) {
      const Eigen::Vector3d v(g(rng), g(rng), g(rng));
      const double w = u(rng);
      S += w * v * (s * R * v).transpose();
      rest += w * v.squaredNorm();
    }
    const Similarity fit = best_similarity(S, rest);
    CHECK(fit.scale == Approx(s).epsilon(1e-12));
    CHECK(max_abs(rotation_matrix(fit.rotor) - R) <= 1e-10);
  }
  // A reflected cell: the best similarity is a proper rotation with tr(R S) = σ1 + σ2 − σ3 (≥ 0 here).
  const Eigen::Matrix3d S = Eigen::Vector3d(2.0, 1.5, -1.0).asDiagonal();
  const Similarity fit = best_similarity(S, 4.0);
  CHECK(fit.scale == Approx((2.0 + 1.5 - 1.0) / 4.0).epsilon(1e-12));
  // No rest extent: scale 0, not a division by zero.
  CHECK(best_similarity(S, 0.0).scale == 0.0);
}

TEST_CASE("best_rotations fits a batch as the single fit does and counts the fallbacks", "[ga][rotation]") {
  std::mt19937 rng(9);
  std::vector<Eigen::Matrix3d> S(2000);
  std::vector<ga::Rot> rotors(S.size(), ga::Rot(1, 0, 0, 0));
  for (size_t k = 0; k < S.size(); ++k) S[k] = random_matrix(rng);
  // Rank-1 covariances (collinear cells) have a family of best rotations: the Jacobi fallback.
  for (size_t k = 0; k < 10; ++k) S[k] = Eigen::Vector3d(1, 2, 3) * Eigen::Vector3d(0, 1, 0).transpose();
  const long fallback = best_rotations(S, rotors);
  long expected = 0;
  for (size_t k = 0; k < S.size(); ++k) {
    RotationInfo info;
    const ga::Rot q = best_rotation(S[k], ga::Rot(1, 0, 0, 0), &info);
    expected += !info.fast;
    CHECK(std::abs(q.w() - rotors[k].w()) + std::abs(q.x() - rotors[k].x()) +
              std::abs(q.y() - rotors[k].y()) + std::abs(q.z() - rotors[k].z()) ==
          0.0);
  }
  CHECK(fallback == expected);
  CHECK(fallback >= 10);
}

}  // namespace test_rotor_fit

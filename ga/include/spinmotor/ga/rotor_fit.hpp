#pragma once
// The closest rotation and similarity fits: the one place the project fits a 3×3 rotation (ARAP's
// rotors, the pose-keeping cleanup's vertex cells, Direct Delta Mush, rigid alignments, the polar part
// of a skinning matrix). Horn's quaternion method (Horn 1987, "Closed-form solution of absolute
// orientation using unit quaternions", §4; CGA paper §VII).
//
// Given a 3×3 covariance S = Σ_j w_j v_j v'_jᵀ (v rest, v' deformed edge vectors), the rotation
// R ∈ SO(3) that minimises Σ_j w_j |v'_j − R v_j|² maximises tr(R S) = Σ_j w_j v'_j·(R v_j). For a unit
// quaternion q (R v = q v q̄, ga::Rot) tr(R(q) S) = qᵀ N(S) q with Horn's symmetric 4×4 matrix N(S)
// (horn_matrix), so the best rotor is the eigenvector of the largest eigenvalue of N(S), and that
// eigenvalue is max tr(R S) = σ1 + σ2 + sign(det S) σ3 (σ the singular values of S). The closest
// rotation to a matrix M (the rotation of its polar decomposition M = R P) is best_rotation(Mᵀ).
//
// This is the SVD answer R = V diag(1, 1, det(V Uᵀ)) Uᵀ (S = U Σ Vᵀ): always a proper rotation (the
// closest rotation when S is a reflection, never the reflection itself). It is unique iff the top
// eigenvalue of N is simple, i.e. σ2 + sign(det S) σ3 > 0: covariances of rank 2 (flat cells) have a
// unique best rotation; rank ≤ 1 (collinear or empty cells) and the reflection ties σ2 = σ3 with
// det S < 0 have a family of them. In that case best_rotation returns the member of the family
// nearest to the warm-start rotor (the normalised projection of the warm quaternion onto the top
// eigenspace; the warm rotor itself when S = 0): a deterministic choice that keeps iterated fits
// continuous, and optimal like every member of the family. The rank-deficient fallback is inside the fit.
//
// The best similarity s R of the same cell (scale s ≥ 0, R as above) minimises Σ w |v' − s R v|²:
// s = max(tr(R S), 0) / Σ w |v|² (best_similarity).
//
// Algorithm (measured in bench_arap, BM_Rotation*):
//   fast path   in the frame of the warm rotor q0 (T = R(q0) S, N = N(T) = [a b; b B]), the top
//               eigenvalue λ of N is the root above λ_max(B) of the secular equation
//               f(λ) = λ − a − bᵀ(λI − B)⁻¹b = 0, f concave increasing there: Newton from λ = a (a
//               lower bound; accepted only when aI − B is positive definite) climbs monotonically to
//               the root, quadratically; the eigenvector is (1, (λI − B)⁻¹b). With a warm start from
//               the previous iteration b is small and 1–3 steps of a 3×3 LDLᵀ solve suffice.
//   fallback    cyclic Jacobi on the 4×4 N (accurate for every spectrum), then the cluster of
//               eigenvalues within 1e-10·|S|_F of the top one is treated as one eigenspace.
// Both paths are allocation-free, inline, and leave q with the sign nearest to the warm rotor.
// best_rotations fits a batch (one covariance per cell, warm-started from the rotors given), in parallel.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <span>

#include "spinmotor/core/parallel.hpp"
#include "spinmotor/ga/products.hpp"
#include "spinmotor/ga/types.hpp"

namespace spinmotor::ga {

/// Horn's matrix N(S) (§VII): inputs S (3×3, S = Σ w v v'ᵀ). Output: symmetric 4×4 N with
/// qᵀ N q = tr(R(q) S) for every unit quaternion q = (w, x, y, z) (the order of ga::Rot).
inline Eigen::Matrix4d horn_matrix(const Eigen::Matrix3d& S) {
  const double xx = S(0, 0), xy = S(0, 1), xz = S(0, 2), yx = S(1, 0), yy = S(1, 1), yz = S(1, 2),
               zx = S(2, 0), zy = S(2, 1), zz = S(2, 2);
  Eigen::Matrix4d N;
  N << xx + yy + zz, yz - zy, zx - xz, xy - yx,  //
      yz - zy, xx - yy - zz, xy + yx, zx + xz,   //
      zx - xz, xy + yx, -xx + yy - zz, yz + zy,  //
      xy - yx, zx + xz, yz + zy, -xx - yy + zz;
  return N;
}

/// The rotation matrix of a unit rotor (R v = q v q̄ = ga::rotate(q, v)).
inline Eigen::Matrix3d rotation_matrix(const ga::Rot& q) {
  const double w = q.w(), x = q.x(), y = q.y(), z = q.z();
  const double tx = 2 * x, ty = 2 * y, tz = 2 * z;
  const double twx = tx * w, twy = ty * w, twz = tz * w, txx = tx * x, txy = ty * x, txz = tz * x,
               tyy = ty * y, tyz = tz * y, tzz = tz * z;
  Eigen::Matrix3d R;
  R << 1 - (tyy + tzz), txy - twz, txz + twy,  //
      txy + twz, 1 - (txx + tzz), tyz - twx,   //
      txz - twy, tyz + twx, 1 - (txx + tyy);
  return R;
}

/// What best_rotation did (for tests and benchmarks).
struct RotationInfo {
  bool fast = false;   ///< the warm-started Newton path answered (else the Jacobi fallback)
  bool unique = true;  ///< the top eigenvalue of N is simple (the best rotation is unique)
  int steps = 0;       ///< Newton steps (fast path) or Jacobi sweeps (fallback)
  double trace = 0.0;  ///< max tr(R S), the top eigenvalue of N(S)
};

namespace detail {

/// Cyclic Jacobi on a symmetric 4×4 (a, in place; v accumulates the eigenvectors as columns).
/// Returns the number of sweeps.
inline int jacobi4(double a[4][4], double v[4][4], double scale) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) v[i][j] = i == j ? 1.0 : 0.0;
  const double tol = std::numeric_limits<double>::epsilon() * scale;
  int sweep = 0;
  for (; sweep < 32; ++sweep) {
    double off = 0.0;
    for (int p = 0; p < 3; ++p)
      for (int q = p + 1; q < 4; ++q) off += a[p][q] * a[p][q];
    if (off <= tol * tol) break;
    for (int p = 0; p < 3; ++p)
      for (int q = p + 1; q < 4; ++q) {
        const double apq = a[p][q];
        if (std::abs(apq) <= 1e-3 * tol) continue;
        // Rotation zeroing a[p][q] (the smaller angle; Numerical Recipes §11.1).
        const double theta = (a[q][q] - a[p][p]) / (2.0 * apq);
        const double t = std::copysign(1.0, theta) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        a[p][p] -= t * apq;
        a[q][q] += t * apq;
        a[p][q] = a[q][p] = 0.0;
        for (int r = 0; r < 4; ++r) {
          if (r != p && r != q) {
            const double arp = a[r][p], arq = a[r][q];
            a[r][p] = a[p][r] = c * arp - s * arq;
            a[r][q] = a[q][r] = s * arp + c * arq;
          }
          const double vrp = v[r][p], vrq = v[r][q];
          v[r][p] = c * vrp - s * vrq;
          v[r][q] = s * vrp + c * vrq;
        }
      }
  }
  return sweep;
}

/// Top eigenvector of the symmetric 4×4 N by Jacobi; a cluster of top eigenvalues (within tol) is
/// one eigenspace, from which the vector nearest to e0 is returned. Writes the top eigenvalue.
inline Eigen::Vector4d top_eigenvector_jacobi(const Eigen::Matrix4d& N, double scale, double& lambda,
                                              bool& unique, int& sweeps) {
  double a[4][4], v[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) a[i][j] = N(i, j);
  sweeps = jacobi4(a, v, scale);
  int k = 0;
  for (int i = 1; i < 4; ++i)
    if (a[i][i] > a[k][k]) k = i;
  lambda = a[k][k];
  const double tol = 1e-10 * scale;
  Eigen::Vector4d proj = Eigen::Vector4d::Zero();
  int cluster = 0;
  for (int i = 0; i < 4; ++i)
    if (lambda - a[i][i] <= tol) {
      ++cluster;
      for (int r = 0; r < 4; ++r) proj[r] += v[0][i] * v[r][i];  // (v_i · e0) v_i
    }
  unique = cluster == 1;
  const double pn = proj.norm();
  if (!unique && pn > 1e-8) return proj / pn;
  return Eigen::Vector4d(v[0][k], v[1][k], v[2][k], v[3][k]);
}

}  // namespace detail

/// Inputs: S (3×3 covariance Σ w v v'ᵀ, finite), warm (a unit rotor: the previous answer, or the
/// identity). Output: the unit rotor q maximising tr(R(q) S) (see the header comment for the
/// non-unique case), with the sign that makes q·warm ≥ 0. `info` (optional) receives the path taken
/// and max tr(R S). For S = 0 returns warm.
inline ga::Rot best_rotation(const Eigen::Matrix3d& S, const ga::Rot& warm = ga::Rot(1.0, 0.0, 0.0, 0.0),
                             RotationInfo* info = nullptr) {
  const double scale = S.norm();
  RotationInfo local;
  RotationInfo& out = info ? *info : local;
  out = RotationInfo{};
  if (!(scale > 0.0)) {
    out.unique = false;
    return warm;
  }
  const double wn =
      std::sqrt(warm.w() * warm.w() + warm.x() * warm.x() + warm.y() * warm.y() + warm.z() * warm.z());
  const ga::Rot q0 = wn > 0.0 ? ga::Rot(warm.w() / wn, warm.x() / wn, warm.y() / wn, warm.z() / wn)
                              : ga::Rot(1.0, 0.0, 0.0, 0.0);
  // Work in the warm frame: R = R' R(q0), tr(R S) = tr(R' T) with T = R(q0) S, and R' ≈ I.
  const Eigen::Matrix3d T = rotation_matrix(q0) * S;
  const double xx = T(0, 0), xy = T(0, 1), xz = T(0, 2), yx = T(1, 0), yy = T(1, 1), yz = T(1, 2),
               zx = T(2, 0), zy = T(2, 1), zz = T(2, 2);
  // N(T) = [a bᵀ; b B] (horn_matrix).
  const double a = xx + yy + zz;
  const double b0 = yz - zy, b1 = zx - xz, b2 = xy - yx;
  const double B00 = xx - yy - zz, B11 = -xx + yy - zz, B22 = -xx - yy + zz;
  const double B01 = xy + yx, B02 = zx + xz, B12 = yz + zy;
  Eigen::Vector4d qp;
  // Fast path: Newton on the secular equation from λ = a (see the header comment).
  {
    double lambda = a, y0 = 0, y1 = 0, y2 = 0;
    bool ok = false;
    int step = 0;
    for (; step < 24; ++step) {
      // LDLᵀ of M = λI − B (symmetric 3×3); positive definite iff λ > λ_max(B).
      const double m00 = lambda - B00, m11 = lambda - B11, m22 = lambda - B22;
      const double d0 = m00;
      if (!(d0 > 0.0)) break;
      const double l10 = -B01 / d0, l20 = -B02 / d0;
      const double d1 = m11 + B01 * l10;  // m11 − l10² d0
      if (!(d1 > 0.0)) break;
      const double l21 = (-B12 - l20 * d0 * l10) / d1;
      const double d2 = m22 - l20 * l20 * d0 - l21 * l21 * d1;
      if (!(d2 > 0.0)) break;
      // Accept only a well-separated top eigenvalue: λ_min(M) ≥ det M / (tr M)² ≥ 1e-8 |S|.
      const double trM = m00 + m11 + m22;
      if (!(d0 * d1 * d2 >= 1e-8 * scale * trM * trM)) break;
      // y = M⁻¹ b.
      const double z0 = b0, z1 = b1 - l10 * z0, z2 = b2 - l20 * z0 - l21 * z1;
      y2 = z2 / d2;
      y1 = z1 / d1 - l21 * y2;
      y0 = z0 / d0 - l10 * y1 - l20 * y2;
      const double f = lambda - a - (b0 * y0 + b1 * y1 + b2 * y2);  // ≤ 0 left of the root
      const double fp = 1.0 + y0 * y0 + y1 * y1 + y2 * y2;
      const double dl = -f / fp;
      if (!(dl <= 4.0 * std::numeric_limits<double>::epsilon() * scale)) {
        lambda += std::max(dl, 0.0);
        continue;
      }
      ok = true;
      out.trace = lambda;
      break;
    }
    if (ok) {
      qp = Eigen::Vector4d(1.0, y0, y1, y2);
      out.fast = true;
      out.steps = step + 1;
    }
  }
  if (!out.fast) {
    Eigen::Matrix4d N;
    N << a, b0, b1, b2, b0, B00, B01, B02, b1, B01, B11, B12, b2, B02, B12, B22;
    double lambda;
    qp = detail::top_eigenvector_jacobi(N, scale, lambda, out.unique, out.steps);
    out.trace = lambda;
  }
  if (qp[0] < 0.0) qp = -qp;  // nearest sign to the warm rotor: q·q0 = q'_w
  qp.normalize();
  // q = q' q0 (Hamilton product = geometric product of rotors): R(q) = R(q') R(q0).
  ga::Rot q = ga::Rot(qp[0], qp[1], qp[2], qp[3]) * q0;
  const double n = std::sqrt(q.w() * q.w() + q.x() * q.x() + q.y() * q.y() + q.z() * q.z());
  return ga::Rot(q.w() / n, q.x() / n, q.y() / n, q.z() / n);
}

/// The best similarity s R (see the header comment): inputs S = Σ w v v'ᵀ, rest = Σ w |v|² (> 0), warm.
struct Similarity {
  ga::Rot rotor = ga::Rot(1.0, 0.0, 0.0, 0.0);
  double scale = 1.0;
};
inline Similarity best_similarity(const Eigen::Matrix3d& S, double rest,
                                  const ga::Rot& warm = ga::Rot(1.0, 0.0, 0.0, 0.0),
                                  RotationInfo* info = nullptr) {
  RotationInfo local;
  RotationInfo& out = info ? *info : local;
  Similarity s;
  s.rotor = best_rotation(S, warm, &out);
  s.scale = rest > 0 ? std::max(out.trace, 0.0) / rest : 0.0;
  return s;
}

/// The rotation of the polar decomposition M = R P (P symmetric positive semi-definite): the rotation
/// closest to M in the Frobenius norm, best_rotation(Mᵀ) (a proper rotation also when det M < 0).
inline Eigen::Matrix3d closest_rotation(const Eigen::Matrix3d& M) {
  return rotation_matrix(best_rotation(M.transpose()));
}

/// A batch of fits: rotors[k] = best_rotation(S[k], rotors[k]) (warm-started from what rotors holds),
/// in parallel. Returns the number of fits that took the Jacobi fallback (rank-deficient or clustered).
inline long best_rotations(std::span<const Eigen::Matrix3d> S, std::span<ga::Rot> rotors) {
  const long n = static_cast<long>(S.size());
  long fallback = 0;
#pragma omp parallel for schedule(static) reduction(+ : fallback) if (parallel::worth(n, parallel::kRotationFit))
  for (long k = 0; k < n; ++k) {
    RotationInfo info;
    rotors[k] = best_rotation(S[k], rotors[k], &info);
    fallback += !info.fast;
  }
  return fallback;
}

}  // namespace spinmotor::ga

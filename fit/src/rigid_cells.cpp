// Rigid cells: ARAP's spokes and spokes-and-rims (cells.hpp).
#include <algorithm>
#include <cmath>

#include "spinmotor/core/parallel.hpp"
#include "spinmotor/fit/cells.hpp"
#include "spinmotor/ga/rotor_fit.hpp"

namespace spinmotor::fit {

RigidCells RigidCells::bind(const RowMatrix3& P, const Eigen::MatrixXi& F,
                            const Eigen::SparseMatrix<double>& L, const Eigen::MatrixXd& C, Kind kind,
                            bool clamp) {
  RigidCells c;
  c.P_ = P;
  c.F_ = F;
  c.L_ = L;
  const int n = static_cast<int>(P.rows());
  c.build_one_ring();
  c.w_.setZero(c.off_[n]);
  c.kappa_.setZero(c.off_[n], 3);
  c.h_.setZero(c.off_[n], 3);
  c.h_self_.setZero(n, 3);
  c.a_rest_.setZero(n);
  if (kind == Kind::Spokes)
    c.bind_spokes(clamp);
  else
    c.bind_rims(clamp ? Eigen::MatrixXd(C.cwiseMax(0.0)) : C);
  c.assemble_global_matrix();
  c.energy_scale_ = c.a_rest_.cwiseAbs().sum();
  c.reset_rotors();
  return c;
}

void RigidCells::reset_rotors() {
  rot_.assign(P_.rows(), ga::Rot(1.0, 0.0, 0.0, 0.0));
  Rm_.assign(P_.rows(), Eigen::Matrix3d::Identity());
}

/// The one-ring CSR: the off-diagonal pattern of the cotangent Laplacian (rows sorted per column).
void RigidCells::build_one_ring() {
  const int n = static_cast<int>(P_.rows());
  off_.assign(n + 1, 0);
  for (int i = 0; i < n; ++i)
    for (Eigen::SparseMatrix<double>::InnerIterator it(L_, i); it; ++it)
      if (it.row() != i) ++off_[i + 1];
  for (int i = 0; i < n; ++i) off_[i + 1] += off_[i];
  nbr_.resize(off_[n]);
  for (int i = 0, k = 0; i < n; ++i)
    for (Eigen::SparseMatrix<double>::InnerIterator it(L_, i); it; ++it)
      if (it.row() != i) nbr_[k++] = static_cast<int>(it.row());
}

/// The CSR slot of neighbour j in vertex i's one-ring.
int RigidCells::slot(int i, int j) const {
  const auto b = nbr_.begin() + off_[i], e = nbr_.begin() + off_[i + 1];
  return static_cast<int>(std::lower_bound(b, e, j) - nbr_.begin());
}

/// Eq. (9): cell i = its spokes (i, j), w_ij = −L_ij. S_i = Σ_j w_ij e_ij e'_ijᵀ = Σ_j κ_ij (x'_j − x'_i)ᵀ
/// with κ_ij = −w_ij e_ij; eq. (12): B_i = ½ Σ_j w_ij (R_i + R_j) e_ij.
void RigidCells::bind_spokes(bool clamp) {
  const int n = static_cast<int>(P_.rows());
  for (int i = 0; i < n; ++i) {
    int k = off_[i];
    for (Eigen::SparseMatrix<double>::InnerIterator it(L_, i); it; ++it) {
      if (it.row() == i) continue;
      const double w = clamp ? std::max(-it.value(), 0.0) : -it.value();
      const Eigen::RowVector3d e = P_.row(i) - P_.row(it.row());
      w_[k] = w;
      kappa_.row(k) = -w * e;
      h_.row(k) = 0.5 * w * e;
      h_self_.row(i) += 0.5 * w * e;
      a_rest_[i] += w * e.squaredNorm();
      ++k;
    }
  }
}

/// Spokes and rims: cell a = every face t ∋ a with its three edges e_k (opposite corner k, e_k =
/// x_{k+2} − x_{k+1}) weighted c_k = ½ cot of corner k (C, clamped if asked). Per face
/// Σ_k c_k e_k e'_kᵀ = Σ_k G_k x'_kᵀ with G_k = W_{k+1} − W_{k+2}, W_k = c_k e_k (Σ_k G_k = 0), and G_k is
/// also the face's share of (L x) at corner k, so B_a = ⅓ Σ_{t ∋ a} (R_t0 + R_t1 + R_t2) G_{t,k(a)}.
void RigidCells::bind_rims(const Eigen::MatrixXd& C) {
  const int n = static_cast<int>(P_.rows());
  const Eigen::Index m = F_.rows();
  const RowMatrix3& P = P_;
  const Eigen::MatrixXi& F = F_;
  rim_off_.assign(n + 1, 0);
  for (Eigen::Index t = 0; t < m; ++t)
    for (int k = 0; k < 3; ++k) ++rim_off_[F(t, k) + 1];
  for (int i = 0; i < n; ++i) rim_off_[i + 1] += rim_off_[i];
  const int rims = rim_off_[n];
  rim_l_.resize(rims);
  rim_m_.resize(rims);
  rim_c_.resize(rims);
  std::vector<int> cursor(rim_off_.begin(), rim_off_.end() - 1);
  for (Eigen::Index t = 0; t < m; ++t) {
    Eigen::Matrix3d W;  // rows W_k
    double face_energy = 0.0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::RowVector3d e = P.row(F(t, (k + 2) % 3)) - P.row(F(t, (k + 1) % 3));
      W.row(k) = C(t, k) * e;
      face_energy += C(t, k) * e.squaredNorm();
    }
    Eigen::Matrix3d G;
    for (int k = 0; k < 3; ++k) G.row(k) = W.row((k + 1) % 3) - W.row((k + 2) % 3);
    for (int k = 0; k < 3; ++k) {
      const int a = F(t, k);
      for (int kk = 1; kk <= 2; ++kk) {
        const int kl = (k + kk) % 3, l = F(t, kl);
        const int s = slot(a, l);
        kappa_.row(s) += G.row(kl);
        h_.row(s) += G.row(k) / 3.0;
        w_[s] += C(t, 3 - k - kl);  // edge (a, l) is opposite the third corner
      }
      h_self_.row(a) += G.row(k) / 3.0;
      a_rest_[a] += face_energy;
      const int r = cursor[a]++;
      rim_l_[r] = F(t, (k + 1) % 3);
      rim_m_[r] = F(t, (k + 2) % 3);
      rim_c_[r] = C(t, k);
    }
  }
}

/// The global matrix from the cells' weights (eq. 12: Σ_j w_ij (x'_i − x'_j) = B_i), in place in L_.
void RigidCells::assemble_global_matrix() {
  const int n = static_cast<int>(P_.rows());
  for (int i = 0; i < n; ++i) {
    int k = off_[i];
    double diag = 0.0;
    double* diag_value = nullptr;
    for (Eigen::SparseMatrix<double>::InnerIterator it(L_, i); it; ++it) {
      if (it.row() == i) {
        diag_value = &it.valueRef();
        continue;
      }
      const int j = static_cast<int>(it.row());
      // Symmetric to the last bit: the lower-triangle weight is taken from the smaller index's slot.
      const double w = j > i ? w_[k] : w_[slot(j, i)];
      it.valueRef() = -w;
      diag += w;
      ++k;
    }
    if (diag_value) *diag_value = diag;
  }
  L_.makeCompressed();
}

double RigidCells::cell_energy_direct(Eigen::Index i, const Eigen::Matrix3d& R, const RowMatrix3& X) const {
  double E = 0.0;
  for (int k = off_[i]; k < off_[i + 1]; ++k) {
    const int j = nbr_[k];
    const Eigen::Vector3d r = (X.row(j) - X.row(i)).transpose() - R * (P_.row(j) - P_.row(i)).transpose();
    E += w_[k] * r.squaredNorm();
  }
  if (!rim_off_.empty())
    for (int k = rim_off_[i]; k < rim_off_[i + 1]; ++k) {
      const int l = rim_l_[k], mm = rim_m_[k];
      const Eigen::Vector3d r = (X.row(mm) - X.row(l)).transpose() - R * (P_.row(mm) - P_.row(l)).transpose();
      E += rim_c_[k] * r.squaredNorm();
    }
  return E;
}

namespace {

/// S_i = Σ_k κ_k (x'_j − x'_i)ᵀ and a'_i = Σ_k w_k |x'_j − x'_i|² + Σ_rims c |x'_m − x'_l|².
[[gnu::always_inline]] inline void cell_covariance(Eigen::Index i, const int* off, const int* nbr,
                                                   const double* w, const double* kappa, const int* rim_off,
                                                   const int* rim_l, const int* rim_m, const double* rim_c,
                                                   const double* X, Eigen::Matrix3d& S, double& ap) {
  const double x0 = X[3 * i], x1 = X[3 * i + 1], x2 = X[3 * i + 2];
  double s00 = 0, s01 = 0, s02 = 0, s10 = 0, s11 = 0, s12 = 0, s20 = 0, s21 = 0, s22 = 0, q = 0;
  for (int k = off[i]; k < off[i + 1]; ++k) {
    const double* xj = X + 3 * static_cast<Eigen::Index>(nbr[k]);
    const double d0 = xj[0] - x0, d1 = xj[1] - x1, d2 = xj[2] - x2;
    const double k0 = kappa[3 * k], k1 = kappa[3 * k + 1], k2 = kappa[3 * k + 2];
    s00 += k0 * d0, s01 += k0 * d1, s02 += k0 * d2;
    s10 += k1 * d0, s11 += k1 * d1, s12 += k1 * d2;
    s20 += k2 * d0, s21 += k2 * d1, s22 += k2 * d2;
    q += w[k] * (d0 * d0 + d1 * d1 + d2 * d2);
  }
  if (rim_off)
    for (int k = rim_off[i]; k < rim_off[i + 1]; ++k) {
      const double* xl = X + 3 * static_cast<Eigen::Index>(rim_l[k]);
      const double* xm = X + 3 * static_cast<Eigen::Index>(rim_m[k]);
      const double e0 = xm[0] - xl[0], e1 = xm[1] - xl[1], e2 = xm[2] - xl[2];
      q += rim_c[k] * (e0 * e0 + e1 * e1 + e2 * e2);
    }
  S << s00, s01, s02, s10, s11, s12, s20, s21, s22;
  ap = q;
}

}  // namespace

double RigidCells::fit(const RowMatrix3& X, Eigen::Index& fallbacks) {
  const Eigen::Index n = P_.rows();
  const int* rim_off = rim_off_.empty() ? nullptr : rim_off_.data();
  double total = 0.0;
  Eigen::Index jacobi = 0;
#pragma omp parallel for schedule(static) reduction(+ : total, jacobi) if (parallel::worth(n, parallel::kRotationFit))
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Matrix3d S;
    double ap;
    cell_covariance(i, off_.data(), nbr_.data(), w_.data(), kappa_.data(), rim_off, rim_l_.data(),
                    rim_m_.data(), rim_c_.data(), X.data(), S, ap);
    ga::RotationInfo info;
    const ga::Rot q = ga::best_rotation(S, rot_[i], &info);  // §VII: Horn's quaternion, largest eigenvector
    jacobi += !info.fast;
    const Eigen::Matrix3d R = ga::rotation_matrix(q);
    const double trRS = R.cwiseProduct(S.transpose()).sum();
    // Cell energy Σ w |e' − R e|² = Σ w |e'|² + Σ w |e|² − 2 tr(R S); term by term where that cancels.
    double E = a_rest_[i] + ap - 2.0 * trRS;
    if (!(E > 1e-6 * (std::abs(a_rest_[i]) + std::abs(ap)))) E = cell_energy_direct(i, R, X);
    rot_[i] = q;
    Rm_[i] = R;
    total += E;
  }
  fallbacks += jacobi;
  return total;
}

void RigidCells::rhs(const Eigen::VectorXi& rows, RowMatrix3& B) const {
  const Eigen::Index nf = rows.size();
  // Eq. (12): B_i = R_i h_i + Σ_j R_j h_ij for the vertex i of row k.
#pragma omp parallel for schedule(static) if (parallel::worth(nf, parallel::kRotationFit))
  for (Eigen::Index k = 0; k < nf; ++k) {
    const int i = rows[k];
    Eigen::Vector3d b = Rm_[i] * h_self_.row(i).transpose();
    for (int s = off_[i]; s < off_[i + 1]; ++s) b.noalias() += Rm_[nbr_[s]] * h_.row(s).transpose();
    B(k, 0) = b[0], B(k, 1) = b[1], B(k, 2) = b[2];
  }
}

double RigidCells::energy(const RowMatrix3& X) const {
  const Eigen::Index n = P_.rows();
  const int* rim_off = rim_off_.empty() ? nullptr : rim_off_.data();
  double total = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : total) if (parallel::worth(n, parallel::kRotationFit))
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Matrix3d S;
    double ap;
    cell_covariance(i, off_.data(), nbr_.data(), w_.data(), kappa_.data(), rim_off, rim_l_.data(),
                    rim_m_.data(), rim_c_.data(), X.data(), S, ap);
    total += cell_energy_direct(i, ga::rotation_matrix(ga::best_rotation(S)), X);
  }
  return total;
}

}  // namespace spinmotor::fit

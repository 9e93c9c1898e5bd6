#include "spinmotor/spin/dirac_assembly.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/linalg/graph_ordering.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "spinmotor/spin/quaternion_matrix.hpp"

namespace spinmotor {

namespace {

using RowQuats = Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>;

void check_rho(const Eigen::VectorXd& rho, Eigen::Index m) {
  if (rho.size() != m) {
    std::ostringstream s;
    s << "DiracAssembly: rho has " << rho.size() << " values for " << m << " faces";
    throw Error(s.str());
  }
}

}  // namespace

DiracAssembly::DiracAssembly(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Ordering ordering,
                             const Eigen::VectorXi& reduced_vertices,
                             const std::vector<Eigen::Matrix<double, 4, 2>>& reductions)
    : n_(V.rows()), m_(F.rows()), F_(F) {
  require_ordering(ordering, kVertexOrderings, "DiracAssembly");
  if (V.cols() != 3 || F.cols() != 3) throw Error("DiracAssembly: V and F must have 3 columns");
  if (m_ == 0) throw Error("DiracAssembly: the mesh has no faces");
  if (reduced_vertices.size() != static_cast<Eigen::Index>(reductions.size()))
    throw Error("DiracAssembly: one 4x2 reduction block is needed per reduced vertex");
  init_face_geometry(V, F);
  init_edges(F);
  init_vertex_corners(F);
  init_ordering(ordering);
  init_unknowns(reduced_vertices, reductions);
  init_neighbours();
}

void DiracAssembly::init_face_geometry(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  area_ = spinmotor::face_areas(V, F);  // also checks indices and finiteness
  normal_.resize(m_, 3);
  edge_vec_.resize(m_, 9);
  vertex_area_ = Eigen::VectorXd::Zero(n_);
  for (Eigen::Index f = 0; f < m_; ++f) {
    const Eigen::Vector3d x0 = V.row(F(f, 0)), x1 = V.row(F(f, 1)), x2 = V.row(F(f, 2));
    const Eigen::Vector3d e[3] = {x2 - x1, x0 - x2, x1 - x0};  // opposite corners 0, 1, 2 (CCW)
    const Eigen::Vector3d cr = (x1 - x0).cross(x2 - x0);
    const double len = cr.norm();
    const double lmax = std::max({e[0].squaredNorm(), e[1].squaredNorm(), e[2].squaredNorm()});
    if (!(len > kDegenerateFace * lmax)) {
      std::ostringstream s;
      s << "DiracAssembly: face " << f << " (" << F(f, 0) << ", " << F(f, 1) << ", " << F(f, 2)
        << ") is degenerate (area " << area_[f] << ")";
      throw Error(s.str());
    }
    normal_.row(f) = cr / len;
    for (int c = 0; c < 3; ++c) {
      edge_vec_.block<1, 3>(f, 3 * c) = e[c].transpose();
      vertex_area_[F(f, c)] += area_[f] / 3.0;
    }
  }
  for (Eigen::Index i = 0; i < n_; ++i)
    if (!(vertex_area_[i] > 0)) {
      std::ostringstream s;
      s << "DiracAssembly: vertex " << i << " is in no face (remove unreferenced vertices first)";
      throw Error(s.str());
    }
}

void DiracAssembly::init_edges(const Eigen::MatrixXi& F) {
  const EdgeTopology topo = edge_topology(F);
  E_ = topo.E;
  EF_offset_ = topo.EF_offset;
  EF_face_ = topo.EF_face;
  const Eigen::Index ne = E_.rows();
  EF_sign_.resize(EF_face_.size());
  EF_corner_.resize(EF_face_.size());
  for (Eigen::Index e = 0; e < ne; ++e)
    for (int k = EF_offset_[e]; k < EF_offset_[e + 1]; ++k) {
      const int f = EF_face_[k];
      int c = -1;
      for (int cc = 0; cc < 3; ++cc)
        if (topo.FE(f, (cc + 2) % 3) == e) c = cc;  // the pair (c, c+1) is the edge opposite c+2
      const int a = F(f, c);
      EF_corner_[k] = c;
      EF_sign_[k] = a == E_(e, 0) ? 1 : -1;
    }
}

void DiracAssembly::init_vertex_corners(const Eigen::MatrixXi& F) {
  VF_offset_ = Eigen::VectorXi::Zero(n_ + 1);
  for (Eigen::Index f = 0; f < m_; ++f)
    for (int c = 0; c < 3; ++c) ++VF_offset_[F(f, c) + 1];
  for (Eigen::Index i = 0; i < n_; ++i) VF_offset_[i + 1] += VF_offset_[i];
  VF_corner_.resize(3 * m_);
  std::vector<int> fillp(VF_offset_.data(), VF_offset_.data() + n_);
  for (Eigen::Index f = 0; f < m_; ++f)
    for (int c = 0; c < 3; ++c) VF_corner_[fillp[F(f, c)]++] = static_cast<int>(3 * f + c);
}

void DiracAssembly::init_ordering(Ordering ordering) {
  // The vertex graph: full symmetric pattern with the diagonal, CSC; the columns are short, so each is
  // sorted by insertion.
  const Eigen::Index ne = E_.rows();
  std::vector<int> colptr(n_ + 1, 0);
  for (Eigen::Index e = 0; e < ne; ++e) ++colptr[E_(e, 0) + 1], ++colptr[E_(e, 1) + 1];
  for (Eigen::Index j = 0; j < n_; ++j) colptr[j + 1] += colptr[j] + 1;  // + the diagonal
  std::vector<int> rowind(colptr[n_]), fillp(colptr.begin(), colptr.end() - 1);
  for (Eigen::Index j = 0; j < n_; ++j) rowind[fillp[j]++] = static_cast<int>(j);
  for (Eigen::Index e = 0; e < ne; ++e) {
    rowind[fillp[E_(e, 0)]++] = E_(e, 1);
    rowind[fillp[E_(e, 1)]++] = E_(e, 0);
  }
  for (Eigen::Index j = 0; j < n_; ++j) {
    int* b = rowind.data() + colptr[j];
    int* en = rowind.data() + colptr[j + 1];
    for (int* a = b + 1; a < en; ++a)  // short columns: insertion sort
      for (int* c = a; c > b && c[-1] > c[0]; --c) std::swap(c[-1], c[0]);
  }
  order_ = graph_ordering(n_, colptr, rowind, ordering, "DiracAssembly");
  rank_.resize(n_);
  for (Eigen::Index k = 0; k < n_; ++k) rank_[order_[k]] = static_cast<int>(k);
}

void DiracAssembly::init_unknowns(const Eigen::VectorXi& reduced_vertices,
                                  const std::vector<Eigen::Matrix<double, 4, 2>>& reductions) {
  U_.assign(n_, Eigen::Matrix<double, 4, 2>::Zero());
  std::vector<int> dof(n_, 4);
  for (Eigen::Index r = 0; r < reduced_vertices.size(); ++r) {
    const int i = reduced_vertices[r];
    if (i < 0 || i >= n_) {
      std::ostringstream s;
      s << "DiracAssembly: reduced vertex " << i << " is outside [0, " << n_ << ")";
      throw Error(s.str());
    }
    if (dof[rank_[i]] == 2) {
      std::ostringstream s;
      s << "DiracAssembly: vertex " << i << " is listed twice among the reduced vertices";
      throw Error(s.str());
    }
    dof[rank_[i]] = 2;
    U_[rank_[i]] = reductions[r];
    reduced_ = true;
  }
  dof_offset_.assign(n_ + 1, 0);
  for (Eigen::Index k = 0; k < n_; ++k) dof_offset_[k + 1] = dof_offset_[k] + dof[k];
}

void DiracAssembly::init_neighbours() {
  const Eigen::Index ne = E_.rows();
  nb_offset_ = Eigen::VectorXi::Zero(n_ + 1);
  for (Eigen::Index e = 0; e < ne; ++e) ++nb_offset_[std::min(rank_[E_(e, 0)], rank_[E_(e, 1)]) + 1];
  for (Eigen::Index j = 0; j < n_; ++j) nb_offset_[j + 1] += nb_offset_[j];
  nb_vertex_.resize(ne);
  nb_edge_.resize(ne);
  nb_e0_is_row_.resize(ne);
  std::vector<int> fillp(nb_offset_.data(), nb_offset_.data() + n_);
  for (Eigen::Index e = 0; e < ne; ++e) {
    const int r0 = rank_[E_(e, 0)], r1 = rank_[E_(e, 1)];
    const int j = std::min(r0, r1), k = std::max(r0, r1);
    const int p = fillp[j]++;
    nb_vertex_[p] = k;
    nb_edge_[p] = static_cast<int>(e);
    nb_e0_is_row_[p] = r0 == k;
  }
  // Sort each vertex's neighbours by new index (a handful each: insertion sort, no allocation).
  for (Eigen::Index j = 0; j < n_; ++j)
    for (int a = nb_offset_[j] + 1; a < nb_offset_[j + 1]; ++a)
      for (int c = a; c > nb_offset_[j] && nb_vertex_[c - 1] > nb_vertex_[c]; --c) {
        std::swap(nb_vertex_[c - 1], nb_vertex_[c]);
        std::swap(nb_edge_[c - 1], nb_edge_[c]);
        std::swap(nb_e0_is_row_[c - 1], nb_e0_is_row_[c]);
      }
}

const Eigen::SparseMatrix<double>& DiracAssembly::pattern() const {
  const Eigen::Index N = dof_offset_[n_];
  if (pattern_.rows() == N && (N == 0 || pattern_.nonZeros() > 0)) return pattern_;
  std::vector<int> dof(static_cast<std::size_t>(n_));
  for (Eigen::Index j = 0; j < n_; ++j) dof[j] = static_cast<int>(dof_offset_[j + 1] - dof_offset_[j]);
  // Lower triangle: column c of vertex j's block holds rows c.. of its own block, then every row of
  // each neighbour k > j (new order).
  pattern_.resize(N, N);
  std::vector<int> outer(N + 1, 0);
  for (Eigen::Index j = 0; j < n_; ++j) {
    Eigen::Index below = 0;
    for (int p = nb_offset_[j]; p < nb_offset_[j + 1]; ++p) below += dof[nb_vertex_[p]];
    for (int c = 0; c < dof[j]; ++c) outer[dof_offset_[j] + c + 1] = static_cast<int>(dof[j] - c + below);
  }
  for (Eigen::Index j = 0; j < N; ++j) outer[j + 1] += outer[j];
  pattern_.resizeNonZeros(outer[N]);
  std::copy(outer.begin(), outer.end(), pattern_.outerIndexPtr());
  int* inner = pattern_.innerIndexPtr();
#pragma omp parallel for schedule(static) if (parallel::worth(n_, parallel::kAssembly))
  for (Eigen::Index j = 0; j < n_; ++j)
    for (int c = 0; c < dof[j]; ++c) {
      int pos = outer[dof_offset_[j] + c];
      for (int r = c; r < dof[j]; ++r) inner[pos++] = static_cast<int>(dof_offset_[j] + r);
      for (int p = nb_offset_[j]; p < nb_offset_[j + 1]; ++p) {
        const int k = nb_vertex_[p];
        for (int r = 0; r < dof[k]; ++r) inner[pos++] = static_cast<int>(dof_offset_[k] + r);
      }
    }
  std::fill(pattern_.valuePtr(), pattern_.valuePtr() + outer[N], 0.0);
  return pattern_;
}

void DiracAssembly::fill(const Eigen::VectorXd& scale, const Eigen::VectorXd& diag, const RowQuats& edge_q,
                         Eigen::SparseMatrix<double>& K) const {
  const Eigen::Index N = num_unknowns();
  if (K.rows() != N || K.cols() != N || K.nonZeros() != pattern().nonZeros() || !K.isCompressed())
    throw Error("DiracAssembly: the output matrix must be a copy of pattern()");
  if (scale.size() != 0 && scale.size() != n_) {
    std::ostringstream s;
    s << "DiracAssembly: scale has " << scale.size() << " entries for " << n_ << " vertices";
    throw Error(s.str());
  }
  const int* outer = K.outerIndexPtr();
  double* val = K.valuePtr();
  const bool scaled = scale.size() == n_;
#pragma omp parallel for schedule(dynamic, 256) if (parallel::worth(n_, parallel::kAssembly))
  for (Eigen::Index j = 0; j < n_; ++j) {
    const int oj = order_[j];
    const double sj = scaled ? scale[oj] : 1.0;
    const int dj = static_cast<int>(dof_offset_[j + 1] - dof_offset_[j]);
    // Diagonal block s_j² d U_jᵀ U_j (U = identity for a free vertex): the diagonal quaternion of a
    // Hermitian matrix is real.
    Eigen::Matrix4d Dj = Eigen::Matrix4d::Zero();
    if (dj == 4)
      Dj.diagonal().setConstant(sj * sj * diag[oj]);
    else
      Dj.topLeftCorner<2, 2>() = sj * sj * diag[oj] * (U_[j].transpose() * U_[j]);
    for (int c = 0; c < dj; ++c) {
      int pos = outer[dof_offset_[j] + c];
      for (int r = c; r < dj; ++r) val[pos++] = Dj(r, c);
    }
    for (int p = nb_offset_[j]; p < nb_offset_[j + 1]; ++p) {
      const int k = nb_vertex_[p];
      const int ok = order_[k];
      const int dk = static_cast<int>(dof_offset_[k + 1] - dof_offset_[k]);
      const auto q = edge_q.row(nb_edge_[p]);
      // Entry (row k, column j): the stored quaternion is (E0, E1); its conjugate is (E1, E0).
      const double sg = nb_e0_is_row_[p] ? 1.0 : -1.0;
      Eigen::Matrix4d X = quaternion_block(ga::Quat(q[0], sg * q[1], sg * q[2], sg * q[3]));
      X *= (scaled ? scale[ok] : 1.0) * sj;
      // Offset of this neighbour's rows inside column c of block j: after the diagonal part and the
      // rows of the neighbours before it.
      Eigen::Matrix4d Y;
      if (dk == 4 && dj == 4) {
        Y = X;
      } else {
        Y.setZero();
        const Eigen::MatrixXd Uk =
            dk == 4 ? Eigen::MatrixXd(Eigen::Matrix4d::Identity()) : Eigen::MatrixXd(U_[k]);
        const Eigen::MatrixXd Uj =
            dj == 4 ? Eigen::MatrixXd(Eigen::Matrix4d::Identity()) : Eigen::MatrixXd(U_[j]);
        Y.topLeftCorner(dk, dj) = Uk.transpose() * X * Uj;
      }
      int before = 0;
      for (int t = nb_offset_[j]; t < p; ++t)
        before += static_cast<int>(dof_offset_[nb_vertex_[t] + 1] - dof_offset_[nb_vertex_[t]]);
      for (int c = 0; c < dj; ++c) {
        int pos = outer[dof_offset_[j] + c] + (dj - c) + before;
        for (int r = 0; r < dk; ++r) val[pos++] = Y(r, c);
      }
    }
  }
}

void DiracAssembly::normal_entries(const Eigen::VectorXd& rho, Eigen::VectorXd& diag,
                                   RowQuats& edge_q) const {
  check_rho(rho, m_);
  const Eigen::Index ne = E_.rows();
  diag.resize(n_);
  edge_q.resize(ne, 4);
  // Per vertex: Σ_f |e_a|²/(4A) + A ρ²/9 (the real diagonal of A*A).
#pragma omp parallel for schedule(static) if (parallel::worth(n_, parallel::kAssembly))
  for (Eigen::Index i = 0; i < n_; ++i) {
    double d = 0;
    for (int t = VF_offset_[i]; t < VF_offset_[i + 1]; ++t) {
      const int f = VF_corner_[t] / 3, c = VF_corner_[t] % 3;
      const double A = area_[f], r = rho[f];
      d += edge_vec_.block<1, 3>(f, 3 * c).squaredNorm() / (4.0 * A) + A * r * r / 9.0;
    }
    diag[i] = d;
  }
  // Per edge (E0, E1): Σ_f of the entry (a, b) = (F(f,c), F(f,c+1)), conjugated when a = E1.
  //   −e_a e_b/(4A) = (e_a·e_b − e_a×e_b)/(4A), and e_c × e_{c+1} = 2A N, so the vector part is −N/2.
#pragma omp parallel for schedule(static) if (parallel::worth(ne, parallel::kAssembly))
  for (Eigen::Index e = 0; e < ne; ++e) {
    Eigen::Vector4d q = Eigen::Vector4d::Zero();
    for (int t = EF_offset_[e]; t < EF_offset_[e + 1]; ++t) {
      const int f = EF_face_[t], c = EF_corner_[t];
      const double A = area_[f], r = rho[f];
      const Eigen::Vector3d ea = edge_vec_.block<1, 3>(f, 3 * c).transpose();
      const Eigen::Vector3d eb = edge_vec_.block<1, 3>(f, 3 * ((c + 1) % 3)).transpose();
      const double w = ea.dot(eb) / (4.0 * A) + A * r * r / 9.0;
      const Eigen::Vector3d v = -0.5 * normal_.row(f).transpose() + (r / 6.0) * (eb - ea);
      q[0] += w;
      q.tail<3>() += EF_sign_[t] * v;
    }
    edge_q.row(e) = q.transpose();
  }
}

void DiracAssembly::mixed_entries(const Eigen::VectorXd& rho, Eigen::VectorXd& diag, RowQuats& edge_q) const {
  check_rho(rho, m_);
  const Eigen::Index ne = E_.rows();
  diag.resize(n_);
  edge_q.resize(ne, 4);
#pragma omp parallel for schedule(static) if (parallel::worth(n_, parallel::kAssembly))
  for (Eigen::Index i = 0; i < n_; ++i) {
    double d = 0;
    for (int t = VF_offset_[i]; t < VF_offset_[i + 1]; ++t) {
      const int f = VF_corner_[t] / 3;
      d -= area_[f] * rho[f] / 9.0;  // real part of (B*A)_ii; −Σ e_a/6 vanishes on a closed 1-ring
    }
    diag[i] = d;
  }
  // (B*A)_ab = Σ_f −e_b/6 − Aρ/9 with b = E1 (the column of the stored entry (E0, E1)).
#pragma omp parallel for schedule(static) if (parallel::worth(ne, parallel::kAssembly))
  for (Eigen::Index e = 0; e < ne; ++e) {
    Eigen::Vector4d q = Eigen::Vector4d::Zero();
    for (int t = EF_offset_[e]; t < EF_offset_[e + 1]; ++t) {
      const int f = EF_face_[t], c = EF_corner_[t];
      const int cb = EF_sign_[t] > 0 ? (c + 1) % 3 : c;  // corner of E1 in face f
      q[0] -= area_[f] * rho[f] / 9.0;
      q.tail<3>() -= edge_vec_.block<1, 3>(f, 3 * cb).transpose() / 6.0;
    }
    edge_q.row(e) = q.transpose();
  }
}

void DiracAssembly::normal_matrix(const Eigen::VectorXd& rho, const Eigen::VectorXd& scale,
                                  Eigen::SparseMatrix<double>& K) const {
  Eigen::VectorXd diag;
  RowQuats edge_q;
  normal_entries(rho, diag, edge_q);
  fill(scale, diag, edge_q, K);
}

void DiracAssembly::mixed_matrix(const Eigen::VectorXd& rho, const Eigen::VectorXd& scale,
                                 Eigen::SparseMatrix<double>& G) const {
  Eigen::VectorXd diag;
  RowQuats edge_q;
  mixed_entries(rho, diag, edge_q);
  fill(scale, diag, edge_q, G);
}

void DiracAssembly::normal_matrix(const Eigen::VectorXd& rho, const Eigen::VectorXd& scale,
                                  Eigen::SparseMatrix<std::complex<double>>& K) const {
  Eigen::VectorXd diag;
  RowQuats edge_q;
  normal_entries(rho, diag, edge_q);
  fill_complex(scale, diag, edge_q, K);
}

void DiracAssembly::mixed_matrix(const Eigen::VectorXd& rho, const Eigen::VectorXd& scale,
                                 Eigen::SparseMatrix<std::complex<double>>& G) const {
  Eigen::VectorXd diag;
  RowQuats edge_q;
  mixed_entries(rho, diag, edge_q);
  fill_complex(scale, diag, edge_q, G);
}

const Eigen::SparseMatrix<std::complex<double>>& DiracAssembly::complex_pattern() const {
  if (reduced_)
    throw Error("DiracAssembly: the complex form needs every vertex unreduced (no boundary tangents)");
  if (complex_pattern_.rows() == 2 * n_) return complex_pattern_;
  // Column 2j: rows 2j, 2j+1, then 2k, 2k+1 per neighbour k > j; column 2j+1: row 2j+1, then the same.
  Eigen::SparseMatrix<std::complex<double>> P(2 * n_, 2 * n_);
  std::vector<int> outer(2 * n_ + 1, 0);
  for (Eigen::Index j = 0; j < n_; ++j) {
    const int nb = 2 * (nb_offset_[j + 1] - nb_offset_[j]);
    outer[2 * j + 1] = 2 + nb;
    outer[2 * j + 2] = 1 + nb;
  }
  for (Eigen::Index j = 0; j < 2 * n_; ++j) outer[j + 1] += outer[j];
  P.resizeNonZeros(outer[2 * n_]);
  std::copy(outer.begin(), outer.end(), P.outerIndexPtr());
  int* inner = P.innerIndexPtr();
#pragma omp parallel for schedule(static) if (parallel::worth(n_, parallel::kAssembly))
  for (Eigen::Index j = 0; j < n_; ++j)
    for (int c = 0; c < 2; ++c) {
      int pos = outer[2 * j + c];
      for (int r = c; r < 2; ++r) inner[pos++] = static_cast<int>(2 * j + r);
      for (int p = nb_offset_[j]; p < nb_offset_[j + 1]; ++p) {
        inner[pos++] = 2 * nb_vertex_[p];
        inner[pos++] = 2 * nb_vertex_[p] + 1;
      }
    }
  std::fill(P.valuePtr(), P.valuePtr() + outer[2 * n_], std::complex<double>(0.0));
  complex_pattern_ = std::move(P);
  return complex_pattern_;
}

void DiracAssembly::fill_complex(const Eigen::VectorXd& scale, const Eigen::VectorXd& diag,
                                 const RowQuats& edge_q, Eigen::SparseMatrix<std::complex<double>>& K) const {
  const Eigen::SparseMatrix<std::complex<double>>& P = complex_pattern();
  if (K.rows() != P.rows() || K.nonZeros() != P.nonZeros() || !K.isCompressed())
    throw Error("DiracAssembly: the output matrix must be a copy of complex_pattern()");
  if (scale.size() != 0 && scale.size() != n_) {
    std::ostringstream s;
    s << "DiracAssembly: scale has " << scale.size() << " entries for " << n_ << " vertices";
    throw Error(s.str());
  }
  using C = std::complex<double>;
  const int* outer = K.outerIndexPtr();
  C* val = K.valuePtr();
  const bool scaled = scale.size() == n_;
#pragma omp parallel for schedule(static) if (parallel::worth(n_, parallel::kAssembly))
  for (Eigen::Index j = 0; j < n_; ++j) {
    const double sj = scaled ? scale[order_[j]] : 1.0;
    const double d = sj * sj * diag[order_[j]];
    int p0 = outer[2 * j], p1 = outer[2 * j + 1];
    val[p0++] = d;
    val[p0++] = 0.0;
    val[p1++] = d;
    for (int p = nb_offset_[j]; p < nb_offset_[j + 1]; ++p) {
      const double s = sj * (scaled ? scale[order_[nb_vertex_[p]]] : 1.0);
      const auto q = edge_q.row(nb_edge_[p]);
      const double sg = nb_e0_is_row_[p] ? 1.0 : -1.0;  // conjugate for the entry (E1, E0)
      // q = a + bi + cj + dk → [z1 −z̄2; z2 z̄1], z1 = a + bi, z2 = c − di.
      const C z1(s * q[0], s * sg * q[1]), z2(s * sg * q[2], -s * sg * q[3]);
      val[p0++] = z1;
      val[p0++] = z2;
      val[p1++] = -std::conj(z2);
      val[p1++] = std::conj(z1);
    }
  }
}

Eigen::MatrixXd DiracAssembly::expand(const Eigen::VectorXcd& w, const Eigen::VectorXd& scale) const {
  if (w.size() != 2 * n_) throw Error("DiracAssembly::expand: wrong number of complex unknowns");
  Eigen::MatrixXd lambda(n_, 4);
  for (Eigen::Index k = 0; k < n_; ++k) {
    const int i = order_[k];
    const double s = scale.size() == n_ ? scale[i] : 1.0;
    lambda.row(i) << s * w[2 * k].real(), s * w[2 * k].imag(), s * w[2 * k + 1].real(),
        -s * w[2 * k + 1].imag();
  }
  return lambda;
}

Eigen::MatrixXd DiracAssembly::expand(const Eigen::VectorXd& x, const Eigen::VectorXd& scale) const {
  if (x.size() != num_unknowns()) throw Error("DiracAssembly::expand: wrong number of unknowns");
  Eigen::MatrixXd lambda(n_, 4);
  for (Eigen::Index k = 0; k < n_; ++k) {
    const int i = order_[k];
    const double s = scale.size() == n_ ? scale[i] : 1.0;
    const Eigen::Index o = dof_offset_[k];
    if (dof_offset_[k + 1] - o == 4)
      lambda.row(i) = s * x.segment<4>(o).transpose();
    else
      lambda.row(i) = s * (U_[k] * x.segment<2>(o)).transpose();
  }
  return lambda;
}

Eigen::VectorXd DiracAssembly::restrict_field(const Eigen::MatrixXd& lambda) const {
  if (lambda.rows() != n_ || lambda.cols() != 4)
    throw Error("DiracAssembly::restrict_field: lambda must be n x 4");
  Eigen::VectorXd x(num_unknowns());
  for (Eigen::Index k = 0; k < n_; ++k) {
    const int i = order_[k];
    const Eigen::Index o = dof_offset_[k];
    const Eigen::Vector4d l = lambda.row(i).transpose();
    if (dof_offset_[k + 1] - o == 4)
      x.segment<4>(o) = l;
    else
      x.segment<2>(o) = (U_[k].transpose() * U_[k]).ldlt().solve(U_[k].transpose() * l);
  }
  return x;
}

}  // namespace spinmotor

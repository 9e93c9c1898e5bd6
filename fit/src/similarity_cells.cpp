// Similarity cells: faces and one-rings of the as-similar-as-possible energy (cells.hpp).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/fit/cells.hpp"
#include "spinmotor/ga/rotor_fit.hpp"
#include "spinmotor/mesh/face_geometry.hpp"  // kDegenerateFace

namespace spinmotor::fit {

namespace {

using Vec3 = Eigen::Vector3d;

inline bool collapsed(const Vec3& e1, const Vec3& e2, const Vec3& e3, const Vec3& nv) {
  const double l2 = std::max({e1.squaredNorm(), e2.squaredNorm(), e3.squaredNorm()});
  return !(nv.norm() > kDegenerateFace * l2);
}

}  // namespace

// ---- faces -------------------------------------------------------------------------------------------

SimilarityFaces SimilarityFaces::bind(const Eigen::MatrixXd& V0, const Eigen::MatrixXi& F,
                                      const std::vector<char>& fixed, const Eigen::VectorXi& free) {
  SimilarityFaces out;
  const Eigen::Index n = V0.rows();
  std::vector<int> rank(static_cast<size_t>(n), -1);
  for (Eigen::Index k = 0; k < free.size(); ++k) rank[free[k]] = static_cast<int>(k);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    if (fixed[a] && fixed[b] && fixed[c]) {
      out.fixed_faces_.push_back(static_cast<int>(f));
      continue;
    }
    ActiveFace af;
    af.v = {a, b, c};
    const Vec3 p0 = V0.row(a), p1 = V0.row(b), p2 = V0.row(c);
    const Vec3 e1 = p1 - p0, e2 = p2 - p0, nv = e1.cross(e2);
    if (collapsed(e1, e2, p2 - p1, nv)) {
      std::ostringstream s;
      s << "PinnedCleanup: rest face " << f << " is degenerate";
      throw Error(s.str());
    }
    af.area = 0.5 * nv.norm();
    af.b1 = e1.normalized();
    af.b2 = nv.normalized().cross(af.b1);
    // 2D corners q0 = 0, q1 = (|e1|, 0), q2 = (e2·b1, e2·b2); ∇φ_i = perp(q_{i+2} − q_{i+1}) / (2A),
    // perp(x, y) = (−y, x) (counter-clockwise quarter turn).
    const std::array<Eigen::Vector2d, 3> q = {Eigen::Vector2d(0, 0), Eigen::Vector2d(e1.norm(), 0),
                                              Eigen::Vector2d(e2.dot(af.b1), e2.dot(af.b2))};
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector2d e = q[(i + 2) % 3] - q[(i + 1) % 3];
      af.grad[2 * i] = -e.y() / (2 * af.area);
      af.grad[2 * i + 1] = e.x() / (2 * af.area);
    }
    out.area_ += af.area;
    out.faces_.push_back(af);
  }
  // Incidences of the free vertices in the faces (CSR by free rank).
  out.inc_offset_.assign(static_cast<size_t>(free.size()) + 1, 0);
  for (const ActiveFace& af : out.faces_)
    for (int c = 0; c < 3; ++c)
      if (rank[af.v[c]] >= 0) ++out.inc_offset_[rank[af.v[c]] + 1];
  for (Eigen::Index k = 0; k < free.size(); ++k) out.inc_offset_[k + 1] += out.inc_offset_[k];
  out.inc_.resize(out.inc_offset_.back());
  std::vector<int> fill(out.inc_offset_.begin(), out.inc_offset_.end() - 1);
  for (size_t f = 0; f < out.faces_.size(); ++f)
    for (int c = 0; c < 3; ++c)
      if (const int s = rank[out.faces_[f].v[c]]; s >= 0) out.inc_[fill[s]++] = {static_cast<int>(f), c};
  out.T_.resize(out.faces_.size());
  out.reset();
  return out;
}

void SimilarityFaces::reset() {
  for (size_t f = 0; f < faces_.size(); ++f) T_[f] = {faces_[f].b1, faces_[f].b2};
}

double SimilarityFaces::fit(const RowMatrix3& V, Eigen::Index& fallbacks) {
  const long na = static_cast<long>(faces_.size());
  double energy = 0;
  long fallback = 0;
  // T_f = the conformal part of J_f in the frames of the rest and current planes.
#pragma omp parallel for schedule(static) reduction(+ : energy, fallback) if (parallel::worth(na, parallel::kMotorBlend))
  for (long k = 0; k < na; ++k) {
    const ActiveFace& af = faces_[k];
    const Vec3 v0 = V.row(af.v[0]), v1 = V.row(af.v[1]), v2 = V.row(af.v[2]);
    const Vec3 c1 = af.grad[0] * v0 + af.grad[2] * v1 + af.grad[4] * v2;
    const Vec3 c2 = af.grad[1] * v0 + af.grad[3] * v1 + af.grad[5] * v2;
    const Vec3 e1 = v1 - v0, e2 = v2 - v0, nv = e1.cross(e2);
    std::array<Vec3, 2>& T = T_[k];
    if (collapsed(e1, e2, v2 - v1, nv)) {
      ++fallback;  // keep the previous T_f
    } else {
      const Vec3 d1 = e1.normalized(), d2 = nv.normalized().cross(d1);
      const double a = d1.dot(c1), b = d1.dot(c2), cc = d2.dot(c1), d = d2.dot(c2);
      const double alpha = 0.5 * (a + d), beta = 0.5 * (cc - b);
      T[0] = alpha * d1 + beta * d2;
      T[1] = -beta * d1 + alpha * d2;
    }
    energy += af.area * ((c1 - T[0]).squaredNorm() + (c2 - T[1]).squaredNorm());
  }
  fallbacks += fallback;
  return energy;
}

void SimilarityFaces::add_rhs(Eigen::Index k, double weight, Eigen::Vector3d& b) const {
  for (int q = inc_offset_[k]; q < inc_offset_[k + 1]; ++q) {
    const auto [f, corner] = inc_[q];
    const ActiveFace& af = faces_[f];
    const std::array<Vec3, 2>& T = T_[f];
    b += weight * af.area * (af.grad[2 * corner] * T[0] + af.grad[2 * corner + 1] * T[1]);
  }
}

// ---- one-rings ---------------------------------------------------------------------------------------

SimilarityOneRings SimilarityOneRings::bind(const Eigen::MatrixXd& V0, const Eigen::SparseMatrix<double>& L,
                                            const Eigen::VectorXi& free) {
  SimilarityOneRings out;
  out.V0_ = V0;
  const Eigen::Index n = V0.rows();
  out.cell_of_.assign(static_cast<size_t>(n), -1);
  for (Eigen::Index k = 0; k < free.size(); ++k) {
    const int i = free[k];
    if (out.cell_of_[i] < 0) out.cell_of_[i] = static_cast<int>(out.vertex_.size()), out.vertex_.push_back(i);
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, i); it; ++it) {
      const int j = static_cast<int>(it.row());
      if (j != i && out.cell_of_[j] < 0)
        out.cell_of_[j] = static_cast<int>(out.vertex_.size()), out.vertex_.push_back(j);
    }
  }
  out.offset_.assign(1, 0);
  for (const int i : out.vertex_) {
    double d = 0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, i); it; ++it) {
      const int j = static_cast<int>(it.row());
      if (j == i || it.value() == 0) continue;
      out.nbr_.push_back(j);
      out.w_.push_back(-it.value());
      d += -it.value() * (V0.row(j) - V0.row(i)).squaredNorm();
    }
    out.offset_.push_back(static_cast<int>(out.nbr_.size()));
    if (!(d > 0)) {  // no similarity can be fitted to this cell
      out.ok_ = false;
      return out;
    }
    out.d_.push_back(d);
    out.dsum_ += d;
  }
  out.T_.resize(out.vertex_.size());
  out.sim_.resize(out.vertex_.size());
  out.reset();
  return out;
}

void SimilarityOneRings::reset() {
  for (auto& T : T_) T = Eigen::Matrix3d::Identity();
  for (auto& s : sim_) s = ga::Similarity{};
}

void SimilarityOneRings::set_similarity(int cell, const ga::Similarity& s) {
  sim_[cell] = s;
  T_[cell] = s.scale * ga::rotation_matrix(s.rotor);
}

double SimilarityOneRings::fit(const RowMatrix3& V, Eigen::Index& fallbacks) {
  const long nc = static_cast<long>(vertex_.size());
  double energy = 0;
  long fallback = 0;
  // T_i = s_i R_i, the best similarity of the cotangent-weighted spokes (3D Procrustes with scale):
  // S_i = Σ_j w_ij e_ij e'_ijᵀ, R_i by ga::best_similarity, s_i = tr(R_i S_i) / Σ_j w_ij |e_ij|²; cell
  // energy Σ w|e'|² − s_i tr(R_i S_i).
#pragma omp parallel for schedule(static) reduction(+ : energy, fallback) if (parallel::worth(nc, parallel::kMotorBlend))
  for (long k = 0; k < nc; ++k) {
    const int i = vertex_[k];
    const Vec3 vi = V.row(i), pi = V0_.row(i);
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    double e2sum = 0;
    for (int q = offset_[k]; q < offset_[k + 1]; ++q) {
      const int j = nbr_[q];
      const double w = w_[q];
      const Vec3 e = Vec3(V0_.row(j)) - pi, ed = Vec3(V.row(j)) - vi;
      S.noalias() += w * e * ed.transpose();
      e2sum += w * ed.squaredNorm();
    }
    if (!(S.norm() > 0)) {
      ++fallback;  // a collapsed cell keeps its previous similarity
      energy += e2sum;
      continue;
    }
    ga::RotationInfo info;
    // Warm-started from the cell's previous rotor: Horn's fast path (a cold start far from the identity
    // takes the Jacobi fallback); where the best rotation is not unique (a cell collapsed to a line) the
    // member nearest the previous one.
    sim_[k] = ga::best_similarity(S, d_[k], sim_[k].rotor, &info);
    T_[k] = sim_[k].scale * ga::rotation_matrix(sim_[k].rotor);
    energy += e2sum - sim_[k].scale * std::max(info.trace, 0.0);
  }
  fallbacks += fallback;
  return energy;
}

void SimilarityOneRings::add_rhs(int i, double weight, Eigen::Vector3d& b) const {
  const int ci = cell_of_[i];
  const Vec3 pi = V0_.row(i);
  Vec3 s = Vec3::Zero();
  for (int q = offset_[ci]; q < offset_[ci + 1]; ++q) {
    const int j = nbr_[q];
    s += 0.5 * w_[q] * ((T_[ci] + T_[cell_of_[j]]) * (pi - Vec3(V0_.row(j))));
  }
  b += weight * s;
}

}  // namespace spinmotor::fit

#include "spinmotor/deform/direct_delta_mush.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "mush_detail.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/ga/rotor_fit.hpp"
#include "spinmotor/linalg/cholesky_solver.hpp"

namespace spinmotor {

namespace {

constexpr const char* kDirectDeltaMush = "DirectDeltaMushDeformer";

/// Right-hand-side block budget of one batch of bones at bind (doubles): 10 columns per bone.
constexpr Eigen::Index kBatchDoubles = 8'000'000;

/// The symmetric 3×3 of a packed Ω (entries 4..9: xx, xy, xz, yy, yz, zz).
inline Eigen::Matrix3d unpack_S(const std::array<double, 10>& o) {
  Eigen::Matrix3d S;
  S << o[4], o[5], o[6], o[5], o[7], o[8], o[6], o[8], o[9];
  return S;
}

}  // namespace

DirectDeltaMushDeformer DirectDeltaMushDeformer::bind(const Mesh& rest, std::span<const Bone> bones,
                                                      const Eigen::MatrixXd& weights,
                                                      const Options& options) {
  return finish(rest, bones, SkinDeformer::bind(rest, bones, weights, {SkinDeformer::Blend::LBS}), options);
}

DirectDeltaMushDeformer DirectDeltaMushDeformer::bind(const Mesh& rest, std::span<const Bone> bones,
                                                      const Eigen::SparseMatrix<double>& weights,
                                                      const Options& options) {
  return finish(rest, bones, SkinDeformer::bind(rest, bones, weights, {SkinDeformer::Blend::LBS}), options);
}

DirectDeltaMushDeformer DirectDeltaMushDeformer::finish(const Mesh& rest, std::span<const Bone> bones,
                                                        const SkinDeformer& skin, const Options& options) {
  if (options.iterations < 0)
    throw Error(std::string(kDirectDeltaMush) + ": iterations must be >= 0, got " +
                std::to_string(options.iterations));
  if (!(options.tau > 0.0) || !std::isfinite(options.tau))
    throw Error(std::string(kDirectDeltaMush) + ": tau must be finite and > 0, got " +
                std::to_string(options.tau));
  if (!(options.prune >= 0.0 && options.prune < 1.0))
    throw Error(std::string(kDirectDeltaMush) + ": prune must be in [0, 1), got " +
                std::to_string(options.prune));
  detail::require_mush_mesh(rest, /*oriented=*/false, kDirectDeltaMush);

  DirectDeltaMushDeformer d;
  d.options_ = options;
  d.bones_.assign(bones.begin(), bones.end());
  d.controls_ = skin.controls();
  d.P_ = rest.V;
  d.W_ = skin.weights();  // validated, ≤ 4 per row, rows sum to 1 (column-major: one column per bone)
  const Eigen::Index n = rest.V.rows();
  const int B = static_cast<int>(bones.size());
  const int p = options.iterations;
  const double tau = options.tau;

  // (1+τ) D − τ A: the symmetric form of I + τ L, L = I − D⁻¹A (lower triangle is what CHOLMOD reads,
  // the full matrix is stored for clarity).
  const detail::Rings rings = detail::vertex_rings(edge_topology(rest.F).E, n);
  Eigen::VectorXd valence(n);
  for (Eigen::Index i = 0; i < n; ++i) valence[i] = rings.valence(i);
  CholeskySolver solver;
  if (p > 0) {
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(rings.index.size() + n);
    for (Eigen::Index i = 0; i < n; ++i) {
      t.emplace_back(i, i, (1.0 + tau) * valence[i]);
      for (int k = rings.offset[i]; k < rings.offset[i + 1]; ++k) t.emplace_back(i, rings.index[k], -tau);
    }
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    solver.compute(A);
  }

  // Moments about the bounding-box centre (smaller raw moments, less cancellation when shifting to u_i).
  const Eigen::RowVector3d centre = 0.5 * (rest.V.colwise().minCoeff() + rest.V.colwise().maxCoeff());
  const Eigen::MatrixXd Y = rest.V.rowwise() - centre;

  std::vector<std::vector<std::pair<int, Packed>>> kept(n);
  const int batch = static_cast<int>(std::clamp<Eigen::Index>(kBatchDoubles / (10 * n), 1, B));
  for (int j0 = 0; j0 < B; j0 += batch) {
    const int nb = std::min(batch, B - j0);
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n, 10 * nb);
    bool any = false;
    for (int jj = 0; jj < nb; ++jj)
      for (Eigen::SparseMatrix<double>::InnerIterator it(d.W_, j0 + jj); it; ++it) {
        const Eigen::Index k = it.row();
        const double w = it.value(), y0 = Y(k, 0), y1 = Y(k, 1), y2 = Y(k, 2);
        const double f[10] = {1.0, y0, y1, y2, y0 * y0, y0 * y1, y0 * y2, y1 * y1, y1 * y2, y2 * y2};
        for (int c = 0; c < 10; ++c) X(k, 10 * jj + c) = w * f[c];
        any = true;
      }
    if (!any) continue;                                                         // bones that keep no weight
    for (int it = 0; it < p; ++it) X = solver.solve(valence.asDiagonal() * X);  // x ← (I + τL)⁻¹ x
    for (Eigen::Index i = 0; i < n; ++i) {
      const double yi[3] = {Y(i, 0), Y(i, 1), Y(i, 2)};
      for (int jj = 0; jj < nb; ++jj) {
        auto at = [&](int c) { return X(i, 10 * jj + c); };
        const double s = at(0);
        if (!(s > options.prune)) continue;
        const double m[3] = {at(1), at(2), at(3)};
        Packed o;
        o[0] = s;
        for (int a = 0; a < 3; ++a) o[1 + a] = m[a] - s * yi[a];
        // Σ ψw (y_k − y_i)_a (y_k − y_i)_b = S_ab − y_ia m_b − m_a y_ib + s y_ia y_ib
        const int ab[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
        for (int e = 0; e < 6; ++e) {
          const int a = ab[e][0], b = ab[e][1];
          o[4 + e] = at(4 + e) - yi[a] * m[b] - m[a] * yi[b] + s * yi[a] * yi[b];
        }
        kept[i].emplace_back(j0 + jj, o);
      }
    }
  }

  d.offset_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (kept[i].empty())  // impossible for prune < 1/B (the masses of a vertex sum to 1), kept as a guard
      throw numerical_error(std::string(kDirectDeltaMush) + ": vertex " + std::to_string(i) +
                            " keeps no bone after pruning (prune " + std::to_string(options.prune) + ")");
    d.offset_[i + 1] = d.offset_[i] + static_cast<int>(kept[i].size());
  }
  d.bone_.reserve(d.offset_[n]);
  d.omega_.reserve(d.offset_[n]);
  for (Eigen::Index i = 0; i < n; ++i)
    for (const auto& [j, o] : kept[i]) d.bone_.push_back(j), d.omega_.push_back(o);
  d.T_.resize(B);
  return d;
}

Eigen::Matrix4d DirectDeltaMushDeformer::omega(Eigen::Index i, int j) const {
  if (i < 0 || i >= vertices() || j < 0 || j >= static_cast<int>(bones_.size()))
    throw Error(std::string(kDirectDeltaMush) + "::omega: vertex " + std::to_string(i) + " or bone " +
                std::to_string(j) + " out of range");
  Eigen::Matrix4d O = Eigen::Matrix4d::Zero();
  for (int a = offset_[i]; a < offset_[i + 1]; ++a)
    if (bone_[a] == j) {
      const Packed& o = omega_[a];
      O.topLeftCorner<3, 3>() = unpack_S(o);
      O.block<3, 1>(0, 3) = Eigen::Vector3d(o[1], o[2], o[3]);
      O.block<1, 3>(3, 0) = Eigen::RowVector3d(o[1], o[2], o[3]);
      O(3, 3) = o[0];
    }
  return O;
}

void DirectDeltaMushDeformer::pose(std::span<const ga::Mot> frames, Eigen::MatrixXd& V_out) {
  detail::bone_matrices(bones_, frames, T_, kDirectDeltaMush);
  const Eigen::Index n = vertices();
  if (V_out.rows() != n || V_out.cols() != 3) V_out.resize(n, 3);
  const Eigen::Matrix<double, 3, 4>* T = T_.data();
  const int* off = offset_.data();
  const int* bone = bone_.data();
  const Packed* om = omega_.data();
  const Eigen::MatrixXd& P = P_;
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend))
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d u(P(i, 0), P(i, 1), P(i, 2));
    const Eigen::Matrix<double, 3, 4>& Tr = T[bone[off[i]]];
    const Eigen::Vector3d c_ref = Tr.leftCols<3>() * u + Tr.col(3);
    double s = 0.0;
    Eigen::Vector3d pm = Eigen::Vector3d::Zero(), qm = Eigen::Vector3d::Zero();
    Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
    for (int a = off[i]; a < off[i + 1]; ++a) {
      const Packed& o = om[a];
      const Eigen::Matrix<double, 3, 4>& Tj = T[bone[a]];
      const Eigen::Vector3d m(o[1], o[2], o[3]);
      const Eigen::Vector3d delta = (Tj.leftCols<3>() * u + Tj.col(3)) - c_ref;  // c_j − c_ref
      s += o[0];
      pm += m;
      qm += Tj.leftCols<3>() * m + o[0] * delta;
      G.noalias() += Tj.leftCols<3>() * unpack_S(o);
      G.noalias() += delta * m.transpose();
    }
    const Eigen::Vector3d pbar = pm / s, qrel = qm / s;  // q̄ = c_ref + qrel
    const Eigen::Matrix3d M = G / s - qrel * pbar.transpose();
    const Eigen::Matrix3d R = ga::closest_rotation(M);  // a proper rotation also when det M < 0
    const Eigen::Vector3d out = c_ref + (qrel - R * pbar);
    V_out(i, 0) = out.x(), V_out(i, 1) = out.y(), V_out(i, 2) = out.z();
  }
}

}  // namespace spinmotor

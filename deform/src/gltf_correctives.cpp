// Corrective morph targets from a cleaned animation (gltf_correctives.hpp).
#include "spinmotor/deform/gltf_correctives.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/gltf_animation.hpp"
#include "spinmotor/deform/gltf_skin.hpp"

namespace spinmotor {

namespace {

/// One frame of the engine's skinning without correctives: per vertex the blended linear part M_i and
/// the position x⁰_i (file targets at their weights at t).
struct EngineFrame {
  std::vector<Eigen::Matrix3d> M;
  Eigen::MatrixXd x0;
};

EngineFrame engine_frame(const GltfRig& rig, int anim, double t) {
  const std::vector<Eigen::Matrix4d> S = joint_matrices(rig, node_world_matrices(rig, anim, t));
  const std::vector<Eigen::VectorXd> m = morph_weights(rig, anim, t);
  Eigen::MatrixXd P = rig.mesh.V;
  for (size_t p = 0; p < rig.pieces.size(); ++p)
    for (Eigen::Index k = 0; k < rig.pieces[p].num_targets(); ++k)
      if (m[p][k] != 0.0)
        P.middleRows(rig.pieces[p].first_vertex, rig.pieces[p].vertices) +=
            m[p][k] * rig.pieces[p].targets[k];
  const Eigen::Index n = P.rows();
  EngineFrame out{std::vector<Eigen::Matrix3d>(static_cast<size_t>(n), Eigen::Matrix3d::Zero()),
                  Eigen::MatrixXd::Zero(n, 3)};
  for (int j = 0; j < rig.weights.outerSize(); ++j) {
    const Eigen::Matrix3d L = S[j].topLeftCorner<3, 3>();
    const Eigen::Vector3d tr = S[j].topRightCorner<3, 1>();
    for (Eigen::SparseMatrix<double>::InnerIterator it(rig.weights, j); it; ++it) {
      out.M[it.row()] += it.value() * L;
      out.x0.row(it.row()) += it.value() * (L * P.row(it.row()).transpose() + tr).transpose();
    }
  }
  return out;
}

void check_inputs(const GltfRig& rig, int anim, const std::vector<double>& times,
                  const std::vector<Eigen::MatrixXd>& frames, const CorrectiveOptions& o) {
  if (anim < 0 || anim >= static_cast<int>(rig.animations.size()))
    throw Error("corrective targets: animation " + std::to_string(anim) + " out of range (the rig has " +
                std::to_string(rig.animations.size()) + ")");
  if (!(o.max_error > 0) || !std::isfinite(o.max_error))
    throw Error("corrective targets: max_error must be positive");
  if (o.max_targets < 1) throw Error("corrective targets: max_targets must be at least 1");
  if (times.empty() || times.size() != frames.size())
    throw Error("corrective targets: " + std::to_string(frames.size()) + " frames for " +
                std::to_string(times.size()) + " times (at least one of each, as many of each)");
  for (size_t f = 0; f < times.size(); ++f) {
    if (!std::isfinite(times[f]) ||
        (f > 0 && !(static_cast<float>(times[f]) > static_cast<float>(times[f - 1]))))
      throw Error("corrective targets: time of frame " + std::to_string(f) +
                  " is not finite or not after the previous one");
    if (frames[f].rows() != rig.mesh.V.rows() || frames[f].cols() != 3 || !frames[f].allFinite())
      throw Error("corrective targets: frame " + std::to_string(f) + " is not a finite " +
                  std::to_string(rig.mesh.V.rows()) + "×3 pose");
  }
}

/// The truncation of one piece's offsets (rows 3 i + c, columns frames): targets (vertices × 3) and
/// weights (F × K). `scale` (n_p × F) bounds |M_i(f)|.
void truncate(const Eigen::MatrixXd& A, const Eigen::MatrixXd& scale, double tolerance, int max_targets,
              std::vector<Eigen::MatrixXd>& targets, Eigen::MatrixXd& weights) {
  targets.clear();
  weights.resize(A.cols(), 0);
  if (A.cwiseAbs().maxCoeff() == 0.0) return;
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  Eigen::MatrixXd R = A;
  const Eigen::Index np = A.rows() / 3, F = A.cols();
  const int limit = static_cast<int>(std::min<Eigen::Index>(max_targets, svd.singularValues().size()));
  int K = 0;
  for (;; ++K) {
    double err = 0;
    for (Eigen::Index f = 0; f < F; ++f)
      for (Eigen::Index i = 0; i < np; ++i) err = std::max(err, scale(i, f) * R.block<3, 1>(3 * i, f).norm());
    if (err <= tolerance || K == limit) break;
    R.noalias() -= svd.singularValues()[K] * svd.matrixU().col(K) * svd.matrixV().col(K).transpose();
  }
  weights = svd.matrixV().leftCols(K);
  for (int c = 0; c < K; ++c) {
    const Eigen::VectorXd d = svd.singularValues()[c] * svd.matrixU().col(c);
    targets.push_back(
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(d.data(), np, 3));
  }
}

/// Weights in [0, 1] for the same sums (Blender's importer clamps shape-key values to [0, 1]): each column c
/// with range [a_c, b_c] becomes u_c = (w_c − a_c) / (b_c − a_c) on the target (b_c − a_c) D_c, and the
/// shifts Σ_c a_c D_c one more target with weight 1 on every frame (a constant column is folded in whole).
void to_unit_weights(std::vector<Eigen::MatrixXd>& targets, Eigen::MatrixXd& weights) {
  if (targets.empty()) return;
  std::vector<Eigen::MatrixXd> out;
  Eigen::MatrixXd offset = Eigen::MatrixXd::Zero(targets[0].rows(), 3), w(weights.rows(), 0);
  for (size_t c = 0; c < targets.size(); ++c) {
    const Eigen::Index k = static_cast<Eigen::Index>(c);
    const double a = weights.col(k).minCoeff(), b = weights.col(k).maxCoeff();
    offset += a * targets[c];
    if (!(b - a > 1e-12 * std::max(std::abs(a), std::abs(b)))) {
      offset += (b - a) * targets[c];  // constant: all of it in the offset (b = a to rounding)
      continue;
    }
    out.push_back((b - a) * targets[c]);
    w.conservativeResize(Eigen::NoChange, w.cols() + 1);
    w.col(w.cols() - 1) = (weights.col(k).array() - a) / (b - a);
  }
  if (offset.cwiseAbs().maxCoeff() > 0) {
    out.push_back(offset);
    w.conservativeResize(Eigen::NoChange, w.cols() + 1);
    w.col(w.cols() - 1).setOnes();
  }
  targets = std::move(out);
  weights = std::move(w);
}

/// The output animation: the cleaned animation's channels, with a weights channel per piece with
/// correctives (the file's weights sampled at the frame times, then the corrective weights).
GltfAnimation corrective_animation(const GltfRig& rig, int anim, const std::vector<double>& times,
                                   const std::vector<Eigen::MatrixXd>& weights) {
  GltfAnimation out = rig.animations[anim];
  std::vector<char> replaced(rig.nodes.size(), 0);
  for (size_t p = 0; p < rig.pieces.size(); ++p) replaced[rig.pieces[p].node] = weights[p].cols() > 0;
  std::erase_if(out.channels,
                [&](const GltfChannel& c) { return c.path == GltfPath::Weights && replaced[c.node]; });
  const Eigen::Index F = static_cast<Eigen::Index>(times.size());
  for (size_t p = 0; p < rig.pieces.size(); ++p) {
    if (weights[p].cols() == 0) continue;
    const Eigen::Index T = rig.pieces[p].num_targets(), K = weights[p].cols();
    GltfChannel c;
    c.node = rig.pieces[p].node;
    c.path = GltfPath::Weights;
    c.interpolation = GltfInterpolation::Linear;
    c.times = Eigen::Map<const Eigen::VectorXd>(times.data(), F);
    c.values.resize(F, T + K);
    for (Eigen::Index f = 0; f < F; ++f) {
      const std::vector<Eigen::VectorXd> m = morph_weights(rig, anim, times[f]);
      c.values.row(f).head(T) = m[p].transpose();
      c.values.row(f).tail(K) = weights[p].row(f);
    }
    out.channels.push_back(std::move(c));
  }
  out.start = std::numeric_limits<double>::infinity(), out.end = -out.start;
  for (const GltfChannel& c : out.channels)
    out.start = std::min(out.start, c.times[0]), out.end = std::max(out.end, c.times[c.times.size() - 1]);
  return out;
}

}  // namespace

CorrectiveRig corrective_rig(const GltfRig& rig, int anim, const std::vector<double>& times,
                             const std::vector<Eigen::MatrixXd>& frames, const CorrectiveOptions& o) {
  check_inputs(rig, anim, times, frames, o);
  const Eigen::Index n = rig.mesh.V.rows(), F = static_cast<Eigen::Index>(times.size());
  const RigSkin skin = rig_skin(rig);
  const double diag = (skin.rest.V.colwise().maxCoeff() - skin.rest.V.colwise().minCoeff()).norm();
  // Offsets δ_i(f) per piece (rows 3 i + c) and the bound |M_i(f)|_F.
  std::vector<Eigen::MatrixXd> delta(rig.pieces.size()), scale(rig.pieces.size());
  for (size_t p = 0; p < rig.pieces.size(); ++p)
    delta[p].resize(3 * rig.pieces[p].vertices, F), scale[p].resize(rig.pieces[p].vertices, F);
  for (Eigen::Index f = 0; f < F; ++f) {
    const EngineFrame e = engine_frame(rig, anim, times[f]);
    for (size_t p = 0; p < rig.pieces.size(); ++p)
      for (Eigen::Index k = 0; k < rig.pieces[p].vertices; ++k) {
        const Eigen::Index i = rig.pieces[p].first_vertex + k;
        const Eigen::FullPivLU<Eigen::Matrix3d> lu(e.M[i]);
        if (!lu.isInvertible())
          throw Error("corrective targets: the blended joint matrix of " + rig.vertex_label(i) +
                      " is singular at t = " + std::to_string(times[f]));
        delta[p].block<3, 1>(3 * k, f) =
            lu.solve(Eigen::Vector3d((frames[f].row(i) - e.x0.row(i)).transpose()));
        scale[p](k, f) = e.M[i].norm();
      }
  }
  CorrectiveRig out;
  out.rig = rig;
  std::vector<Eigen::MatrixXd> weights(rig.pieces.size());
  for (size_t p = 0; p < rig.pieces.size(); ++p) {
    std::vector<Eigen::MatrixXd> targets;
    truncate(delta[p], scale[p], o.max_error * diag, o.max_targets, targets, weights[p]);
    to_unit_weights(targets, weights[p]);
    GltfPiece& piece = out.rig.pieces[p];
    const Eigen::Index T = piece.num_targets(), K = static_cast<Eigen::Index>(targets.size());
    out.targets.push_back(static_cast<int>(K));
    for (Eigen::Index c = 0; c < K; ++c) {
      char name[40];
      std::snprintf(name, sizeof name, "spinmotor_corrective_%02d", static_cast<int>(c));
      piece.targets.push_back(targets[c]);
      piece.target_names.emplace_back(name);
    }
    piece.default_weights.conservativeResize(T + K);
    piece.default_weights.tail(K).setZero();
  }
  out.rig.animations = {corrective_animation(rig, anim, times, weights)};
  // The exact error of what was written.
  double sum2 = 0;
  for (Eigen::Index f = 0; f < F; ++f) {
    const EngineFrame e = engine_frame(rig, anim, times[f]);
    for (size_t p = 0; p < rig.pieces.size(); ++p)
      for (Eigen::Index k = 0; k < rig.pieces[p].vertices; ++k) {
        const Eigen::Index i = rig.pieces[p].first_vertex + k;
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        for (Eigen::Index c = 0; c < weights[p].cols(); ++c)
          d += weights[p](f, c) *
               out.rig.pieces[p].targets[rig.pieces[p].num_targets() + c].row(k).transpose();
        const double err =
            (e.x0.row(i).transpose() + e.M[i] * d - frames[f].row(i).transpose()).norm() / diag;
        out.max_error = std::max(out.max_error, err);
        sum2 += err * err;
      }
  }
  out.rms_error = std::sqrt(sum2 / static_cast<double>(n * F));
  out.bound_met = out.max_error <= o.max_error * (1 + 1e-9);
  return out;
}

}  // namespace spinmotor

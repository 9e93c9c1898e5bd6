#include "spinmotor/deform/skinning.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "dlb_point.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/deform/motor_blend_field.hpp"
#include "spinmotor/ga/rotor_fit.hpp"

namespace spinmotor {

namespace {

const ga::Mot kIdentity(1, 0, 0, 0, 0, 0, 0, 0);

/// Distance from p to the segment a–b and the parameter t ∈ [0, 1] of the closest point.
double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        double& t) {
  const Eigen::Vector3d d = b - a;
  t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - a - t * d).norm();
}

/// checked_unit_motor's test, with its message (a string built per call) made only on failure, so that
/// pose() allocates nothing per frame.
ga::Mot unit_frame(const ga::Mot& m, const std::string& bone) {
  bool ok = true;
  for (double c : m.c) ok = ok && std::isfinite(c);
  if (ok) {
    const auto nn = m * ga::reverse(m);
    ok = std::abs(nn.get<ga::blade::s>() - 1.0) <= 1e-6 && std::abs(nn.get<ga::blade::e123ni>()) <= 1e-6;
  }
  return ok ? ga::normalize(m) : checked_unit_motor(m, "frame of bone '" + bone + "'");
}

}  // namespace

void check_skeleton(std::span<const Bone> bones) {
  const int B = static_cast<int>(bones.size());
  if (B == 0) throw Error("skeleton: no bones");
  std::map<std::string, int> names;
  for (int j = 0; j < B; ++j) {
    const Bone& b = bones[j];
    const std::string who = "skeleton: bone " + std::to_string(j) + " '" + b.name + "'";
    if (b.name.empty()) throw Error("skeleton: bone " + std::to_string(j) + " has an empty name");
    if (!names.emplace(b.name, j).second)
      throw Error(who + " has the same name as bone " + std::to_string(names[b.name]));
    if (b.parent < -1 || b.parent >= B || b.parent == j)
      throw Error(who + " has parent " + std::to_string(b.parent) + " (must be −1 or another bone's index)");
    if (!b.head.allFinite() || !b.tail.allFinite() || (b.tail - b.head).norm() == 0.0)
      throw Error(who + ": head and tail must be finite and distinct");
    checked_unit_motor(b.rest, who + ": rest frame");
  }
  for (int j = 0; j < B; ++j) {  // a chain of parents longer than B has a cycle
    int p = j;
    for (int steps = 0; p >= 0; ++steps, p = bones[p].parent)
      if (steps > B) throw Error("skeleton: bone '" + bones[j].name + "' is on a cycle of parents");
  }
}

std::vector<ga::Mot> inherit_bone_motions(std::span<const Bone> bones, std::span<const ga::Mot> given,
                                          const std::vector<bool>& has) {
  check_skeleton(bones);
  const std::size_t B = bones.size();
  if (given.size() != B || has.size() != B)
    throw Error("inherit_bone_motions: sizes differ from the bone count");
  std::vector<ga::Mot> out(B);
  for (std::size_t j = 0; j < B; ++j) {
    int p = static_cast<int>(j);
    while (p >= 0 && !has[p]) p = bones[p].parent;  // nearest ancestor (or itself) with an entry
    out[j] = p >= 0 ? given[p] : kIdentity;
  }
  return out;
}

Eigen::MatrixXd bone_harmonic_weights(const Mesh& mesh, std::span<const Bone> bones, double joint_fraction,
                                      HarmonicWeights weights) {
  check_skeleton(bones);
  if (!(joint_fraction >= 0.0 && joint_fraction < 0.5))
    throw Error("bone_harmonic_weights: joint_fraction must be in [0, 0.5)");
  const int B = static_cast<int>(bones.size());
  std::vector<bool> has_child(B, false);
  for (const Bone& b : bones)
    if (b.parent >= 0) has_child[b.parent] = true;
  std::vector<std::vector<int>> region(B);
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    const Eigen::Vector3d p = mesh.V.row(i).transpose();
    int best = 0;
    double dbest = INFINITY, tbest = 0.0;
    for (int j = 0; j < B; ++j) {
      double t;
      const double d = segment_distance(p, bones[j].head, bones[j].tail, t);
      if (d < dbest) dbest = d, best = j, tbest = t;
    }
    const bool near_head = bones[best].parent >= 0 && tbest < joint_fraction;
    const bool near_tail = has_child[best] && tbest > 1.0 - joint_fraction;
    if (!near_head && !near_tail) region[best].push_back(static_cast<int>(i));
  }
  std::vector<Handle> handles(B);
  for (int j = 0; j < B; ++j) {
    if (region[j].empty())
      throw Error("bone_harmonic_weights: bone '" + bones[j].name +
                  "' is the nearest bone of no vertex away from its joints");
    handles[j] = {"bone '" + bones[j].name + "'",
                  Eigen::Map<Eigen::VectorXi>(region[j].data(), region[j].size())};
  }
  return harmonic_coordinates(mesh.V, mesh.F, handles, weights);
}

Eigen::MatrixXd read_skin_weights(const std::filesystem::path& path, std::span<const Bone> bones,
                                  Eigen::Index n) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open the skin weight file");
  const int B = static_cast<int>(bones.size());
  std::map<std::string, int> skeleton;
  for (int j = 0; j < B; ++j) skeleton[bones[j].name] = j;
  std::vector<int> column;  // file column -> skeleton bone
  Eigen::MatrixXd W(n, B);
  Eigen::Index row = 0;
  std::string line;
  std::size_t lineno = 0;
  auto fail = [&](const std::string& msg) {
    throw Error(path.string() + ":" + std::to_string(lineno) + ": " + msg);
  };
  while (std::getline(in, line)) {
    ++lineno;
    if (const auto h = line.find('#'); h != std::string::npos) line.resize(h);
    std::istringstream s(line);
    std::string tok;
    std::vector<std::string> toks;
    while (s >> tok) toks.push_back(tok);
    if (toks.empty()) continue;
    if (column.empty()) {
      if (toks[0] != "bones") fail("expected the header 'bones <name> ...' first");
      std::vector<bool> seen(B, false);
      for (std::size_t c = 1; c < toks.size(); ++c) {
        const auto it = skeleton.find(toks[c]);
        if (it == skeleton.end()) fail("bone '" + toks[c] + "' is not in the skeleton");
        if (seen[it->second]) fail("bone '" + toks[c] + "' is named twice");
        seen[it->second] = true;
        column.push_back(it->second);
      }
      for (int j = 0; j < B; ++j)
        if (!seen[j]) fail("the header does not name skeleton bone '" + bones[j].name + "'");
      continue;
    }
    if (row >= n) fail("more vertex lines than the mesh's " + std::to_string(n) + " vertices");
    if (static_cast<int>(toks.size()) != B)
      fail(std::to_string(toks.size()) + " values for " + std::to_string(B) + " bones (vertex " +
           std::to_string(row) + ")");
    double sum = 0.0;
    for (int c = 0; c < B; ++c) {
      double v = 0.0;
      std::size_t used = 0;
      try {
        v = std::stod(toks[c], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != toks[c].size())
        fail("'" + toks[c] + "' is not a number (vertex " + std::to_string(row) + ")");
      if (!std::isfinite(v) || v < 0.0)
        fail("weight " + toks[c] + " of vertex " + std::to_string(row) + " must be finite and ≥ 0");
      W(row, column[c]) = v;
      sum += v;
    }
    if (!(sum > 0.0)) fail("vertex " + std::to_string(row) + " has no positive weight");
    ++row;
  }
  if (column.empty()) throw Error(path.string() + ": no 'bones' header (empty file?)");
  if (row != n)
    throw Error(path.string() + ": " + std::to_string(row) + " vertex lines for a mesh of " +
                std::to_string(n) + " vertices");
  return W;
}

SkinDeformer SkinDeformer::bind(const Mesh& rest, std::span<const Bone> bones, const Eigen::MatrixXd& W,
                                const Options& options) {
  std::vector<std::vector<std::pair<int, double>>> rows(W.rows());
  for (Eigen::Index i = 0; i < W.rows(); ++i)
    for (Eigen::Index j = 0; j < W.cols(); ++j)
      if (W(i, j) != 0.0) rows[i].emplace_back(static_cast<int>(j), W(i, j));
  if (W.cols() != static_cast<Eigen::Index>(bones.size()))
    throw Error("SkinDeformer: " + std::to_string(W.cols()) + " weight columns for " +
                std::to_string(bones.size()) + " bones");
  if (W.rows() != rest.V.rows())
    throw Error("SkinDeformer: " + std::to_string(W.rows()) + " weight rows for " +
                std::to_string(rest.V.rows()) + " vertices");
  return bind_rows(rest, bones, std::move(rows), options);
}

SkinDeformer SkinDeformer::bind(const Mesh& rest, std::span<const Bone> bones,
                                const Eigen::SparseMatrix<double>& W, const Options& options) {
  if (W.cols() != static_cast<Eigen::Index>(bones.size()) || W.rows() != rest.V.rows())
    throw Error("SkinDeformer: weights are " + std::to_string(W.rows()) + "×" + std::to_string(W.cols()) +
                " for " + std::to_string(rest.V.rows()) + " vertices and " + std::to_string(bones.size()) +
                " bones");
  std::vector<std::vector<std::pair<int, double>>> rows(W.rows());
  for (Eigen::Index j = 0; j < W.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(W, j); it; ++it)
      if (it.value() != 0.0) rows[it.row()].emplace_back(static_cast<int>(it.col()), it.value());
  for (auto& r : rows) std::sort(r.begin(), r.end());
  return bind_rows(rest, bones, std::move(rows), options);
}

SkinDeformer SkinDeformer::bind_rows(const Mesh& rest, std::span<const Bone> bones,
                                     std::vector<std::vector<std::pair<int, double>>> rows,
                                     const Options& options) {
  check_skeleton(bones);
  if (options.max_influences < 0) throw Error("SkinDeformer: max_influences must be ≥ 0 (0 = all)");
  const Eigen::Index n = rest.V.rows();
  const bool motor_log = options.blend == Blend::Log || options.blend == Blend::PivotLog;
  const std::size_t cap =
      motor_log ? std::size_t(options.max_influences == 0 ? 4 : std::min(options.max_influences, 4))
      : options.max_influences == 0 ? std::numeric_limits<std::size_t>::max()
                                    : std::size_t(options.max_influences);
  SkinDeformer d;
  d.options_ = options;
  d.bones_.assign(bones.begin(), bones.end());
  d.P_ = rest.V;
  d.inf_.resize(n);
  d.kept_begin_.assign(1, 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!rest.V.row(i).allFinite())
      throw Error("SkinDeformer: vertex " + std::to_string(i) + " is not finite");
    auto& r = rows[i];
    for (const auto& [j, w] : r)
      if (!std::isfinite(w) || w < 0.0)
        throw Error("SkinDeformer: weight of vertex " + std::to_string(i) + " for bone '" + bones[j].name +
                    "' is negative or not finite");
    // the largest, ties to the lower bone index (the pivot is then ga::blend's first maximum)
    std::stable_sort(r.begin(), r.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    if (r.size() > cap) r.resize(cap);
    double sum = 0.0;
    for (const auto& e : r) sum += e.second;
    if (std::isinf(sum)) {  // finite weights near DBL_MAX: normalise them relative to the largest first
      const double largest = r[0].second;
      sum = 0.0;
      for (auto& e : r) sum += (e.second /= largest);
    }
    if (!(sum > 0.0))
      throw Error("SkinDeformer: vertex " + std::to_string(i) + " has no positive bone weight");
    for (auto& e : r) e.second /= sum;
    const std::size_t top = std::min<std::size_t>(r.size(), 4);
    double top_sum = 0.0;
    for (std::size_t s = 0; s < top; ++s) top_sum += r[s].second;
    for (std::size_t s = 0; s < top; ++s)
      d.inf_[i].bone[s] = r[s].first, d.inf_[i].w[s] = r[s].second / top_sum;
    for (std::size_t s = top; s < 4; ++s) d.inf_[i].bone[s] = r[0].first;  // weight 0, a valid bone
    d.kept_.insert(d.kept_.end(), r.begin(), r.end());
    d.kept_begin_.push_back(d.kept_.size());
  }
  const std::size_t B = bones.size();
  const Eigen::Index blocks = (n + kLbsBlock - 1) / kLbsBlock;
  std::vector<int> slot(B, -1);  // bone -> its entry in the current block
  d.lbs_begin_.assign(1, 0);
  for (Eigen::Index k = 0; k < blocks; ++k) {
    const std::size_t first = d.lbs_bones_.size();
    const Eigen::Index s0 = k * kLbsBlock, len = std::min(kLbsBlock, n - s0);
    for (Eigen::Index i = s0; i < s0 + len; ++i)
      for (std::size_t e = d.kept_begin_[i]; e < d.kept_begin_[i + 1]; ++e) {
        const auto [bone, w] = d.kept_[e];
        if (w == 0.0) continue;
        int& slot_e = slot[bone];
        if (slot_e < 0) {
          slot_e = static_cast<int>(d.lbs_bones_.size());
          d.lbs_bones_.push_back(bone);
          d.lbs_w_.resize(d.lbs_bones_.size() * kLbsBlock, 0.0);
        }
        d.lbs_w_[static_cast<std::size_t>(slot_e) * kLbsBlock + static_cast<std::size_t>(i - s0)] = w;
      }
    for (std::size_t e = first; e < d.lbs_bones_.size(); ++e) slot[d.lbs_bones_[e]] = -1;
    d.lbs_begin_.push_back(d.lbs_bones_.size());
    int pivot = d.inf_[s0].bone[0];  // DLB: one pivot bone for the whole block, or -1
    for (Eigen::Index i = s0; i < s0 + len; ++i)
      if (d.inf_[i].bone[0] != pivot) pivot = -1;
    d.lbs_pivot_.push_back(pivot);
  }
  d.motions_.resize(B);
  d.matrices_.resize(B);
  d.stretch_.resize(B);
  d.logs_.resize(options.blend == Blend::PivotLog ? B * B : B);
  d.signs_.resize(options.blend == Blend::DLB ? B * B : 0);
  for (const Bone& b : bones) d.controls_.push_back({b.name, b.head});
  return d;
}

void SkinDeformer::prepare(std::span<const ga::Mot> frames) {
  const std::size_t B = bones_.size();
  if (frames.size() != B)
    throw Error("SkinDeformer: " + std::to_string(frames.size()) + " bone frames for " + std::to_string(B) +
                " bones");
  for (std::size_t j = 0; j < B; ++j)  // K_j = F_j ~F_j^0
    motions_[j] = ga::normalize(unit_frame(frames[j], bones_[j].name) * ga::reverse(bones_[j].rest));
  prepare_blend();
}

void SkinDeformer::prepare_blend() {
  const std::size_t B = bones_.size();
  switch (options_.blend) {
    case Blend::LBS:
      for (std::size_t j = 0; j < B; ++j) matrices_[j] = ga::to_isometry(motions_[j]).matrix().topRows<3>();
      break;
    case Blend::Log:
      for (std::size_t j = 0; j < B; ++j) logs_[j] = ga::log(motions_[j]);
      break;
    case Blend::PivotLog:
      for (std::size_t p = 0; p < B; ++p) {
        const ga::Mot inv = ga::reverse(motions_[p]);
        for (std::size_t j = 0; j < B; ++j)
          logs_[p * B + j] = j == p ? ga::Dll{} : ga::log(motions_[j] * inv);
      }
      break;
    case Blend::DLB:
      for (std::size_t p = 0; p < B; ++p) {
        const ga::Mot rp = ga::reverse(motions_[p]);
        for (std::size_t j = 0; j < B; ++j)
          signs_[p * B + j] = std::signbit(ga::scalar(motions_[j], rp)) ? -1.0 : 1.0;
      }
      break;
  }
}

void SkinDeformer::pose(std::span<const ga::Mot> frames, Eigen::MatrixXd& V_out) {
  prepare(frames);
  if (V_out.rows() != vertices() || V_out.cols() != 3) V_out.resize(vertices(), 3);
  if (options_.blend == Blend::LBS)
    blend_lbs(P_, matrices_.data(), V_out);
  else
    blend_motors(P_, V_out);
}

void SkinDeformer::pose_affine(std::span<const Affine> transforms, const Eigen::MatrixXd* points,
                               Eigen::MatrixXd& V_out) {
  const std::size_t B = bones_.size();
  if (transforms.size() != B)
    throw Error("SkinDeformer: " + std::to_string(transforms.size()) + " bone transforms for " +
                std::to_string(B) + " bones");
  const Eigen::MatrixXd& P = points ? *points : P_;
  if (P.rows() != vertices() || P.cols() != 3)
    throw Error("SkinDeformer: " + std::to_string(P.rows()) + "×" + std::to_string(P.cols()) +
                " points for " + std::to_string(vertices()) + " vertices");
  if (V_out.rows() != vertices() || V_out.cols() != 3) V_out.resize(vertices(), 3);
  for (std::size_t j = 0; j < B; ++j)
    if (!transforms[j].allFinite())
      throw Error("SkinDeformer: the transform of bone '" + bones_[j].name + "' is not finite");
  if (options_.blend == Blend::LBS) return blend_lbs(P, transforms.data(), V_out);
  for (std::size_t j = 0; j < B; ++j)
    if (!(transforms[j].leftCols<3>().determinant() > 0))
      throw Error("SkinDeformer: the transform of bone '" + bones_[j].name +
                  "' mirrors or collapses space (det ≤ 0): only LBS blends such transforms");
  // Two phases (header comment): the stretches about the rest heads, then the rigid motions.
  bool stretched = false;
  for (std::size_t j = 0; j < B; ++j) {
    const Eigen::Matrix3d L = transforms[j].leftCols<3>();
    const Eigen::Matrix3d R = ga::closest_rotation(L);  // L = R S, the polar decomposition (det L > 0)
    const Eigen::Matrix3d S0 = R.transpose() * L;
    const Eigen::Matrix3d S = 0.5 * (S0 + S0.transpose());  // symmetric to roundoff
    const Eigen::Vector3d c = bones_[j].head;
    const bool rigid = (S - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-9;
    stretched = stretched || !rigid;
    stretch_[j].leftCols<3>() = rigid ? Eigen::Matrix3d::Identity() : S;
    stretch_[j].col(3) = rigid ? Eigen::Vector3d::Zero() : Eigen::Vector3d(c - S * c);
    Eigen::Isometry3d M = Eigen::Isometry3d::Identity();  // a rigid A_j's float noise projected onto R
    M.linear() = R;
    M.translation() = transforms[j].col(3) + (rigid ? Eigen::Vector3d::Zero() : Eigen::Vector3d((L - R) * c));
    motions_[j] = ga::normalize(ga::from_isometry(M));
  }
  prepare_blend();
  if (!stretched) return blend_motors(P, V_out);
  if (stretched_.rows() != vertices()) stretched_.resize(vertices(), 3);
  blend_lbs(P, stretch_.data(), stretched_);
  blend_motors(stretched_, V_out);
}

void SkinDeformer::blend_lbs(const Eigen::MatrixXd& P, const Eigen::Matrix<double, 3, 4>* T,
                             Eigen::MatrixXd& V_out) const {
  // v_i = Σ_j w_ij T_j [p_i; 1], bone by bone over blocks of vertices
  const Eigen::Index n = vertices();
  const Eigen::Index blocks = (n + kLbsBlock - 1) / kLbsBlock;
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend))
  for (Eigen::Index k = 0; k < blocks; ++k) {
    const Eigen::Index s0 = k * kLbsBlock, len = std::min(kLbsBlock, n - s0);
    const auto x = P.col(0).segment(s0, len).array(), y = P.col(1).segment(s0, len).array(),
               z = P.col(2).segment(s0, len).array();
    auto vx = V_out.col(0).segment(s0, len).array(), vy = V_out.col(1).segment(s0, len).array(),
         vz = V_out.col(2).segment(s0, len).array();
    vx.setZero(), vy.setZero(), vz.setZero();
    for (std::size_t e = lbs_begin_[k]; e < lbs_begin_[k + 1]; ++e) {
      const Eigen::Matrix<double, 3, 4>& M = T[lbs_bones_[e]];
      const Eigen::Map<const Eigen::ArrayXd> w(lbs_w_.data() + static_cast<Eigen::Index>(e) * kLbsBlock, len);
      vx += w * (M(0, 0) * x + M(0, 1) * y + M(0, 2) * z + M(0, 3));
      vy += w * (M(1, 0) * x + M(1, 1) * y + M(1, 2) * z + M(1, 3));
      vz += w * (M(2, 0) * x + M(2, 1) * y + M(2, 2) * z + M(2, 3));
    }
  }
}

void SkinDeformer::blend_motors(const Eigen::MatrixXd& P, Eigen::MatrixXd& V_out) const {
  const Eigen::Index n = vertices(), B = static_cast<Eigen::Index>(bones_.size());
  const Influence* inf = inf_.data();
  if (options_.blend == Blend::DLB) {  // Σ_j s_pj w_ij K_j bone by bone over blocks, then dlb_point's formula
    const ga::Mot* K = motions_.data();
    const double* S = signs_.data();
    const Eigen::Index blocks = (n + kLbsBlock - 1) / kLbsBlock;
    bool cancelled = false;
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend)) \
    reduction(||                                                                         \
              : cancelled)
    for (Eigen::Index k = 0; k < blocks; ++k) {
      using A = Eigen::Array<double, Eigen::Dynamic, 1, 0, kLbsBlock, 1>;  // on the stack
      const Eigen::Index s0 = k * kLbsBlock, len = std::min(kLbsBlock, n - s0);
      std::array<A, 8> m;
      for (A& c : m) c.setZero(len);
      A ws(len);
      for (std::size_t e = lbs_begin_[k]; e < lbs_begin_[k + 1]; ++e) {
        const int j = lbs_bones_[e];
        const double* w = lbs_w_.data() + static_cast<Eigen::Index>(e) * kLbsBlock;
        const double* kj = K[j].data();
        if (const int p = lbs_pivot_[k]; p >= 0) {  // one pivot bone p for the block: one sign s_pj
          const Eigen::Map<const Eigen::ArrayXd> wm(w, len);
          const double sj = S[static_cast<Eigen::Index>(p) * B + j];
          for (int c = 0; c < 8; ++c) m[c] += (sj * kj[c]) * wm;
          continue;
        }
        for (Eigen::Index i = 0; i < len; ++i)  // s_pj: the sign of K_j against the vertex's pivot bone p
          ws[i] = w[i] * S[static_cast<Eigen::Index>(inf[s0 + i].bone[0]) * B + j];
        for (int c = 0; c < 8; ++c) m[c] += kj[c] * ws;
      }
      // dlb_point's formula (dlb_point.hpp), across the block
      const auto px = P.col(0).segment(s0, len).array(), py = P.col(1).segment(s0, len).array(),
                 pz = P.col(2).segment(s0, len).array();
      auto ox = V_out.col(0).segment(s0, len).array(), oy = V_out.col(1).segment(s0, len).array(),
           oz = V_out.col(2).segment(s0, len).array();
      detail::dlb_point_into<A>(m, px, py, pz, ox, oy, oz);
      cancelled = cancelled || !(ox.isFinite().all() && oy.isFinite().all() && oz.isFinite().all());
    }
    if (cancelled)
      throw numerical_error("SkinDeformer: the linear blend of the bone motors cancels at a vertex");
    return;
  }
  const bool pivot = options_.blend == Blend::PivotLog;
  const ga::Dll* L = logs_.data();
  const ga::Mot* K = motions_.data();
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend))
  for (Eigen::Index i = 0; i < n; ++i) {
    const Influence& f = inf[i];
    const ga::Dll* l = pivot ? L + static_cast<Eigen::Index>(f.bone[0]) * B : L;
    ga::Dll acc;
    for (int s = 0; s < 4; ++s)
      for (int c = 0; c < 6; ++c) acc.c[c] += f.w[s] * l[f.bone[s]].c[c];
    ga::Mot m = ga::exp(acc);  // eq. (1)
    if (pivot) m = m * K[f.bone[0]];
    const Eigen::Vector3d q = ga::transform(m, Eigen::Vector3d(P(i, 0), P(i, 1), P(i, 2)));
    V_out(i, 0) = q.x(), V_out(i, 1) = q.y(), V_out(i, 2) = q.z();
  }
}

Eigen::SparseMatrix<double> SkinDeformer::weights() const {
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index i = 0; i < vertices(); ++i)
    for (std::size_t e = kept_begin_[i]; e < kept_begin_[i + 1]; ++e)
      if (kept_[e].second != 0.0) t.emplace_back(i, kept_[e].first, kept_[e].second);
  Eigen::SparseMatrix<double> W(vertices(), static_cast<Eigen::Index>(bones_.size()));
  W.setFromTriplets(t.begin(), t.end());
  return W;
}

ga::Mot SkinDeformer::vertex_motor(Eigen::Index i, std::span<const ga::Mot> frames) const {
  if (i < 0 || i >= vertices())
    throw Error("SkinDeformer::vertex_motor: vertex " + std::to_string(i) + " out of range");
  if (frames.size() != bones_.size()) throw Error("SkinDeformer::vertex_motor: wrong frame count");
  std::vector<ga::Mot> m;
  std::vector<double> w;
  for (int s = 0; s < 4; ++s)
    if (inf_[i].w[s] != 0.0) {
      m.push_back(ga::normalize(frames[inf_[i].bone[s]] * ga::reverse(bones_[inf_[i].bone[s]].rest)));
      w.push_back(inf_[i].w[s]);
    }
  const ga::Blend mode = options_.blend == Blend::Log        ? ga::Blend::Log
                         : options_.blend == Blend::PivotLog ? ga::Blend::PivotLog
                                                             : ga::Blend::DLB;
  return ga::blend(m, w, mode);
}

}  // namespace spinmotor

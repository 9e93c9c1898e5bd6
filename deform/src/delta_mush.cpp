#include "spinmotor/deform/delta_mush.hpp"

#include <cmath>
#include <string>

#include "mush_detail.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"

namespace spinmotor {

namespace {

constexpr const char* kDeltaMush = "DeltaMushDeformer";

/// A projected tangent shorter than this fraction of its edge counts as vanished (the edge is along n).
constexpr double kTangentFloor = 1e-10;

}  // namespace

DeltaMushDeformer DeltaMushDeformer::bind(const Mesh& rest, std::span<const Bone> bones,
                                          const Eigen::MatrixXd& weights, const Options& options) {
  return finish(rest, SkinDeformer::bind(rest, bones, weights, {options.blend}), options);
}

DeltaMushDeformer DeltaMushDeformer::bind(const Mesh& rest, std::span<const Bone> bones,
                                          const Eigen::SparseMatrix<double>& weights,
                                          const Options& options) {
  return finish(rest, SkinDeformer::bind(rest, bones, weights, {options.blend}), options);
}

DeltaMushDeformer DeltaMushDeformer::finish(const Mesh& rest, SkinDeformer skin, const Options& options) {
  if (options.iterations < 0)
    throw Error(std::string(kDeltaMush) + ": iterations must be >= 0, got " +
                std::to_string(options.iterations));
  if (!(options.step > 0.0 && options.step <= 1.0))
    throw Error(std::string(kDeltaMush) + ": step must be in (0, 1], got " + std::to_string(options.step));
  detail::require_mush_mesh(rest, /*oriented=*/true, kDeltaMush);

  DeltaMushDeformer d;
  d.options_ = options;
  d.skin_ = std::move(skin);
  const Eigen::Index n = rest.V.rows(), m = rest.F.rows();
  const detail::Rings rings = detail::vertex_rings(edge_topology(rest.F).E, n);
  d.ring_offset_ = rings.offset;
  d.ring_ = rings.index;

  d.fan_offset_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) ++d.fan_offset_[rest.F(f, c) + 1];
  for (Eigen::Index i = 0; i < n; ++i) d.fan_offset_[i + 1] += d.fan_offset_[i];
  d.fan_.resize(d.fan_offset_[n]);
  std::vector<int> fill(d.fan_offset_.begin(), d.fan_offset_.end() - 1);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c)
      d.fan_[fill[rest.F(f, c)]++] = {rest.F(f, (c + 1) % 3), rest.F(f, (c + 2) % 3)};

  for (auto* buf : {&d.a_, &d.b_, &d.tan_, &d.bit_, &d.nrm_}) buf->resize(n, 3);
  d.smooth(rest.V);
  if (const int bad = d.frames(); bad >= 0)
    throw Error(std::string(kDeltaMush) + ": the smoothed rest mesh has no normal or no tangent at vertex " +
                std::to_string(bad) + " (its one-ring collapsed under " + std::to_string(options.iterations) +
                " smoothing iterations)");
  d.delta_.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d e = rest.V.row(i).transpose() - d.a_.row(i).transpose();
    d.delta_(i, 0) = e.dot(d.tan_.row(i));
    d.delta_(i, 1) = e.dot(d.bit_.row(i));
    d.delta_(i, 2) = e.dot(d.nrm_.row(i));
  }
  d.skinned_.resize(n, 3);
  return d;
}

void DeltaMushDeformer::smooth(const Eigen::MatrixXd& x) {
  const Eigen::Index n = x.rows();
  a_ = x;  // storage conversion into preallocated row-major scratch (same size: no allocation)
  const double lambda = options_.step;
  const int* off = ring_offset_.data();
  const int* nb = ring_.data();
  for (int it = 0; it < options_.iterations; ++it) {
    const double* src = a_.data();
    double* dst = b_.data();
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend))
    for (Eigen::Index i = 0; i < n; ++i) {
      double s0 = 0.0, s1 = 0.0, s2 = 0.0;
      for (int k = off[i]; k < off[i + 1]; ++k) {
        const double* q = src + 3 * static_cast<Eigen::Index>(nb[k]);
        s0 += q[0], s1 += q[1], s2 += q[2];
      }
      const double inv = 1.0 / (off[i + 1] - off[i]);  // ≥ 1 neighbour: no unreferenced vertex (bind)
      const double* p = src + 3 * i;
      double* o = dst + 3 * i;
      o[0] = p[0] + lambda * (s0 * inv - p[0]);
      o[1] = p[1] + lambda * (s1 * inv - p[1]);
      o[2] = p[2] + lambda * (s2 * inv - p[2]);
    }
    a_.swap(b_);  // pointer swap
  }
}

int DeltaMushDeformer::frames() {
  const Eigen::Index n = a_.rows();
  const double* X = a_.data();
  const int* off = ring_offset_.data();
  const int* nb = ring_.data();
  const int* foff = fan_offset_.data();
  const std::array<int, 2>* fan = fan_.data();
  double* T = tan_.data();
  double* Bt = bit_.data();
  double* N = nrm_.data();
  int bad = static_cast<int>(n);
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend)) reduction(min : bad)
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Map<const Eigen::Vector3d> xi(X + 3 * i);
    Eigen::Vector3d nsum = Eigen::Vector3d::Zero();
    for (int k = foff[i]; k < foff[i + 1]; ++k) {
      const Eigen::Map<const Eigen::Vector3d> xa(X + 3 * static_cast<Eigen::Index>(fan[k][0]));
      const Eigen::Map<const Eigen::Vector3d> xb(X + 3 * static_cast<Eigen::Index>(fan[k][1]));
      nsum += (xa - xi).cross(xb - xi);  // 2·area·(unit face normal)
    }
    const double len = nsum.norm();
    bool ok = len > 0.0 && std::isfinite(len);
    Eigen::Vector3d nn = ok ? Eigen::Vector3d(nsum / len) : Eigen::Vector3d::UnitZ();
    Eigen::Vector3d t = Eigen::Vector3d::UnitX();
    bool found = false;
    for (int k = off[i]; ok && !found && k < off[i + 1]; ++k) {
      const Eigen::Vector3d e =
          Eigen::Map<const Eigen::Vector3d>(X + 3 * static_cast<Eigen::Index>(nb[k])) - xi;
      const Eigen::Vector3d p = e - e.dot(nn) * nn;
      const double pl = p.norm();
      if (pl > kTangentFloor * e.norm()) t = p / pl, found = true;
    }
    ok = ok && found;
    if (!ok) {
      bad = std::min(bad, static_cast<int>(i));
      nn = Eigen::Vector3d::UnitZ(), t = Eigen::Vector3d::UnitX();  // finite placeholders
    }
    const Eigen::Vector3d b = nn.cross(t);
    for (int c = 0; c < 3; ++c) T[3 * i + c] = t[c], Bt[3 * i + c] = b[c], N[3 * i + c] = nn[c];
  }
  return bad < n ? bad : -1;
}

void DeltaMushDeformer::pose(std::span<const ga::Mot> frames_in, Eigen::MatrixXd& V_out) {
  if (frames_in.size() != controls().size())
    throw Error(std::string(kDeltaMush) + ": " + std::to_string(frames_in.size()) + " bone frames for " +
                std::to_string(controls().size()) + " bones");
  skin_.pose(frames_in, skinned_);  // checks the frames, naming the bone
  smooth(skinned_);
  if (const int bad = frames(); bad >= 0)
    throw numerical_error(std::string(kDeltaMush) +
                          ": the smoothed posed mesh has no normal or no tangent at vertex " +
                          std::to_string(bad) + " (its one-ring collapsed)");
  const Eigen::Index n = vertices();
  if (V_out.rows() != n || V_out.cols() != 3) V_out.resize(n, 3);
  const Eigen::MatrixXd& D = delta_;
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend))
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d0 = D(i, 0), d1 = D(i, 1), d2 = D(i, 2);
    for (int c = 0; c < 3; ++c)
      V_out(i, c) = a_(i, c) + (d0 * tan_(i, c) + d1 * bit_(i, c) + d2 * nrm_(i, c));
  }
}

}  // namespace spinmotor

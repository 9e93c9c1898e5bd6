// Pins from skin weights: see rig_pins.hpp.
#include "spinmotor/deform/rig_pins.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <utility>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"

namespace spinmotor {

namespace {

void check_inputs(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W, double threshold, const char* who) {
  if (V.cols() != 3) throw Error(std::string(who) + ": V must be n×3");
  if (W.rows() != V.rows() || W.cols() < 1) {
    std::ostringstream s;
    s << who << ": the weights are " << W.rows() << "×" << W.cols() << ", expected " << V.rows()
      << "×B (B ≥ 1)";
    throw Error(s.str());
  }
  if (!(threshold > 0 && threshold <= 1)) {
    std::ostringstream s;
    s << who << ": threshold " << threshold << " is not in (0, 1]";
    throw Error(s.str());
  }
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if (!V.row(i).allFinite()) {
      std::ostringstream s;
      s << who << ": vertex " << i << " has a non-finite coordinate";
      throw Error(s.str());
    }
    double sum = 0;
    for (Eigen::Index j = 0; j < W.cols(); ++j) {
      const double w = W(i, j);
      if (!std::isfinite(w) || w < 0) {
        std::ostringstream s;
        s << who << ": weight of vertex " << i << " for bone " << j << " is " << w << " (need finite, ≥ 0)";
        throw Error(s.str());
      }
      sum += w;
    }
    if (!(sum > 0)) {
      std::ostringstream s;
      s << who << ": vertex " << i << " has no positive weight";
      throw Error(s.str());
    }
  }
}

/// Dominant weight (normalised) and the two largest bones of row i.
struct RowTop {
  double dominant;
  int first, second;
};

RowTop row_top(const Eigen::MatrixXd& W, Eigen::Index i) {
  int a = 0, b = -1;
  double sum = 0;
  for (Eigen::Index j = 0; j < W.cols(); ++j) sum += W(i, j);
  for (Eigen::Index j = 1; j < W.cols(); ++j)
    if (W(i, j) > W(i, a)) a = static_cast<int>(j);
  for (Eigen::Index j = 0; j < W.cols(); ++j)
    if (j != a && (b < 0 || W(i, j) > W(i, b))) b = static_cast<int>(j);
  return {W(i, a) / sum, a, b};
}

}  // namespace

Eigen::VectorXi pins_from_weights(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W, double threshold,
                                  double margin) {
  check_inputs(V, W, threshold, "pins_from_weights");
  if (!(margin >= 0) || !std::isfinite(margin)) {
    std::ostringstream s;
    s << "pins_from_weights: margin " << margin << " must be finite and ≥ 0";
    throw Error(s.str());
  }
  const Eigen::Index n = V.rows();
  std::vector<char> candidate(n);
  std::vector<int> blended;
  for (Eigen::Index i = 0; i < n; ++i) {
    candidate[i] = row_top(W, i).dominant >= threshold;
    if (!candidate[i]) blended.push_back(static_cast<int>(i));
  }
  if (margin > 0 && !blended.empty() && n > 0) {
    // Dense grid (CSR) of the blended vertices over the bounding box, cells of size h = margin/2,
    // doubled while the grid would have more than max(4n, 2^16) cells (which only costs more points per
    // cell); a candidate looks at the cells within ceil(margin/h) of its own, skips those whose box is
    // farther than the margin, and stops at the first non-empty box lying entirely within the margin
    // or at the first blended vertex within it.
    const Eigen::RowVector3d lo = V.colwise().minCoeff(), ext = V.colwise().maxCoeff() - lo;
    double h = 0.5 * margin;
    std::int64_t dims[3];
    const double max_cells = std::max(4.0 * static_cast<double>(n), 65536.0);
    for (;;) {
      double total = 1;
      for (int k = 0; k < 3; ++k) total *= std::floor(ext[k] / h) + 1;
      if (total <= max_cells) break;
      h *= 2;
    }
    for (int k = 0; k < 3; ++k) dims[k] = static_cast<std::int64_t>(std::floor(ext[k] / h)) + 1;
    const int R = static_cast<int>(std::ceil(margin / h));
    auto coord = [&](double x, int axis) {
      return std::clamp(static_cast<std::int64_t>(std::floor((x - lo[axis]) / h)), std::int64_t(0),
                        dims[axis] - 1);
    };
    auto index = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
      return (z * dims[1] + y) * dims[0] + x;
    };
    std::vector<int> start(static_cast<size_t>(dims[0] * dims[1] * dims[2]) + 1, 0), pts(blended.size());
    for (const int k : blended) ++start[index(coord(V(k, 0), 0), coord(V(k, 1), 1), coord(V(k, 2), 2)) + 1];
    for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
    {
      std::vector<int> fill(start.begin(), start.end() - 1);
      for (const int k : blended)
        pts[fill[index(coord(V(k, 0), 0), coord(V(k, 1), 1), coord(V(k, 2), 2))]++] = k;
    }
    const double m2 = margin * margin;
    const long nl = static_cast<long>(n);
#pragma omp parallel for schedule(dynamic, 1024) if (parallel::worth(nl, parallel::kMotorBlend))
    for (long i = 0; i < nl; ++i) {
      if (!candidate[i]) continue;
      const Eigen::RowVector3d p = V.row(i);
      const std::int64_t c[3] = {coord(p[0], 0), coord(p[1], 1), coord(p[2], 2)};
      bool near = false;
      for (std::int64_t z = std::max<std::int64_t>(0, c[2] - R);
           z <= std::min(dims[2] - 1, c[2] + R) && !near; ++z)
        for (std::int64_t y = std::max<std::int64_t>(0, c[1] - R);
             y <= std::min(dims[1] - 1, c[1] + R) && !near; ++y)
          for (std::int64_t x = std::max<std::int64_t>(0, c[0] - R); x <= std::min(dims[0] - 1, c[0] + R);
               ++x) {
            const std::int64_t cid = index(x, y, z);
            if (start[cid] == start[cid + 1]) continue;
            const std::int64_t g[3] = {x, y, z};
            double dmin2 = 0, dmax2 = 0;
            for (int k = 0; k < 3; ++k) {
              const double b0 = lo[k] + static_cast<double>(g[k]) * h, b1 = b0 + h;
              const double below = std::max({b0 - p[k], p[k] - b1, 0.0});
              const double far = std::max(std::abs(p[k] - b0), std::abs(p[k] - b1));
              dmin2 += below * below;
              dmax2 += far * far;
            }
            if (dmin2 > m2) continue;
            if (dmax2 <= m2) {
              near = true;
              break;
            }
            for (int q = start[cid]; q < start[cid + 1]; ++q)
              if ((V.row(pts[q]) - p).squaredNorm() <= m2) {
                near = true;
                break;
              }
            if (near) break;
          }
      if (near) candidate[i] = 0;
    }
  }
  std::vector<int> out;
  for (Eigen::Index i = 0; i < n; ++i)
    if (candidate[i]) out.push_back(static_cast<int>(i));
  return Eigen::Map<const Eigen::VectorXi>(out.data(), static_cast<Eigen::Index>(out.size()));
}

std::vector<JointBlend> joint_blend_bands(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W,
                                          std::span<const Bone> bones, double threshold) {
  check_inputs(V, W, threshold, "joint_blend_bands");
  if (static_cast<Eigen::Index>(bones.size()) != W.cols()) {
    std::ostringstream s;
    s << "joint_blend_bands: " << bones.size() << " bones for " << W.cols() << " weight columns";
    throw Error(s.str());
  }
  std::vector<Eigen::Vector3d> axis(bones.size());
  for (size_t j = 0; j < bones.size(); ++j) {
    const Eigen::Vector3d d = bones[j].tail - bones[j].head;
    if (!(d.norm() > 0) || !d.allFinite())
      throw Error("joint_blend_bands: bone '" + bones[j].name + "' has head == tail (no axis)");
    axis[j] = d.normalized();
  }
  struct Range {
    Eigen::Index count = 0;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  };
  std::map<std::pair<int, int>, Range> joints;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const RowTop t = row_top(W, i);
    if (t.dominant >= threshold || t.second < 0) continue;
    const int a = std::min(t.first, t.second), b = std::max(t.first, t.second);
    Range& r = joints[{a, b}];
    ++r.count;
    const Eigen::Vector3d p = V.row(i).transpose();
    const int ab[2] = {a, b};
    for (int s = 0; s < 2; ++s) {
      const double x = axis[ab[s]].dot(p);
      r.lo[s] = std::min(r.lo[s], x);
      r.hi[s] = std::max(r.hi[s], x);
    }
  }
  std::vector<JointBlend> out;
  for (const auto& [k, r] : joints)
    out.push_back({k.first, k.second, r.count, std::max(r.hi[0] - r.lo[0], r.hi[1] - r.lo[1])});
  return out;
}

double default_pin_margin(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W, std::span<const Bone> bones,
                          double threshold) {
  double w = 0;
  for (const JointBlend& j : joint_blend_bands(V, W, bones, threshold)) w = std::max(w, j.width);
  return 0.25 * w;
}

Eigen::VectorXi pins_from_weights(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W, double threshold,
                                  const Eigen::VectorXd& margins) {
  check_inputs(V, W, threshold, "pins_from_weights");
  if (margins.size() != W.cols())
    throw Error("pins_from_weights: " + std::to_string(margins.size()) + " margins for " +
                std::to_string(W.cols()) + " bones");
  // One pass of the scalar search per distinct margin, each keeping the candidates of its bones.
  std::vector<int> dominant(static_cast<size_t>(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) dominant[i] = row_top(W, i).first;
  std::vector<double> distinct(margins.data(), margins.data() + margins.size());
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  std::vector<int> out;
  for (const double m : distinct) {
    const Eigen::VectorXi p = pins_from_weights(V, W, threshold, m);
    for (Eigen::Index k = 0; k < p.size(); ++k)
      if (margins[dominant[p[k]]] == m) out.push_back(p[k]);
  }
  std::sort(out.begin(), out.end());
  return Eigen::Map<const Eigen::VectorXi>(out.data(), static_cast<Eigen::Index>(out.size()));
}

Eigen::VectorXd default_pin_margins(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W,
                                    std::span<const Bone> bones, double threshold) {
  Eigen::VectorXd m = Eigen::VectorXd::Zero(W.cols());
  for (const JointBlend& j : joint_blend_bands(V, W, bones, threshold)) {
    m[j.bone_a] = std::max(m[j.bone_a], 0.25 * j.width);
    m[j.bone_b] = std::max(m[j.bone_b], 0.25 * j.width);
  }
  return m;
}

Eigen::VectorXd pin_attraction_from_weights(const Eigen::MatrixXd& W, double threshold, double low) {
  check_inputs(Eigen::MatrixXd::Zero(W.rows(), 3), W, threshold, "pin_attraction_from_weights");
  if (!(low >= 0 && low < threshold)) {
    std::ostringstream s;
    s << "pin_attraction_from_weights: low " << low << " must be in [0, threshold = " << threshold << ")";
    throw Error(s.str());
  }
  Eigen::VectorXd a(W.rows());
  for (Eigen::Index i = 0; i < W.rows(); ++i) {
    const double t = std::clamp((row_top(W, i).dominant - low) / (threshold - low), 0.0, 1.0);
    a[i] = t * t * (3 - 2 * t);
  }
  return a;
}

}  // namespace spinmotor

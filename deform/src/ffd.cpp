#include "spinmotor/deform/ffd.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "dlb_point.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/deform/motor_blend_field.hpp"
#include "spinmotor/deform/spline_basis.hpp"

namespace spinmotor {

namespace {

using A8 = Eigen::Array<double, 8, 1>;
using A4 = Eigen::Array<double, 4, 1>;

/// Clamped uniform knot vector of `count` controls, degree d: d+1 zeros, i/(count−d), d+1 ones.
/// Greville abscissa of control a: the mean of knots a+1 .. a+d.
double greville(int a, int count, int d) {
  double s = 0.0;
  for (int j = a + 1; j <= a + d; ++j) s += clamped_knot(j, count, d);
  return s / d;
}

/// Σ over the supporting controls of w_abc · lanes[index(abc)] for one vertex: the tensor contraction of
/// eq. 6, innermost axis first. O > 0: every axis has O non-zero functions (unrolled); O = 0: runtime.
/// `sign` (DLB) multiplies control c's lane by its sign relative to the pivot.
template <int O, class Lane, bool Signed>
[[gnu::always_inline]] inline Lane contract(const Lane* lanes, const std::array<int, 3>& dims,
                                            const std::array<int, 3>& order, const std::array<int, 3>& start,
                                            const double* bu, const double* sign) {
  const int oa = O ? O : order[0], ob = O ? O : order[1], oc = O ? O : order[2];
  const Eigen::Index m = dims[1], n = dims[2];
  const double* bv = bu + oa;
  const double* bw = bv + ob;
  Lane acc = Lane::Zero();
  for (int a = 0; a < oa; ++a) {
    Lane ta = Lane::Zero();
    for (int b = 0; b < ob; ++b) {
      const Eigen::Index base = (static_cast<Eigen::Index>(start[0] + a) * m + start[1] + b) * n + start[2];
      const Lane* row = lanes + base;
      Lane t = Lane::Zero();
      for (int c = 0; c < oc; ++c) {
        if constexpr (Signed)
          t += (sign[base + c] * bw[c]) * row[c];
        else
          t += bw[c] * row[c];
      }
      ta += bv[b] * t;
    }
    acc += bu[a] * ta;
  }
  return acc;
}

enum class Kernel { Position, Log, DLB };

/// The Position and DLB kernels, vertex by vertex (Log: run_log below).
template <int O, Kernel K>
void run(const Eigen::MatrixXd& P, const std::vector<unsigned char>& inside,
         const std::vector<std::array<int, 3>>& start, const std::vector<double>& basis,
         const std::array<int, 3>& dims, const std::array<int, 3>& order, const void* lanes,
         const double* signs, const std::vector<int>& pivot, Eigen::MatrixXd& V_out) {
  const Eigen::Index n = P.rows(), L = static_cast<Eigen::Index>(dims[0]) * dims[1] * dims[2];
  const int stride = order[0] + order[1] + order[2];
  bool cancelled = false;
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend)) \
    reduction(||                                                                         \
              : cancelled)
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d p(P(i, 0), P(i, 1), P(i, 2));
    if (!inside[i]) {
      V_out(i, 0) = p.x(), V_out(i, 1) = p.y(), V_out(i, 2) = p.z();
      continue;
    }
    const double* b = basis.data() + i * stride;
    Eigen::Vector3d q;
    if constexpr (K == Kernel::Position) {
      const A4 s = contract<O, A4, false>(static_cast<const A4*>(lanes), dims, order, start[i], b, nullptr);
      q = Eigen::Vector3d(s[0], s[1], s[2]);  // eq. 8
    } else {
      const A8 s = contract<O, A8, true>(static_cast<const A8*>(lanes), dims, order, start[i], b,
                                         signs + static_cast<Eigen::Index>(pivot[i]) * L);
      q = detail::dlb_point(s.data(), p);  // normalize(Σ s_c w_c R_c) applied to p
      if (!q.allFinite()) cancelled = true, q = p;
    }
    V_out(i, 0) = q.x(), V_out(i, 1) = q.y(), V_out(i, 2) = q.z();
  }
  if (cancelled)
    throw numerical_error("FfdDeformer: the linear blend of the control motors cancels at a vertex");
}

/// The Log kernel by blocks of 4 vertices: each vertex's blended generator Σ w_c log R_c (the tensor
/// contraction as in run()), then exp and the point transform across the block in SIMD lanes
/// (ga::detail::exp_lanes, transform_lanes). Outside vertices get the zero generator and keep their
/// rest position.
template <int O>
void run_log(const Eigen::MatrixXd& P, const std::vector<unsigned char>& inside,
             const std::vector<std::array<int, 3>>& start, const std::vector<double>& basis,
             const std::array<int, 3>& dims, const std::array<int, 3>& order, const A8* lanes,
             Eigen::MatrixXd& V_out) {
  constexpr int K = 4;
  using Lanes = ga::detail::Lanes<K>;
  const Eigen::Index n = P.rows(), blocks = (n + K - 1) / K;
  const int stride = order[0] + order[1] + order[2];
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend))
  for (Eigen::Index blk = 0; blk < blocks; ++blk) {
    const Eigen::Index i0 = blk * K;
    const int count = static_cast<int>(std::min<Eigen::Index>(K, n - i0));
    Lanes g[6], p[3];
    for (int v = 0; v < K; ++v) {
      const Eigen::Index i = i0 + std::min(v, count - 1);  // a short last block repeats its last vertex
      for (int c = 0; c < 3; ++c) p[c][v] = P(i, c);
      if (!inside[i]) {
        for (int c = 0; c < 6; ++c) g[c][v] = 0.0;
        continue;
      }
      const A8 s = contract<O, A8, false>(lanes, dims, order, start[i], basis.data() + i * stride, nullptr);
      for (int c = 0; c < 6; ++c) g[c][v] = s[c];
    }
    Lanes m[8], q[3];
    ga::detail::exp_lanes(g, m);  // exp(Σ w log R)
    ga::detail::transform_lanes(m, p, q);
    for (int v = 0; v < count; ++v) {
      const Eigen::Index i = i0 + v;
      if (inside[i])
        V_out(i, 0) = q[0][v], V_out(i, 1) = q[1][v], V_out(i, 2) = q[2][v];
      else
        V_out(i, 0) = p[0][v], V_out(i, 1) = p[1][v], V_out(i, 2) = p[2][v];
    }
  }
}

template <Kernel K>
void dispatch(const Eigen::MatrixXd& P, const std::vector<unsigned char>& inside,
              const std::vector<std::array<int, 3>>& start, const std::vector<double>& basis,
              const std::array<int, 3>& dims, const std::array<int, 3>& order, const void* lanes,
              const double* signs, const std::vector<int>& pivot, Eigen::MatrixXd& V_out) {
  const bool cubic = order[0] == 4 && order[1] == 4 && order[2] == 4;
  if constexpr (K == Kernel::Log) {
    if (cubic)
      run_log<4>(P, inside, start, basis, dims, order, static_cast<const A8*>(lanes), V_out);
    else
      run_log<0>(P, inside, start, basis, dims, order, static_cast<const A8*>(lanes), V_out);
  } else if (cubic) {
    run<4, K>(P, inside, start, basis, dims, order, lanes, signs, pivot, V_out);
  } else {
    run<0, K>(P, inside, start, basis, dims, order, lanes, signs, pivot, V_out);
  }
}

}  // namespace

FfdDeformer FfdDeformer::bind(const Mesh& rest, const Options& options) { return bind(rest.V, options); }

FfdDeformer FfdDeformer::bind(const Eigen::MatrixXd& V, const Options& options) {
  const Eigen::Index n = V.rows();
  if (V.cols() != 3) throw Error("FfdDeformer: V must have 3 columns");
  if (n == 0) throw Error("FfdDeformer: the mesh has no vertices");
  for (Eigen::Index i = 0; i < n; ++i)
    if (!V.row(i).allFinite()) throw Error("FfdDeformer: vertex " + std::to_string(i) + " is not finite");
  static const char* kAxis[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a)
    if (options.lattice[a] < 2 || options.lattice[a] > 256)
      throw Error(std::string("FfdDeformer: lattice size along ") + kAxis[a] + " is " +
                  std::to_string(options.lattice[a]) + " (must be in [2, 256])");
  if (options.basis == Basis::BSpline && (options.degree < 1 || options.degree > 31))
    throw Error("FfdDeformer: B-spline degree " + std::to_string(options.degree) + " (must be in [1, 31])");
  if (options.mode == Mode::Motor && options.blend == ga::Blend::PivotLog)
    throw Error("FfdDeformer: the pivot-log blend is not offered for FFD (use log or dlb)");
  FfdDeformer f;
  f.options_ = options;
  f.dims_ = options.lattice;
  const Eigen::Index L = static_cast<Eigen::Index>(f.dims_[0]) * f.dims_[1] * f.dims_[2];
  if (options.mode == Mode::Motor && options.blend == ga::Blend::DLB && L > 2048)
    throw Error("FfdDeformer: the dlb blend is limited to 2048 controls (" + std::to_string(L) + " given)");
  for (int a = 0; a < 3; ++a) {
    if (options.basis == Basis::Bezier && f.dims_[a] > 32)
      throw Error(std::string("FfdDeformer: a Bezier lattice of more than 32 controls along ") + kAxis[a] +
                  " (use bspline)");
    f.order_[a] =
        1 + (options.basis == Basis::Bezier ? f.dims_[a] - 1 : std::min(options.degree, f.dims_[a] - 1));
  }

  if (options.box) {
    f.box_ = *options.box;
    if (!f.box_.min().allFinite() || !f.box_.max().allFinite() || !(f.box_.sizes().array() > 0.0).all())
      throw Error("FfdDeformer: the lattice box must be finite with max > min on every axis");
  } else {
    if (!(options.margin >= 0.0) || !std::isfinite(options.margin))
      throw Error("FfdDeformer: the box margin must be finite and ≥ 0");
    Eigen::AlignedBox3d b(V.colwise().minCoeff().transpose(), V.colwise().maxCoeff().transpose());
    const Eigen::Vector3d size = b.sizes();
    const double big = size.maxCoeff() > 0.0 ? size.maxCoeff() : 1.0;
    Eigen::Vector3d grow;
    for (int a = 0; a < 3; ++a)
      grow[a] = size[a] > 0.0 ? options.margin * size[a] : std::max(options.margin, 0.05) * big;
    f.box_ = Eigen::AlignedBox3d(b.min() - grow, b.max() + grow);
  }

  // Rest control points at the Greville abscissae (linear precision).
  f.C_.resize(L, 3);
  for (int a = 0; a < f.dims_[0]; ++a)
    for (int b = 0; b < f.dims_[1]; ++b)
      for (int c = 0; c < f.dims_[2]; ++c) {
        const Eigen::Vector3d xi(greville(a, f.dims_[0], f.order_[0] - 1),
                                 greville(b, f.dims_[1], f.order_[1] - 1),
                                 greville(c, f.dims_[2], f.order_[2] - 1));
        f.C_.row(f.index(a, b, c)) = (f.box_.min() + xi.cwiseProduct(f.box_.sizes())).transpose();
      }

  f.P_ = V;
  const int stride = f.order_[0] + f.order_[1] + f.order_[2];
  f.start_.assign(n, {0, 0, 0});
  f.basis_.assign(n * stride, 0.0);
  f.inside_.assign(n, 0);
  if (options.mode == Mode::Motor && options.blend == ga::Blend::DLB) f.pivot_.assign(n, 0);
  const Eigen::Vector3d lo = f.box_.min(), inv = f.box_.sizes().cwiseInverse();
  Eigen::Index outside = 0;
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend)) reduction(+ : outside)
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d s = (V.row(i).transpose() - lo).cwiseProduct(inv);  // local coordinates (§V)
    if (!((s.array() >= 0.0).all() && (s.array() <= 1.0).all())) {
      ++outside;
      continue;
    }
    f.inside_[i] = 1;
    double* b = f.basis_.data() + i * stride;
    std::array<int, 3> arg{};
    for (int a = 0; a < 3; ++a) {
      f.start_[i][a] = bspline_nonzero(f.dims_[a], f.order_[a] - 1, s[a], b);
      int best = 0;
      for (int r = 1; r < f.order_[a]; ++r) best = b[r] > b[best] ? r : best;
      arg[a] = f.start_[i][a] + best;
      b += f.order_[a];
    }
    if (!f.pivot_.empty()) f.pivot_[i] = static_cast<int>(f.index(arg[0], arg[1], arg[2]));
  }
  f.outside_ = outside;
  f.lanes_.assign(L, A8::Zero());
  f.points4_.assign(L, A4::Zero());
  f.motors_.resize(L);
  if (!f.pivot_.empty()) f.signs_.assign(L * L, 1);
  f.controls_.reserve(static_cast<std::size_t>(f.C_.rows()));
  for (int a = 0; a < f.dims_[0]; ++a)
    for (int b = 0; b < f.dims_[1]; ++b)
      for (int c = 0; c < f.dims_[2]; ++c)
        f.controls_.push_back(
            {"ffd[" + std::to_string(a) + "," + std::to_string(b) + "," + std::to_string(c) + "]",
             f.C_.row(f.index(a, b, c)).transpose()});
  return f;
}

void FfdDeformer::check_motors(std::span<const ga::Mot> motors) {
  const Eigen::Index L = C_.rows();
  if (static_cast<Eigen::Index>(motors.size()) != L) {
    std::ostringstream s;
    s << "FfdDeformer: " << motors.size() << " motors given for " << L << " lattice controls";
    throw Error(s.str());
  }
  for (Eigen::Index j = 0; j < L; ++j)
    motors_[j] = checked_unit_motor(motors[j], "FFD control motor " + std::to_string(j));
}

void FfdDeformer::pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out) {
  check_motors(motors);
  const Eigen::Index L = C_.rows(), n = vertices();
  if (options_.mode == Mode::Position) {
    if (points_.rows() != L) points_.resize(L, 3);
    for (Eigen::Index j = 0; j < L; ++j)
      points_.row(j) = ga::transform(motors_[j], C_.row(j).transpose()).transpose();
    pose_points(points_, V_out);
    return;
  }
  if (V_out.rows() != n || V_out.cols() != 3) V_out.resize(n, 3);
  if (options_.blend == ga::Blend::Log) {
    for (Eigen::Index j = 0; j < L; ++j) {
      const ga::Dll l = ga::log(motors_[j]);
      lanes_[j] << l[0], l[1], l[2], l[3], l[4], l[5], 0.0, 0.0;
    }
    dispatch<Kernel::Log>(P_, inside_, start_, basis_, dims_, order_, lanes_.data(), nullptr, pivot_, V_out);
  } else {
    for (Eigen::Index j = 0; j < L; ++j) lanes_[j] = Eigen::Map<const A8>(motors_[j].data());
    for (Eigen::Index p = 0; p < L; ++p) {
      const ga::Mot rp = ga::reverse(motors_[p]);
      for (Eigen::Index j = 0; j < L; ++j)
        signs_[p * L + j] = std::signbit(ga::scalar(motors_[j], rp)) ? -1 : 1;
    }
    dispatch<Kernel::DLB>(P_, inside_, start_, basis_, dims_, order_, lanes_.data(), signs_.data(), pivot_,
                          V_out);
  }
}

void FfdDeformer::pose_points(const Eigen::MatrixXd& controls_in, Eigen::MatrixXd& V_out) {
  const Eigen::Index L = C_.rows(), n = vertices();
  if (options_.mode != Mode::Position) throw Error("FfdDeformer::pose_points needs the position mode");
  if (controls_in.rows() != L || controls_in.cols() != 3) {
    std::ostringstream s;
    s << "FfdDeformer: " << controls_in.rows() << "×" << controls_in.cols()
      << " control points for a lattice of " << L;
    throw Error(s.str());
  }
  for (Eigen::Index j = 0; j < L; ++j) {
    if (!controls_in.row(j).allFinite())
      throw Error("FfdDeformer: control point " + std::to_string(j) + " is not finite");
    points4_[j] << controls_in(j, 0), controls_in(j, 1), controls_in(j, 2), 0.0;
  }
  if (V_out.rows() != n || V_out.cols() != 3) V_out.resize(n, 3);
  dispatch<Kernel::Position>(P_, inside_, start_, basis_, dims_, order_, points4_.data(), nullptr, pivot_,
                             V_out);
}

Eigen::SparseMatrix<double, Eigen::RowMajor> FfdDeformer::weights() const {
  const Eigen::Index n = vertices(), L = C_.rows();
  const int stride = order_[0] + order_[1] + order_[2];
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!inside_[i]) continue;
    const double* bu = basis_.data() + i * stride;
    const double* bv = bu + order_[0];
    const double* bw = bv + order_[1];
    for (int a = 0; a < order_[0]; ++a)
      for (int b = 0; b < order_[1]; ++b)
        for (int c = 0; c < order_[2]; ++c)
          t.emplace_back(i, index(start_[i][0] + a, start_[i][1] + b, start_[i][2] + c),
                         bu[a] * bv[b] * bw[c]);
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> W(n, L);
  W.setFromTriplets(t.begin(), t.end());
  return W;
}

ga::Mot FfdDeformer::vertex_motor(Eigen::Index i, std::span<const ga::Mot> motors) const {
  if (i < 0 || i >= vertices())
    throw Error("FfdDeformer::vertex_motor: vertex " + std::to_string(i) + " out of range");
  if (static_cast<Eigen::Index>(motors.size()) != C_.rows())
    throw Error("FfdDeformer::vertex_motor: wrong motor count");
  if (!inside_[i]) return ga::Mot(1.0, 0, 0, 0, 0, 0, 0, 0);
  const double* bu = basis_.data() + i * (order_[0] + order_[1] + order_[2]);
  const double* bv = bu + order_[0];
  const double* bw = bv + order_[1];
  std::vector<ga::Mot> m;
  std::vector<double> w;
  for (int a = 0; a < order_[0]; ++a)
    for (int b = 0; b < order_[1]; ++b)
      for (int c = 0; c < order_[2]; ++c) {
        m.push_back(motors[index(start_[i][0] + a, start_[i][1] + b, start_[i][2] + c)]);
        w.push_back(bu[a] * bv[b] * bw[c]);
      }
  return ga::blend(m, w, options_.blend == ga::Blend::DLB ? ga::Blend::DLB : ga::Blend::Log);
}

}  // namespace spinmotor

// bench_arap: ArapDeformer (Horn rotor local step, CHOLMOD global step) against a straightforward ARAP in
// the same run: JacobiSVD per cell for the local step, Eigen SimplicialLDLT for the global step, cells
// as explicit edge lists (the baseline of issue 6).
//
//   BM_Rotation/<method>   best rotation of one cell, ns per cell, on covariances and warm rotors taken
//                          from an ARAP iteration of the 80k tube: Horn warm-started (the deformer's
//                          path), Horn cold (identity warm start), the Jacobi fallback alone, Eigen's
//                          SelfAdjointEigenSolver<Matrix4d> on Horn's matrix, JacobiSVD<Matrix3d>.
//                          "ns_per_cell"; "x_svd" = ns / JacobiSVD ns (the SVD timed in the same run).
//   BM_Arap/<mesh>         precompute (bind) and per-iteration time of both implementations on the same
//                          problem, K iterations from the same rest initial guess (so both produce the
//                          same energy sequence; "E_rel_diff" checks it): nefertiti (50k vertices) and the
//                          80k-vertex open tube (400 rings × 200 sides, radius 1, length 10), bottom 5% of
//                          z fixed, top 5% translated by 0.3·(z extent) in x; the 1M-vertex tube
//                          (2000 × 500) with 3 iterations. Counters: *_bind_ms, *_iter_ms (whole pose
//                          time / K, including the energy evaluation), local/global split, ratios
//                          base/ours.
//   BM_ArapInitial/<init>  iterations and time to reach tolerance 1e-5 on a 2.4k tube whose top turns 90°:
//                          rest vs harmonic initial guess.
// Spokes-and-rims energy throughout (libigl's default for triangle meshes, the comparison).
#include <benchmark/benchmark.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/deform/arap.hpp"
#include "spinmotor/ga/rotor_fit.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"

using namespace spinmotor;

namespace {

using Clock = std::chrono::steady_clock;
/// Process CPU time (all threads) in ms: the work done, whatever the load of the (shared) machine.
double cpu_ms() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

struct Problem {
  std::string name;
  Mesh mesh;
  std::vector<Handle> handles;
  std::vector<ga::Mot> motors;
};

Handle z_slab(const Mesh& m, double lo, double hi, const std::string& name) {
  const double z0 = m.V.col(2).minCoeff(), z1 = m.V.col(2).maxCoeff();
  std::vector<int> v;
  for (int i = 0; i < m.V.rows(); ++i) {
    const double t = (m.V(i, 2) - z0) / (z1 - z0);
    if (t >= lo && t <= hi) v.push_back(i);
  }
  return {name, Eigen::Map<Eigen::VectorXi>(v.data(), static_cast<Eigen::Index>(v.size()))};
}

/// Bottom 5% of z fixed, top 5% translated by 0.3·(z extent) along x.
Problem translate_top(std::string name, Mesh mesh) {
  Problem p{std::move(name), std::move(mesh), {}, {}};
  const double h = p.mesh.V.col(2).maxCoeff() - p.mesh.V.col(2).minCoeff();
  p.handles = {z_slab(p.mesh, 0.0, 0.05, "bottom"), z_slab(p.mesh, 0.95, 1.0, "top")};
  p.motors = {ga::Mot(1, 0, 0, 0, 0, 0, 0, 0),
              ga::motor(ga::Rot(1, 0, 0, 0), ga::translator({0.3 * h, 0, 0}))};
  return p;
}

const Problem& problem(const std::string& which) {
  static std::map<std::string, Problem> cache;
  auto it = cache.find(which);
  if (it != cache.end()) return it->second;
  Problem p;
  if (which == "nefertiti")
    p = translate_top("nefertiti", read_mesh(std::filesystem::path(SPINMOTOR_MESHES_DIR) / "nefertiti.obj"));
  else if (which == "tube80k")
    p = translate_top("tube80k", tube(1.0, 10.0, 400, 200, false));
  else if (which == "tube1M")
    p = translate_top("tube1M", tube(1.0, 10.0, 2000, 500, false));
  return cache.emplace(which, std::move(p)).first->second;
}

/// The straightforward ARAP (spokes and rims): each cell an explicit list of weighted edges, the local
/// step a JacobiSVD per cell (parallel), the right-hand side scattered edge by edge, the global matrix
/// Σ c (δu − δv)(δu − δv)ᵀ assembled from triplets and factorized by Eigen's SimplicialLDLT.
class BaselineArap {
 public:
  struct Term {
    int u, v;
    double c;
    Eigen::Vector3d e;  // rest edge x_u − x_v
  };

  BaselineArap(const Mesh& m, const std::vector<Handle>& handles) : P_(m.V) {
    const int n = static_cast<int>(m.V.rows());
    cells_.resize(n);
    for (int t = 0; t < m.F.rows(); ++t)
      for (int k = 0; k < 3; ++k) {
        const int a = m.F(t, k), u = m.F(t, (k + 1) % 3), v = m.F(t, (k + 2) % 3);
        const Eigen::Vector3d e1 = P_.row(u) - P_.row(a), e2 = P_.row(v) - P_.row(a);
        const double c = 0.5 * e1.dot(e2) / e1.cross(e2).norm();
        const Eigen::Vector3d e = (P_.row(u) - P_.row(v)).transpose();
        for (int q = 0; q < 3; ++q) cells_[m.F(t, q)].push_back({u, v, c, e});
      }
    free_of_.assign(n, 0);
    for (const Handle& h : handles)
      for (Eigen::Index k = 0; k < h.vertices.size(); ++k) {
        free_of_[h.vertices[k]] = -1 - static_cast<int>(constrained_.size());
        constrained_.push_back(h.vertices[k]);
      }
    for (int i = 0; i < n; ++i)
      if (free_of_[i] == 0) free_of_[i] = static_cast<int>(free_.size()), free_.push_back(i);
    std::vector<Eigen::Triplet<double>> ff, fc;
    for (const auto& cell : cells_)
      for (const Term& e : cell) {
        const int idx[2] = {e.u, e.v};
        const double sgn[2] = {1.0, -1.0};
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b) {
            const int r = free_of_[idx[a]], s = free_of_[idx[b]];
            if (r < 0) continue;
            if (s >= 0)
              ff.emplace_back(r, s, e.c * sgn[a] * sgn[b]);
            else
              fc.emplace_back(r, -1 - s, e.c * sgn[a] * sgn[b]);
          }
      }
    const auto nf = static_cast<Eigen::Index>(free_.size()),
               nc = static_cast<Eigen::Index>(constrained_.size());
    K_FF_.resize(nf, nf);
    K_FF_.setFromTriplets(ff.begin(), ff.end());
    K_FC_.resize(nf, nc);
    K_FC_.setFromTriplets(fc.begin(), fc.end());
    ldlt_.compute(K_FF_);
    if (ldlt_.info() != Eigen::Success) throw std::runtime_error("baseline: SimplicialLDLT failed");
    R_.assign(n, Eigen::Matrix3d::Identity());
  }

  Eigen::Matrix3d covariance(int i, const Eigen::MatrixXd& X) const {
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    for (const Term& e : cells_[i]) S.noalias() += e.c * e.e * (X.row(e.u) - X.row(e.v));
    return S;
  }

  /// Local step: rotations of X (stored) and the energy E(X).
  double local(const Eigen::MatrixXd& X) {
    const int n = static_cast<int>(cells_.size());
    double E = 0;
#pragma omp parallel for schedule(static) reduction(+ : E)
    for (int i = 0; i < n; ++i) {
      const Eigen::Matrix3d S = covariance(i, X);
      Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
      const double d = (svd.matrixV() * svd.matrixU().transpose()).determinant() > 0 ? 1.0 : -1.0;
      R_[i] = svd.matrixV() * Eigen::Vector3d(1, 1, d).asDiagonal() * svd.matrixU().transpose();
      for (const Term& e : cells_[i])
        E += e.c * ((X.row(e.u) - X.row(e.v)).transpose() - R_[i] * e.e).squaredNorm();
    }
    return E;
  }

  /// Global step in place.
  void global(Eigen::MatrixXd& X) const {
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(free_.size()), 3);
    for (std::size_t i = 0; i < cells_.size(); ++i)
      for (const Term& e : cells_[i]) {
        const Eigen::RowVector3d r = e.c * (R_[i] * e.e).transpose();
        if (free_of_[e.u] >= 0) b.row(free_of_[e.u]) += r;
        if (free_of_[e.v] >= 0) b.row(free_of_[e.v]) -= r;
      }
    Eigen::MatrixXd XC(static_cast<Eigen::Index>(constrained_.size()), 3);
    for (std::size_t r = 0; r < constrained_.size(); ++r)
      XC.row(static_cast<Eigen::Index>(r)) = X.row(constrained_[r]);
    const Eigen::MatrixXd XF = ldlt_.solve(b - K_FC_ * XC);
    for (std::size_t r = 0; r < free_.size(); ++r) X.row(free_[r]) = XF.row(static_cast<Eigen::Index>(r));
  }

  const std::vector<Eigen::Matrix3d>& rotations() const { return R_; }

 private:
  Eigen::MatrixXd P_;
  std::vector<std::vector<Term>> cells_;
  std::vector<int> free_of_, free_, constrained_;
  Eigen::SparseMatrix<double> K_FF_, K_FC_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  std::vector<Eigen::Matrix3d> R_;
};

Eigen::MatrixXd initial_guess(const Problem& p) {
  Eigen::MatrixXd X = p.mesh.V;
  for (std::size_t h = 0; h < p.handles.size(); ++h)
    for (Eigen::Index k = 0; k < p.handles[h].vertices.size(); ++k) {
      const int v = p.handles[h].vertices[k];
      X.row(v) = ga::transform(p.motors[h], p.mesh.V.row(v).transpose()).transpose();
    }
  return X;
}

// ---- the rotation kernel ----------------------------------------------------------------------------

struct RotationData {
  std::vector<Eigen::Matrix3d> S;
  std::vector<ga::Rot> warm;
};

const RotationData& rotation_data() {
  static RotationData d = [] {
    const Problem& p = problem("tube80k");
    BaselineArap base(p.mesh, p.handles);
    Eigen::MatrixXd X = initial_guess(p);
    for (int k = 0; k < 3; ++k) {
      base.local(X);
      base.global(X);
    }
    base.local(X);  // rotations of iteration 3: the warm starts of iteration 4
    RotationData r;
    for (const Eigen::Matrix3d& R : base.rotations())
      r.warm.push_back(ga::from_quaterniond(Eigen::Quaterniond(R)));
    base.global(X);
    for (int i = 0; i < X.rows(); ++i) r.S.push_back(base.covariance(i, X));
    return r;
  }();
  return d;
}

Eigen::Matrix3d svd_rotation(const Eigen::Matrix3d& S) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const double d = (svd.matrixV() * svd.matrixU().transpose()).determinant() > 0 ? 1.0 : -1.0;
  return svd.matrixV() * Eigen::Vector3d(1, 1, d).asDiagonal() * svd.matrixU().transpose();
}

/// ns per cell of the JacobiSVD baseline, measured once in this run (best of 3 passes).
double svd_ns() {
  static const double ns = [] {
    const RotationData& d = rotation_data();
    double best = 1e300;
    for (int rep = 0; rep < 3; ++rep) {
      const auto t = Clock::now();
      for (const Eigen::Matrix3d& S : d.S) {
        Eigen::Matrix3d R = svd_rotation(S);
        benchmark::DoNotOptimize(R);
      }
      best = std::min(best, ms_since(t) * 1e6 / static_cast<double>(d.S.size()));
    }
    return best;
  }();
  return ns;
}

template <class F>
void run_rotation(benchmark::State& state, F&& f) {
  const RotationData& d = rotation_data();
  const double base = svd_ns();
  const std::size_t n = d.S.size();
  double ms = 0;
  for (auto _ : state) {
    const auto t = Clock::now();
    for (std::size_t i = 0; i < n; ++i) {
      auto r = f(d.S[i], d.warm[i]);
      benchmark::DoNotOptimize(r);
    }
    ms += ms_since(t);
  }
  const double ns = ms * 1e6 / (static_cast<double>(state.iterations()) * static_cast<double>(n));
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * n));
  state.counters["ns_per_cell"] = ns;
  state.counters["x_svd"] = ns / base;
}

void BM_Rotation_svd(benchmark::State& state) {
  run_rotation(state, [](const Eigen::Matrix3d& S, const ga::Rot&) { return svd_rotation(S); });
}
void BM_Rotation_horn_warm(benchmark::State& state) {
  ga::RotationInfo info;
  std::size_t fast = 0, calls = 0;
  run_rotation(state, [&](const Eigen::Matrix3d& S, const ga::Rot& w) {
    const ga::Rot q = best_rotation(S, w, &info);
    fast += info.fast;
    ++calls;
    return q;
  });
  state.counters["fast_fraction"] = static_cast<double>(fast) / static_cast<double>(calls);
}
void BM_Rotation_horn_cold(benchmark::State& state) {
  ga::RotationInfo info;
  std::size_t fast = 0, calls = 0;
  run_rotation(state, [&](const Eigen::Matrix3d& S, const ga::Rot&) {
    const ga::Rot q = best_rotation(S, ga::Rot(1, 0, 0, 0), &info);
    fast += info.fast;
    ++calls;
    return q;
  });
  state.counters["fast_fraction"] = static_cast<double>(fast) / static_cast<double>(calls);
}
void BM_Rotation_jacobi(benchmark::State& state) {
  run_rotation(state, [](const Eigen::Matrix3d& S, const ga::Rot&) {
    double lambda;
    bool unique;
    int sweeps;
    return ga::detail::top_eigenvector_jacobi(ga::horn_matrix(S), S.norm(), lambda, unique, sweeps);
  });
}
void BM_Rotation_eigen_selfadjoint(benchmark::State& state) {
  run_rotation(state, [](const Eigen::Matrix3d& S, const ga::Rot&) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> es(ga::horn_matrix(S));
    return Eigen::Vector4d(es.eigenvectors().col(3));
  });
}

// ---- whole ARAP ------------------------------------------------------------------------------------

void BM_Arap(benchmark::State& state, const std::string& which, int K, bool with_baseline) {
  const Problem& p = problem(which);
  for (auto _ : state) {
    ArapDeformer::Options o;
    o.energy = ArapEnergy::SpokesAndRims;
    o.iterations = K;
    o.tolerance = 0.0;
    o.initial = ArapInitial::Rest;  // libigl and CGAL start from the rest positions too: same energies
    auto t = Clock::now();
    double c = cpu_ms();
    ArapDeformer d = ArapDeformer::bind(p.mesh, p.handles, o);
    const double bind_ms = ms_since(t), bind_cpu = cpu_ms() - c;
    Eigen::MatrixXd V;
    t = Clock::now();
    c = cpu_ms();
    d.pose(p.motors, V);
    const double pose_ms = ms_since(t), pose_cpu = cpu_ms() - c;
    state.counters["ours_bind_cpu_ms"] = bind_cpu;
    state.counters["ours_iter_cpu_ms"] = pose_cpu / K;
    const ArapReport& r = d.report();
    state.counters["n"] = static_cast<double>(p.mesh.V.rows());
    state.counters["ours_bind_ms"] = bind_ms;
    state.counters["ours_iter_ms"] = pose_ms / K;
    state.counters["ours_local_ms"] = r.local_ms / (K + 1);
    state.counters["ours_global_ms"] = r.global_ms / K;
    state.counters["ours_jacobi_frac"] = static_cast<double>(r.fallback_fits) / ((K + 1.0) * p.mesh.V.rows());
    state.counters["ours_rhs_ms"] = r.rhs_ms / K;
    state.counters["ours_solve_ms"] = r.solve_ms / K;
    const ArapBindReport& b = d.bind_report();
    state.counters["ours_factor_ms"] = b.factor_ms;
    state.counters["E_K"] = r.energy.back();
    std::printf(
        "[bench_arap] %s n=%lld: ours bind %.1f ms (weights %.1f, cells %.1f, factor %.1f), %.2f ms/iter "
        "(local %.2f, "
        "rhs %.2f, solve %.2f), E_0 %.6g E_%d %.6g\n",
        which.c_str(), static_cast<long long>(p.mesh.V.rows()), bind_ms, b.weights_ms, b.cells_ms,
        b.factor_ms, pose_ms / K, r.local_ms / (K + 1), r.rhs_ms / K, r.solve_ms / K, r.energy.front(), K,
        r.energy.back());
    std::printf("[bench_arap] %s: ours CPU time (all threads) bind %.1f ms, %.2f ms/iter\n", which.c_str(),
                bind_cpu, pose_cpu / K);
    if (with_baseline) {
      t = Clock::now();
      c = cpu_ms();
      BaselineArap base(p.mesh, p.handles);
      const double base_bind = ms_since(t), base_bind_cpu = cpu_ms() - c;
      Eigen::MatrixXd X = initial_guess(p);
      double local_ms = 0, global_ms = 0, E = 0;
      t = Clock::now();
      c = cpu_ms();
      for (int k = 0; k <= K; ++k) {
        auto tl = Clock::now();
        E = base.local(X);
        local_ms += ms_since(tl);
        if (k == K) break;
        tl = Clock::now();
        base.global(X);
        global_ms += ms_since(tl);
      }
      const double base_pose = ms_since(t), base_pose_cpu = cpu_ms() - c;
      state.counters["base_bind_cpu_ms"] = base_bind_cpu;
      state.counters["base_iter_cpu_ms"] = base_pose_cpu / K;
      state.counters["bind_cpu_ratio"] = base_bind_cpu / bind_cpu;
      state.counters["iter_cpu_ratio"] = base_pose_cpu / pose_cpu;
      state.counters["base_bind_ms"] = base_bind;
      state.counters["base_iter_ms"] = base_pose / K;
      state.counters["base_local_ms"] = local_ms / (K + 1);
      state.counters["base_global_ms"] = global_ms / K;
      state.counters["bind_ratio"] = base_bind / bind_ms;
      state.counters["iter_ratio"] = (base_pose / K) / (pose_ms / K);
      state.counters["E_rel_diff"] = std::abs(E - r.energy.back()) / E;
      std::printf(
          "[bench_arap] %s: baseline bind %.1f ms, %.2f ms/iter (local %.2f + global %.2f), E_%d %.6g; "
          "ratios bind %.2fx, iter %.2fx\n",
          which.c_str(), base_bind, base_pose / K, local_ms / (K + 1), global_ms / K, K, E,
          base_bind / bind_ms, base_pose / pose_ms);
      std::printf(
          "[bench_arap] %s: baseline CPU time bind %.1f ms, %.2f ms/iter; CPU ratios bind %.2fx, iter "
          "%.2fx\n",
          which.c_str(), base_bind_cpu, base_pose_cpu / K, base_bind_cpu / bind_cpu,
          base_pose_cpu / pose_cpu);
    }
  }
}

void BM_ArapInitial(benchmark::State& state, ArapInitial initial) {
  static const Mesh m = tube(1.0, 10.0, 60, 40, false);
  const std::vector<Handle> hs = {z_slab(m, 0.0, 0.05, "bottom"), z_slab(m, 0.95, 1.0, "top")};
  const double Rb = 10.0 / (M_PI / 2);
  const std::vector<ga::Mot> motors = {
      ga::Mot(1, 0, 0, 0, 0, 0, 0, 0),
      ga::motor(ga::rotor({0, 1, 0}, M_PI / 2), ga::translator({Rb - 10.0, 0, Rb}))};
  ArapDeformer::Options o;
  o.initial = initial;
  o.iterations = 2000;
  o.tolerance = 1e-5;
  ArapDeformer d = ArapDeformer::bind(m, hs, o);
  Eigen::MatrixXd V;
  for (auto _ : state) d.pose(motors, V);
  state.counters["iterations"] = d.report().iterations;
  state.counters["E"] = d.report().energy.back();
}

}  // namespace

BENCHMARK(BM_Rotation_svd)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Rotation_horn_warm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Rotation_horn_cold)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Rotation_jacobi)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Rotation_eigen_selfadjoint)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Arap, nefertiti, std::string("nefertiti"), 10, true)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Arap, tube80k, std::string("tube80k"), 10, true)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Arap, tube1M, std::string("tube1M"), 3, false)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ArapInitial, rest, ArapInitial::Rest)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ArapInitial, harmonic, ArapInitial::Harmonic)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();

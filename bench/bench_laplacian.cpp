// bench_laplacian: discrete operator assembly and sparse solves on latitude–longitude spheres of
// ~10k, ~100k and ~1M vertices (uv_sphere 70×142 → 9,942; 223×446 → 99,460; 707×1414 → 999,700),
// each compared in the same run with a baseline computed on the same input:
//
//   cotan_assembly/<size>     cotangent_laplacian (direct compressed-column assembly, OpenMP) vs the
//                             usual triplet list + setFromTriplets (libigl's cotmatrix pattern).
//                             Counters: ours_ms, ours_1thread_ms, base_ms, speedup = base/ours.
//   mass_assembly/<size>      mass_matrix(Voronoi) alone, no baseline (for the record).
//   cholesky_solve/<size>     (L + M)·X = M·V, 3 right-hand sides: CholeskySolver (CHOLMOD supernodal,
//                             default ordering) analyze + factorize + solve vs Eigen::SimplicialLDLT
//                             compute + solve (1M: baseline with SPINMOTOR_BENCH_FULL=1). Counters:
//                             *_analyze_ms, *_factor_ms, *_solve_ms,
//                             *_total_ms, speedup = base_total/ours_total, rel_diff of the solutions.
//   cholesky_ordering/<ord>/<kind>/<size>   the ordering study (docs/design.md: choose the ordering
//                             deliberately): AMD, METIS, NESDIS × supernodal/simplicial on 100k (and
//                             AMD/METIS supernodal on 1M): analyze, factorize (refactorize with the same
//                             pattern), solve, nnz(L), flops. No baseline: compare the rows.
//   lu_solve/<size>           (L_mv + M)·X = M·V with the mean-value Laplacian (non-symmetric):
//                             LUSolver (SuperLU, COLAMD) vs Eigen::SparseLU (COLAMD), 10k and 100k.
//   lu_ordering/<ord>/10k     SuperLU column orderings: COLAMD, MMD(AᵀA), MMD(Aᵀ+A), natural.
//
// A summary table (time and speedup per size) is printed at the end. SPINMOTOR_BENCH_QUICK=1 (set by
// `bench/run --quick`) keeps the 10k size only. At 1M the SimplicialLDLT baseline alone takes minutes
// (594 s measured on the shared 2-core machine, against 89 s for CHOLMOD), and the 1M ordering rows
// add two more factorizations: both run only with SPINMOTOR_BENCH_FULL=1 (`bench/run --full`); the
// default run times CholeskySolver alone at 1M.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/linalg/lu_solver.hpp"
#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/mass_matrix.hpp"
#include "spinmotor/mesh/mean_value_laplacian.hpp"

using namespace spinmotor;
using SpMat = Eigen::SparseMatrix<double>;

namespace {

using Clock = std::chrono::steady_clock;

struct Size {
  const char* label;
  int rings, sectors;
  int assembly_iters, solve_iters;
};
const Size kSizes[] = {{"10k", 70, 142, 40, 5}, {"100k", 223, 446, 8, 2}, {"1M", 707, 1414, 2, 1}};

const Mesh& sphere(const Size& s) {
  static std::map<std::string, Mesh> cache;
  auto it = cache.find(s.label);
  if (it == cache.end()) it = cache.emplace(s.label, uv_sphere(s.rings, s.sectors)).first;
  return it->second;
}

// Summary rows, keyed by benchmark name, printed after the run.
struct Row {
  double n = 0, ours_ms = 0, base_ms = 0;
  std::string note;
};
std::map<std::string, Row>& summary() {
  static std::map<std::string, Row> rows;
  return rows;
}

// Baseline: libigl-style cotangent Laplacian from 12 triplets per face (same sign convention).
SpMat cotan_triplets(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(12 * F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d x[3] = {V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2))};
    const double dbl_area = (x[1] - x[0]).cross(x[2] - x[0]).norm();
    for (int c = 0; c < 3; ++c) {
      const int i = F(f, (c + 1) % 3), j = F(f, (c + 2) % 3);
      const double w = 0.5 * (x[(c + 1) % 3] - x[c]).dot(x[(c + 2) % 3] - x[c]) / dbl_area;
      t.emplace_back(i, j, -w);
      t.emplace_back(j, i, -w);
      t.emplace_back(i, i, w);
      t.emplace_back(j, j, w);
    }
  }
  SpMat L(V.rows(), V.rows());
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

void cotan_assembly(benchmark::State& state, const std::string& key, Size size) {
  const Mesh& m = sphere(size);
  double ours = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    SpMat L = cotangent_laplacian(m.V, m.F);
    benchmark::DoNotOptimize(L.valuePtr());
    ours += ms_since(t0);
  }
  const int iters = static_cast<int>(state.iterations());
  ours /= iters;
  double one = 0, base = 0;
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  for (int k = 0; k < iters; ++k) {
    const auto t0 = Clock::now();
    SpMat L = cotangent_laplacian(m.V, m.F);
    benchmark::DoNotOptimize(L.valuePtr());
    one += ms_since(t0);
  }
  omp_set_num_threads(threads);
  SpMat Lb;
  for (int k = 0; k < iters; ++k) {
    const auto t0 = Clock::now();
    Lb = cotan_triplets(m.V, m.F);
    benchmark::DoNotOptimize(Lb.valuePtr());
    base += ms_since(t0);
  }
  one /= iters;
  base /= iters;
  const SpMat L = cotangent_laplacian(m.V, m.F);
  state.counters["n"] = static_cast<double>(m.V.rows());
  state.counters["nnz"] = static_cast<double>(L.nonZeros());
  state.counters["ours_ms"] = ours;
  state.counters["ours_1thread_ms"] = one;
  state.counters["base_ms"] = base;
  state.counters["speedup"] = base / ours;
  state.counters["max_abs_diff"] = SpMat(L - Lb).coeffs().cwiseAbs().maxCoeff();
  summary()[key] = {static_cast<double>(m.V.rows()), ours, base,
                    "1 thread " + std::to_string(one).substr(0, 6) + " ms"};
}

void mass_assembly(benchmark::State& state, const std::string& key, Size size) {
  const Mesh& m = sphere(size);
  for (auto _ : state) {
    SpMat M = mass_matrix(m.V, m.F, MassType::Voronoi);
    benchmark::DoNotOptimize(M.valuePtr());
  }
  state.counters["n"] = static_cast<double>(m.V.rows());
}

struct Problem {
  SpMat A;
  Eigen::MatrixXd B;
};
Problem spd_problem(const Mesh& m) {
  const SpMat M = mass_matrix(m.V, m.F);
  return {SpMat(cotangent_laplacian(m.V, m.F) + M), M * m.V};
}

void cholesky_solve(benchmark::State& state, const std::string& key, Size size, bool baseline) {
  const Mesh& m = sphere(size);
  const Problem p = spd_problem(m);
  double an = 0, fa = 0, so = 0;
  Eigen::MatrixXd X;
  for (auto _ : state) {
    CholeskySolver c;
    auto t0 = Clock::now();
    c.analyze(p.A);
    an += ms_since(t0);
    t0 = Clock::now();
    c.factorize(p.A);
    fa += ms_since(t0);
    t0 = Clock::now();
    X = c.solve(p.B);
    so += ms_since(t0);
    state.counters["ours_nnzL"] = c.factor_nonzeros();
  }
  const int iters = static_cast<int>(state.iterations());
  an /= iters, fa /= iters, so /= iters;
  double ban = 0, bfa = 0, bso = 0;
  Eigen::MatrixXd Xb;
  for (int k = 0; k < (baseline ? iters : 0); ++k) {
    Eigen::SimplicialLDLT<SpMat> ldlt;
    auto t0 = Clock::now();
    ldlt.analyzePattern(p.A);
    ban += ms_since(t0);
    t0 = Clock::now();
    ldlt.factorize(p.A);
    bfa += ms_since(t0);
    t0 = Clock::now();
    Xb = ldlt.solve(p.B);
    bso += ms_since(t0);
    if (ldlt.info() != Eigen::Success) state.SkipWithError("SimplicialLDLT failed");
  }
  ban /= iters, bfa /= iters, bso /= iters;
  const double ours = an + fa + so, base = ban + bfa + bso;
  if (!baseline) {
    state.counters["n"] = static_cast<double>(m.V.rows());
    state.counters["ours_analyze_ms"] = an;
    state.counters["ours_factor_ms"] = fa;
    state.counters["ours_solve_ms"] = so;
    state.counters["ours_total_ms"] = ours;
    summary()[key] = {static_cast<double>(m.V.rows()), ours, 0, "baseline only with SPINMOTOR_BENCH_FULL=1"};
    return;
  }
  state.counters["n"] = static_cast<double>(m.V.rows());
  state.counters["ours_analyze_ms"] = an;
  state.counters["ours_factor_ms"] = fa;
  state.counters["ours_solve_ms"] = so;
  state.counters["ours_total_ms"] = ours;
  state.counters["base_analyze_ms"] = ban;
  state.counters["base_factor_ms"] = bfa;
  state.counters["base_solve_ms"] = bso;
  state.counters["base_total_ms"] = base;
  state.counters["speedup"] = base / ours;
  state.counters["factor_speedup"] = bfa / fa;
  state.counters["rel_diff"] = (X - Xb).norm() / Xb.norm();
  summary()[key] = {static_cast<double>(m.V.rows()), ours, base,
                    "factor " + std::to_string(bfa / fa).substr(0, 4) + "x"};
}

void cholesky_ordering(benchmark::State& state, const std::string& key, Size size,
                       CholeskySolver::Ordering ordering, bool supernodal) {
  const Mesh& m = sphere(size);
  const Problem p = spd_problem(m);
  double an = 0, fa = 0, so = 0;
  CholeskySolver c({ordering, supernodal});
  for (auto _ : state) {
    auto t0 = Clock::now();
    c.analyze(p.A);
    an += ms_since(t0);
    t0 = Clock::now();
    c.factorize(p.A);
    fa += ms_since(t0);
    t0 = Clock::now();
    Eigen::MatrixXd X = c.solve(p.B);
    benchmark::DoNotOptimize(X.data());
    so += ms_since(t0);
  }
  const double it = static_cast<double>(state.iterations());
  state.counters["n"] = static_cast<double>(m.V.rows());
  state.counters["analyze_ms"] = an / it;
  state.counters["factor_ms"] = fa / it;
  state.counters["solve_ms"] = so / it;
  state.counters["total_ms"] = (an + fa + so) / it;
  state.counters["nnzL"] = c.factor_nonzeros();
  state.counters["gflop"] = c.factor_flops() * 1e-9;
  summary()[key] = {static_cast<double>(m.V.rows()), (an + fa + so) / it, 0,
                    "analyze " + std::to_string(an / it).substr(0, 6) + " ms, factor " +
                        std::to_string(fa / it).substr(0, 6) + " ms, nnz(L) " +
                        std::to_string(static_cast<long>(c.factor_nonzeros()))};
}

Problem lu_problem(const Mesh& m) {
  const SpMat M = mass_matrix(m.V, m.F);
  return {SpMat(mean_value_laplacian(m.V, m.F) + M), M * m.V};
}

void lu_solve(benchmark::State& state, const std::string& key, Size size) {
  const Mesh& m = sphere(size);
  const Problem p = lu_problem(m);
  double ours = 0;
  Eigen::MatrixXd X;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    LUSolver lu;
    lu.compute(p.A);
    X = lu.solve(p.B);
    ours += ms_since(t0);
    state.counters["ours_nnzLU"] = lu.factor_nonzeros();
  }
  const int iters = static_cast<int>(state.iterations());
  ours /= iters;
  double base = 0;
  Eigen::MatrixXd Xb;
  for (int k = 0; k < iters; ++k) {
    const auto t0 = Clock::now();
    Eigen::SparseLU<SpMat> lu;
    lu.compute(p.A);
    Xb = lu.solve(p.B);
    base += ms_since(t0);
    if (lu.info() != Eigen::Success) state.SkipWithError("SparseLU failed");
  }
  base /= iters;
  state.counters["n"] = static_cast<double>(m.V.rows());
  state.counters["ours_ms"] = ours;
  state.counters["base_ms"] = base;
  state.counters["speedup"] = base / ours;
  state.counters["rel_diff"] = (X - Xb).norm() / Xb.norm();
  summary()[key] = {static_cast<double>(m.V.rows()), ours, base, ""};
}

void lu_ordering(benchmark::State& state, const std::string& key, Size size, LUSolver::Ordering ordering) {
  const Mesh& m = sphere(size);
  const Problem p = lu_problem(m);
  LUSolver lu({ordering, 1.0});
  double an = 0, fa = 0;
  for (auto _ : state) {
    auto t0 = Clock::now();
    lu.analyze(p.A);
    an += ms_since(t0);
    t0 = Clock::now();
    lu.factorize(p.A);
    fa += ms_since(t0);
  }
  const double it = static_cast<double>(state.iterations());
  state.counters["analyze_ms"] = an / it;
  state.counters["factor_ms"] = fa / it;
  state.counters["nnzLU"] = lu.factor_nonzeros();
  summary()[key] = {static_cast<double>(m.V.rows()), (an + fa) / it, 0,
                    "nnz(L+U) " + std::to_string(static_cast<long>(lu.factor_nonzeros()))};
}

std::string name(Ordering o) { return std::string(option_name(o)); }

}  // namespace

int main(int argc, char** argv) {
  const auto env_on = [](const char* name) {
    return std::getenv(name) && std::string(std::getenv(name)) == "1";
  };
  const bool quick = env_on("SPINMOTOR_BENCH_QUICK"), full = env_on("SPINMOTOR_BENCH_FULL");
  const int nsizes = quick ? 1 : 3;
  using O = CholeskySolver::Ordering;
  // Registers fn under `name`, passing the name on as the summary key.
  const auto reg = [](const std::string& name, auto fn, int iterations, auto... args) {
    benchmark::RegisterBenchmark(name.c_str(), fn, name, args...)
        ->Iterations(iterations)
        ->Unit(benchmark::kMillisecond);
  };
  for (int s = 0; s < nsizes; ++s) {
    const Size sz = kSizes[s];
    const std::string l = sz.label;
    reg("cotan_assembly/" + l, cotan_assembly, sz.assembly_iters, sz);
    reg("mass_assembly/" + l, mass_assembly, sz.assembly_iters, sz);
    reg("cholesky_solve/" + l, cholesky_solve, sz.solve_iters, sz, s < 2 || full);
  }
  const Size s100k = kSizes[quick ? 0 : 1];
  for (O o : {O::AMD, O::METIS, O::NESDIS})
    for (bool super : {true, false})
      reg(std::string("cholesky_ordering/") + name(o) + (super ? "/supernodal/" : "/simplicial/") +
              s100k.label,
          cholesky_ordering, s100k.solve_iters, s100k, o, super);
  if (!quick && full)
    for (O o : {O::AMD, O::METIS})
      reg(std::string("cholesky_ordering/") + name(o) + "/supernodal/1M", cholesky_ordering, 1, kSizes[2], o,
          true);
  for (int s = 0; s < std::min(nsizes, 2); ++s)
    reg(std::string("lu_solve/") + kSizes[s].label, lu_solve, kSizes[s].solve_iters, kSizes[s]);
  using LO = LUSolver::Ordering;
  for (LO o : {LO::COLAMD, LO::MMD_AtA, LO::MMD_AtPlusA, LO::Natural})
    reg(std::string("lu_ordering/") + name(o) + "/10k", lu_ordering, 2, kSizes[0], o);

  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();

  std::printf("\nSummary (ms per operation; speedup = baseline / ours, same input, same run)\n");
  std::printf("%-42s %10s %12s %12s %8s  %s\n", "benchmark", "n", "ours_ms", "baseline_ms", "speedup",
              "note");
  for (const auto& [k, r] : summary()) {
    if (r.base_ms > 0)
      std::printf("%-42s %10.0f %12.2f %12.2f %7.2fx  %s\n", k.c_str(), r.n, r.ours_ms, r.base_ms,
                  r.base_ms / r.ours_ms, r.note.c_str());
    else
      std::printf("%-42s %10.0f %12.2f %12s %8s  %s\n", k.c_str(), r.n, r.ours_ms, "-", "-", r.note.c_str());
  }
  return 0;
}

// bench_fairing: face-based Dirac operators (Ye et al. 2018) and curvature-space fairing / extrusion
// (Le Folgoc & Blanc 2019) on spot (2,930 vertices, 5,856 faces) and nefertiti (49,971 vertices, 99,938
// faces), each timed next to a baseline in the same run:
//   assembly/<mesh>   edge-constraint net + intrinsic 4|F|×4|F| operator; baseline: the cotangent
//                     Laplacian of the same mesh (ratio = ours / baseline)
//   fair_step/<mesh>  one eq. 8 step (h̄ = ½h); baseline: one step of the vertex-based conformal Willmore
//                     flow (Crane 2011 §7.3, τ = ½) on the same mesh (ratio = ours / baseline)
//   ye_step/spot      one fast-fairing step of Ye §5.3 (problem 26 spectrum + eq. 21 + least squares)
//   fair10/spot       10 steps of τ = ½, free and with the area constraint (ε = 1.5): W, Q, log area
//   extrude/spot      8-step extrusion from the free 10-step sphere: mean / max vertex distance after
//                     similarity alignment (relative to the bounding-box diagonal)
// Nefertiti rows need SPINMOTOR_BENCH_FULL=1 (one step factors a 400k-unknown system).
// Measured (2026-11-22, 2 shared cores, load ~4.7; wall times):
//   assembly   spot 25.2 ms (cotangent Laplacian 0.64 ms, ×39: validation + topology dominate);
//              nefertiti 510 ms (71 ms, ×7.1)
//   fair_step  spot 379 ms (Crane flow step 69 ms, ×5.5), closure 0.0076;
//              nefertiti 11.4 s (2.40 s, ×4.8), closure 0.032
//   ye_step    spot 2.3 s, W 151.56 -> 20.66
//   fair10     free 3.73 s: W 151.56 -> 12.79, Q max 1.96 mean 1.155, |log area| max 9.42 mean 1.88;
//              area ε = 1.5, 5.09 s: W 13.96, Q max 5.23 mean 1.272, |log area| max 8.18 mean 1.49
//   extrude    8 steps 2.48 s: mean 0.21%, max 0.84% of the diagonal
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <string>

#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/area_distortion.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/curvature_spin_flow.hpp"
#include "spinmotor/spin/dirac_fairing.hpp"
#include "spinmotor/spin/edge_constraint_net.hpp"
#include "spinmotor/spin/face_dirac_operator.hpp"
#include "spinmotor/spin/willmore_flow.hpp"

using namespace spinmotor;

namespace {

const std::string kMeshes = SPINMOTOR_MESHES_DIR;

const Mesh& mesh(const std::string& name) {
  static Mesh spot = read_mesh(kMeshes + "/spot.obj");
  static Mesh nef;
  if (name == "spot") return spot;
  if (nef.V.rows() == 0) nef = read_mesh(kMeshes + "/nefertiti.obj");
  return nef;
}

bool full() { return std::getenv("SPINMOTOR_BENCH_FULL") != nullptr; }

void BM_assembly(benchmark::State& state, std::string name) {
  if (name != "spot" && !full()) return state.SkipWithError("set SPINMOTOR_BENCH_FULL=1");
  const Mesh& m = mesh(name);
  double ours = 0, base = 0;
  for (auto _ : state) {
    auto t = std::chrono::steady_clock::now();
    const EdgeConstraintNet net = edge_constraint_net(m.V, m.F);
    const Eigen::SparseMatrix<double> D = face_dirac_operator(m.V, m.F, net, FaceDiracKind::Intrinsic);
    benchmark::DoNotOptimize(D.nonZeros());
    ours = ms_since(t);
    t = std::chrono::steady_clock::now();
    const Eigen::SparseMatrix<double> L = cotangent_laplacian(m.V, m.F);
    benchmark::DoNotOptimize(L.nonZeros());
    base = ms_since(t);
  }
  state.counters["ours_ms"] = ours;
  state.counters["cotan_laplacian_ms"] = base;
  state.counters["ratio"] = ours / base;
}

void BM_fair_step(benchmark::State& state, std::string name) {
  if (name != "spot" && !full()) return state.SkipWithError("set SPINMOTOR_BENCH_FULL=1");
  const Mesh& m = mesh(name);
  double ours = 0, base = 0, closure = 0;
  for (auto _ : state) {
    auto t = std::chrono::steady_clock::now();
    const EdgeConstraintNet net = edge_constraint_net(m.V, m.F);
    const CurvatureSpinStep st = curvature_spin_step(m.V, m.F, 0.5 * net.h, {}, {});
    closure = st.closure;
    ours = ms_since(t);
    t = std::chrono::steady_clock::now();
    WillmoreFlowOptions o;
    o.tau = 0.5;
    o.steps = 1;
    o.keep_positions = false;
    benchmark::DoNotOptimize(willmore_flow(m, o).V.data());
    base = ms_since(t);
  }
  state.counters["ours_ms"] = ours;
  state.counters["crane_flow_step_ms"] = base;
  state.counters["ratio"] = ours / base;
  state.counters["closure"] = closure;
}

void BM_ye_step(benchmark::State& state) {
  const Mesh& m = mesh("spot");
  double w0 = 0, w1 = 0;
  for (auto _ : state) {
    const DiracFairing f = dirac_fairing(m.V, m.F, 1);
    w0 = f.willmore[0];
    w1 = f.willmore[1];
  }
  state.counters["W_before"] = w0;
  state.counters["W_after"] = w1;
}

void BM_fair10_extrude(benchmark::State& state) {
  const Mesh& m = mesh("spot");
  for (auto _ : state) {
    auto t = std::chrono::steady_clock::now();
    const CurvatureFlow free = curvature_fairing(m.V, m.F, 10, 0.5);
    const double free_ms = ms_since(t);
    CurvatureSpinOptions ao;
    ao.area_epsilon = 1.5;
    t = std::chrono::steady_clock::now();
    const CurvatureFlow area = curvature_fairing(m.V, m.F, 10, 0.5, ao);
    const double area_ms = ms_since(t);
    t = std::chrono::steady_clock::now();
    const CurvatureFlow back = curvature_extrusion(free.V, m.F, m.V, 8);
    const double ext_ms = ms_since(t);
    const QuasiConformalSummary qf = quasi_conformal_summary(m.V, m.F, free.V);
    const QuasiConformalSummary qa = quasi_conformal_summary(m.V, m.F, area.V);
    const AreaDistortionSummary sf = area_distortion_summary(m.V, m.F, free.V);
    const AreaDistortionSummary sa = area_distortion_summary(m.V, m.F, area.V);
    const VertexDistances d = vertex_distances(m.V, back.V, Alignment::Similarity);
    state.counters["free_ms"] = free_ms;
    state.counters["free_W"] = free.willmore.back();
    state.counters["free_Qmax"] = qf.q_max;
    state.counters["free_Qmean"] = qf.q_mean;
    state.counters["free_logA_mean"] = sf.mean_abs;
    state.counters["free_logA_max"] = sf.max_abs;
    state.counters["area_ms"] = area_ms;
    state.counters["area_W"] = area.willmore.back();
    state.counters["area_Qmax"] = qa.q_max;
    state.counters["area_Qmean"] = qa.q_mean;
    state.counters["area_logA_mean"] = sa.mean_abs;
    state.counters["area_logA_max"] = sa.max_abs;
    state.counters["extrude_ms"] = ext_ms;
    state.counters["extrude_mean"] = d.d.mean() / d.diagonal;
    state.counters["extrude_max"] = d.max;
    state.counters["area_vs_free_ms"] = area_ms / free_ms;
  }
}

}  // namespace

BENCHMARK_CAPTURE(BM_assembly, spot, std::string("spot"))->Iterations(3)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_assembly, nefertiti, std::string("nefertiti"))
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_fair_step, spot, std::string("spot"))->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_fair_step, nefertiti, std::string("nefertiti"))
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ye_step)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_fair10_extrude)->Iterations(1)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();

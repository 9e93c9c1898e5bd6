// FFD, skinning and cage coordinates (deform/ffd.hpp, skinning.hpp, cage_coordinates.hpp), 2 cores.
//   BM_ffd_pose     pose of a 1M-vertex tube: 4×4×4 Bezier and 8×8×8 cubic B-spline lattices, modes
//                   position (classic FFD, the baseline measured in the same run: vs_position), motor
//                   Log and motor DLB. Target (issue 5): motor mode ≤ 40 ms.
//   BM_skin_pose    pose of a 1M-vertex tube with 8 bones, 4 influences per vertex, each blend against
//                   LBS measured in the same run (vs_lbs). Target: Linear (DLB) ≤ 1.2× LBS.
//   BM_cage_bind    harmonic cage coordinates of a 10k-vertex torus in a 98-vertex cage, grid 32 / 64
//                   (128 with SPINMOTOR_BENCH_CAGE128=1 in the environment: ~2M grid nodes, a 3D
//                   factorization of much larger fill; not run by default), against MVC on the same
//                   points (vs_mvc), with the reproduction error and its stated bound.
//   BM_mvc_bind     mean value coordinates alone (10k and 100k points).
//   BM_skin_pose_small  LBS of a 4.6k-vertex two-bone arm against libigl's formulation (dense weight
//                   matrix times stacked bone matrices, vs_matrix), measured in the same run.
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include "spinmotor/deform/cage_coordinates.hpp"
#include "spinmotor/deform/ffd.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/generators.hpp"

using namespace spinmotor;

namespace {

const Mesh& tube_1m() {
  static const Mesh m = tube(1.0, 10.0, 2000, 500);  // 1,000,000 vertices
  return m;
}

template <class F>
double median_ms(F&& f, int runs = 5) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    t.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

ga::Mot random_motor(std::mt19937& rng, double degrees, double shift) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return ga::motor(ga::rotor(Eigen::Vector3d(u(rng), u(rng), u(rng)), degrees * u(rng) * M_PI / 180.0),
                   ga::translator(shift * Eigen::Vector3d(u(rng), u(rng), u(rng))));
}

/// args: lattice (0 = 4³ Bezier, 1 = 8³ cubic B-spline), mode (0 position, 1 motor Log, 2 motor DLB)
void BM_ffd_pose(benchmark::State& state) {
  const Mesh& m = tube_1m();
  FfdDeformer::Options o;
  const bool bspline = state.range(0) == 1;
  o.basis = bspline ? FfdDeformer::Basis::BSpline : FfdDeformer::Basis::Bezier;
  o.lattice = bspline ? std::array<int, 3>{8, 8, 8} : std::array<int, 3>{4, 4, 4};
  o.mode = state.range(1) == 0 ? FfdDeformer::Mode::Position : FfdDeformer::Mode::Motor;
  o.blend = state.range(1) == 2 ? ga::Blend::DLB : ga::Blend::Log;
  FfdDeformer d = FfdDeformer::bind(m, o);
  FfdDeformer::Options po = o;
  po.mode = FfdDeformer::Mode::Position;
  FfdDeformer baseline = FfdDeformer::bind(m, po);
  std::mt19937 rng(1);
  std::vector<ga::Mot> M(d.controls().size());
  for (auto& x : M) x = random_motor(rng, 30, 0.2);
  Eigen::MatrixXd V, Vb;
  d.pose(M, V);
  baseline.pose(M, Vb);
  const double base_ms = median_ms([&] { baseline.pose(M, Vb); });
  double total = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    d.pose(M, V);
    benchmark::DoNotOptimize(V.data());
    total += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  state.counters["vertices"] = static_cast<double>(m.V.rows());
  state.counters["controls"] = static_cast<double>(d.controls().size());
  state.counters["position_ms"] = base_ms;
  state.counters["vs_position"] = total / state.iterations() / base_ms;
  state.SetLabel(std::string(bspline ? "8x8x8 bspline " : "4x4x4 bezier ") + (state.range(1) == 0 ? "position"
                                                                              : state.range(1) == 1
                                                                                  ? "motor-log"
                                                                                  : "motor-dlb"));
}
BENCHMARK(BM_ffd_pose)
    ->ArgsProduct({{0, 1}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(1.0)
    ->UseRealTime();

/// 8 bones along the tube, 4 influences per vertex (the 4 bones nearest along z, smooth weights).
struct SkinSetup {
  std::vector<Bone> bones;
  Eigen::SparseMatrix<double> W;
  std::vector<ga::Mot> frames;
};

const SkinSetup& skin_setup() {
  static const SkinSetup s = [] {
    SkinSetup s;
    const Mesh& m = tube_1m();
    const int B = 8;
    for (int j = 0; j < B; ++j) {
      std::string name = "b";  // not "b" + to_string(j): GCC 12's -Wrestrict false positive (bug 105329)
      name += std::to_string(j);
      s.bones.push_back({std::move(name), j - 1, {0, 0, 10.0 * j / B}, {0, 0, 10.0 * (j + 1) / B}});
    }
    std::vector<Eigen::Triplet<double>> t;
    for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
      const double z = m.V(i, 2) / 10.0 * B - 0.5;  // bone centres at j
      const int j0 = std::clamp(static_cast<int>(std::floor(z)) - 1, 0, B - 4);
      double w[4], sum = 0;
      for (int k = 0; k < 4; ++k) sum += w[k] = std::exp(-std::pow(z - (j0 + k), 2));
      for (int k = 0; k < 4; ++k) t.emplace_back(i, j0 + k, w[k] / sum);
    }
    s.W.resize(m.V.rows(), B);
    s.W.setFromTriplets(t.begin(), t.end());
    std::mt19937 rng(2);
    for (int j = 0; j < B; ++j) s.frames.push_back(random_motor(rng, 90, 0.5));
    return s;
  }();
  return s;
}

/// arg: blend (0 LBS, 1 Linear, 2 Log, 3 PivotLog)
void BM_skin_pose(benchmark::State& state) {
  const Mesh& m = tube_1m();
  const SkinSetup& s = skin_setup();
  const SkinDeformer::Blend blends[] = {SkinDeformer::Blend::LBS, SkinDeformer::Blend::DLB,
                                        SkinDeformer::Blend::Log, SkinDeformer::Blend::PivotLog};
  SkinDeformer d = SkinDeformer::bind(m, s.bones, s.W, {blends[state.range(0)]});
  SkinDeformer lbs = SkinDeformer::bind(m, s.bones, s.W, {SkinDeformer::Blend::LBS});
  Eigen::MatrixXd V, Vb;
  d.pose(s.frames, V);
  lbs.pose(s.frames, Vb);
  const double base_ms = median_ms([&] { lbs.pose(s.frames, Vb); });
  double total = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    d.pose(s.frames, V);
    benchmark::DoNotOptimize(V.data());
    total += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  state.counters["vertices"] = static_cast<double>(m.V.rows());
  state.counters["lbs_ms"] = base_ms;
  state.counters["vs_lbs"] = total / state.iterations() / base_ms;
  const char* names[] = {"lbs", "dlb", "log", "pivot-log"};
  state.SetLabel(names[state.range(0)]);
}
BENCHMARK(BM_skin_pose)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime();

/// LBS of a small mesh (issue 20: per-call overhead): a 4,608-vertex arm (tube 72 × 64, length 6) with
/// two bones, upper arm and forearm, blended over the elbow (at most 2 influences per vertex). The
/// baseline, measured in the same run (vs_matrix), is libigl's formulation of LBS (igl::lbs_matrix):
/// a dense n × 4B matrix M of weights times homogeneous rest coordinates, built once, and one
/// product V = M T per pose with T the 4B × 3 stack of the bones' transposed affine matrices.
void BM_skin_pose_small(benchmark::State& state) {
  static const Mesh arm = tube(0.5, 6.0, 72, 64);
  const Eigen::Index n = arm.V.rows();
  const std::vector<Bone> bones = {{"upper", -1, {0, 0, 0}, {0, 0, 3}}, {"fore", 0, {0, 0, 3}, {0, 0, 6}}};
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double u = std::clamp((arm.V(i, 2) - 2.5) / 1.0, 0.0, 1.0), w1 = u * u * (3 - 2 * u);
    if (w1 < 1) t.emplace_back(i, 0, 1 - w1);
    if (w1 > 0) t.emplace_back(i, 1, w1);
  }
  Eigen::SparseMatrix<double> W(n, 2);
  W.setFromTriplets(t.begin(), t.end());
  std::mt19937 rng(3);
  const std::vector<ga::Mot> frames = {random_motor(rng, 30, 0.2), random_motor(rng, 90, 0.2)};
  SkinDeformer d = SkinDeformer::bind(arm, bones, W, {SkinDeformer::Blend::LBS});
  Eigen::MatrixXd V;
  d.pose(frames, V);
  // libigl's formulation: M(i, 4j + c) = W(i, j) [p_i; 1](c); T rows 4j..4j+3 = (T_j)^T with T_j the
  // 3 × 4 affine matrix of bone j's motion (frame × rest⁻¹, as SkinDeformer composes it).
  const Eigen::MatrixXd Wd(W);
  Eigen::MatrixXd M(n, 8);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int j = 0; j < 2; ++j) {
      M.block<1, 3>(i, 4 * j) = Wd(i, j) * arm.V.row(i);
      M(i, 4 * j + 3) = Wd(i, j);
    }
  Eigen::MatrixXd T(8, 3), Vb(n, 3);
  auto matrix_pose = [&] {
    for (int j = 0; j < 2; ++j)
      T.block<4, 3>(4 * j, 0) = ga::to_isometry(ga::normalize(frames[j] * ga::reverse(bones[j].rest)))
                                    .matrix()
                                    .topRows<3>()
                                    .transpose();
    Vb.noalias() = M * T;
  };
  matrix_pose();
  const double base_ms = median_ms([&] {
                           for (int r = 0; r < 100; ++r) matrix_pose();
                         }) /
                         100;
  double total = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    d.pose(frames, V);
    benchmark::DoNotOptimize(V.data());
    total += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  state.counters["vertices"] = static_cast<double>(n);
  state.counters["matrix_ms"] = base_ms;
  state.counters["vs_matrix"] = total / state.iterations() / base_ms;
  state.counters["max_diff"] = (V - Vb).cwiseAbs().maxCoeff();  // the two formulations agree
}
BENCHMARK(BM_skin_pose_small)->Unit(benchmark::kMicrosecond)->MinTime(1.0)->UseRealTime();

struct CageSetup {
  Mesh cage, inner, inner100k;
};
const CageSetup& cage_setup() {
  static const CageSetup s = [] {
    CageSetup s;
    s.cage = uv_sphere(8, 12, 2.2);      // 98 vertices, 192 faces
    s.inner = torus(1.0, 0.4, 128, 80);  // 10,240 vertices
    s.inner100k = torus(1.0, 0.4, 400, 250);
    return s;
  }();
  return s;
}

/// arg: grid cells along the cage's largest extent
void BM_cage_bind(benchmark::State& state) {
  const CageSetup& s = cage_setup();
  const int grid = static_cast<int>(state.range(0));
  const double mvc_ms = median_ms(
      [&] { benchmark::DoNotOptimize(mean_value_coordinates(s.cage.V, s.cage.F, s.inner.V).data()); }, 3);
  double total = 0, err = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const Eigen::MatrixXd W = harmonic_cage_coordinates(s.cage.V, s.cage.F, s.inner.V, grid);
    total += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    err = (W * s.cage.V - s.inner.V).rowwise().norm().maxCoeff();
  }
  state.counters["cage_vertices"] = static_cast<double>(s.cage.V.rows());
  state.counters["points"] = static_cast<double>(s.inner.V.rows());
  state.counters["mvc_ms"] = mvc_ms;
  state.counters["vs_mvc"] = total / state.iterations() / mvc_ms;
  state.counters["reproduction_err"] = err;
  state.counters["bound"] = harmonic_interpolation_bound(s.cage.V, grid);
}
BENCHMARK(BM_cage_bind)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond)->Iterations(2);
// grid 128 only on request (SPINMOTOR_BENCH_CAGE128=1): ~2M grid nodes, a long 3D factorization.
const bool kCage128 =
    std::getenv("SPINMOTOR_BENCH_CAGE128") &&
    (benchmark::RegisterBenchmark("BM_cage_bind/128", [](benchmark::State& st) { BM_cage_bind(st); })
         ->Arg(128)
         ->Unit(benchmark::kMillisecond)
         ->Iterations(1),
     true);

/// arg: 10 or 100 (thousand points)
void BM_mvc_bind(benchmark::State& state) {
  const CageSetup& s = cage_setup();
  const Mesh& inner = state.range(0) == 10 ? s.inner : s.inner100k;
  for (auto _ : state) benchmark::DoNotOptimize(mean_value_coordinates(s.cage.V, s.cage.F, inner.V).data());
  state.counters["points"] = static_cast<double>(inner.V.rows());
  state.counters["cage_vertices"] = static_cast<double>(s.cage.V.rows());
}
BENCHMARK(BM_mvc_bind)->Arg(10)->Arg(100)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace

BENCHMARK_MAIN();

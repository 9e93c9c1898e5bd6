// bench_pinned_cleanup: the pose-keeping conformal cleanup (spin/pinned_cleanup.hpp) per frame.
//
// Mesh: the two-bone arm of tests/test_pinned_cleanup.cpp at two resolutions — capsule of radius 1 with
// a cylinder of length 6 (poles at z = −1 and 7), elbow at z = 3, lower-bone weight a smoothstep over
// z ∈ [2, 4]; pins = pins_from_weights(V, W, 0.999, 0.5) (3/8 of the length is free):
//   arm10k   capsule(1, 6, 120, 84):   10,082 vertices
//   arm100k  capsule(1, 6, 380, 264): 100,322 vertices (not with SPINMOTOR_BENCH_QUICK=1)
// Rows:
//   bind/<mesh>              PinnedCleanup::bind (validation, Laplacian, cells, factor of L_FF)
//   frame/<edit>/<mesh>      one cleanup() on the bound object (no factorisation), default options;
//                            edits: LBS of the elbow bent 90° (bend90) and bent 90° + twisted 90°
//                            (bend90twist90)
//   frame/<edit>/<mesh>/attract10   the same with the rig defaults' pose attraction (γ = 10, weights
//                            pin_attraction_from_weights: scene/rig_cleanup.hpp)
//   anim/<mesh>[/warm]       30 frames of an animation (elbow 0 → 90°, twist 0 → 45°, frame k at k/30),
//                            cleaned in order by one bound object; the time is per frame; /warm with
//                            options.warm_start (each frame starts from the previous correction);
//                            /attract10 with the rig defaults' pose attraction as above
// Counters: iterations (anim: mean per frame), local_ms, solve_ms, q_edit, q_mean, q_max, volume (ratio to
// rest), free (free vertices), rms (RMS distance to the edit / diagonal).
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "spinmotor/deform/rig_pins.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

namespace {

using namespace spinmotor;

struct Arm {
  Mesh mesh;
  Eigen::MatrixXd W;
  Eigen::VectorXi pins;
};

const Arm& arm(int rings, int sides) {
  static std::map<std::pair<int, int>, Arm> cache;
  auto it = cache.find({rings, sides});
  if (it != cache.end()) return it->second;
  Arm a;
  a.mesh = capsule(1.0, 6.0, rings, sides);
  a.W.resize(a.mesh.V.rows(), 2);
  for (Eigen::Index i = 0; i < a.mesh.V.rows(); ++i) {
    const double t = std::clamp((a.mesh.V(i, 2) - 2.0) / 2.0, 0.0, 1.0), w = t * t * (3 - 2 * t);
    a.W(i, 0) = 1 - w;
    a.W(i, 1) = w;
  }
  a.pins = pins_from_weights(a.mesh.V, a.W, 0.999, 0.5);
  return cache.emplace(std::make_pair(rings, sides), std::move(a)).first->second;
}

Eigen::MatrixXd lbs(const Arm& a, double bend, double twist) {
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(bend, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(twist, Eigen::Vector3d::UnitZ()))
          .toRotationMatrix();
  const Eigen::Vector3d e(0, 0, 3);
  Eigen::MatrixXd V = a.mesh.V;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const Eigen::Vector3d p = a.mesh.V.row(i).transpose();
    V.row(i) = (a.W(i, 0) * p + a.W(i, 1) * (R * (p - e) + e)).transpose();
  }
  return V;
}

void BM_Bind(benchmark::State& st, int rings, int sides) {
  const Arm& a = arm(rings, sides);
  for (auto _ : st) {
    PinnedCleanup pc = PinnedCleanup::bind(a.mesh, a.pins);
    benchmark::DoNotOptimize(pc.vertices());
  }
  st.counters["vertices"] = static_cast<double>(a.mesh.V.rows());
  st.counters["pins"] = static_cast<double>(a.pins.size());
}

void BM_Frame(benchmark::State& st, int rings, int sides, double bend_deg, double twist_deg, double gamma) {
  const Arm& a = arm(rings, sides);
  PinnedCleanupOptions o;
  o.pose_weight = gamma;
  PinnedCleanup pc = PinnedCleanup::bind(a.mesh, a.pins, o, pin_attraction_from_weights(a.W));
  const Eigen::MatrixXd E = lbs(a, bend_deg * M_PI / 180, twist_deg * M_PI / 180);
  Eigen::MatrixXd V;
  PinnedCleanupResult r;
  for (auto _ : st) {
    r = pc.cleanup(E, V);
    benchmark::DoNotOptimize(V.data());
  }
  const QuasiConformalSummary qe = quasi_conformal_summary(a.mesh.V, a.mesh.F, E);
  const QuasiConformalSummary q = quasi_conformal_summary(a.mesh.V, a.mesh.F, V);
  st.counters["iterations"] = r.iterations;
  st.counters["local_ms"] = r.local_ms;  // cell fits and energies
  st.counters["rhs_ms"] = r.rhs_ms;      // right-hand sides and the measure row's gradient
  st.counters["solve_ms"] = r.solve_ms;  // back-substitutions
  st.counters["q_edit"] = qe.q_mean;
  st.counters["q_mean"] = q.q_mean;
  st.counters["q_max"] = q.q_max;
  st.counters["volume"] = r.measure_ratio();
  st.counters["free"] = static_cast<double>(pc.free_vertices().size());
  st.counters["rms"] = std::sqrt((V - E).rowwise().squaredNorm().mean()) /
                       (E.colwise().maxCoeff() - E.colwise().minCoeff()).norm();
}

void BM_Anim(benchmark::State& st, int rings, int sides, bool warm, double gamma) {
  const Arm& a = arm(rings, sides);
  constexpr int kFrames = 30;
  std::vector<Eigen::MatrixXd> E;
  for (int f = 1; f <= kFrames; ++f) E.push_back(lbs(a, f * (M_PI / 2) / kFrames, f * (M_PI / 4) / kFrames));
  PinnedCleanupOptions o;
  o.warm_start = warm;
  o.pose_weight = gamma;
  PinnedCleanup pc = PinnedCleanup::bind(a.mesh, a.pins, o, pin_attraction_from_weights(a.W));
  Eigen::MatrixXd V;
  PinnedCleanupResult r;
  long steps = 0, runs = 0;
  for (auto _ : st) {
    pc.reset();
    for (const Eigen::MatrixXd& e : E) {
      r = pc.cleanup(e, V);
      steps += r.iterations;
    }
    ++runs;
    benchmark::DoNotOptimize(V.data());
  }
  const QuasiConformalSummary q = quasi_conformal_summary(a.mesh.V, a.mesh.F, V);
  st.counters["frames"] = kFrames;
  st.counters["iterations"] = static_cast<double>(steps) / static_cast<double>(runs * kFrames);
  st.counters["q_mean"] = q.q_mean;
  st.counters["q_max"] = q.q_max;
  st.counters["energy"] = r.energy.back();
  st.SetItemsProcessed(runs * kFrames);  // items/s = frames per second
}

const bool registered = [] {
  const bool quick = std::getenv("SPINMOTOR_BENCH_QUICK") != nullptr;
  struct M {
    const char* name;
    int rings, sides;
  };
  for (const M m : {M{"arm10k", 120, 84}, M{"arm100k", 380, 264}}) {
    if (quick && m.rings > 200) continue;
    const int reps = m.rings > 200 ? 2 : 5;
    benchmark::RegisterBenchmark((std::string("bind/") + m.name).c_str(), BM_Bind, m.rings, m.sides)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(reps);
    for (const double gamma : {0.0, 10.0}) {
      const std::string suffix = gamma > 0 ? "/attract10" : "";
      benchmark::RegisterBenchmark((std::string("frame/bend90/") + m.name + suffix).c_str(), BM_Frame,
                                   m.rings, m.sides, 90.0, 0.0, gamma)
          ->Unit(benchmark::kMillisecond)
          ->Iterations(reps);
      benchmark::RegisterBenchmark((std::string("frame/bend90twist90/") + m.name + suffix).c_str(), BM_Frame,
                                   m.rings, m.sides, 90.0, 90.0, gamma)
          ->Unit(benchmark::kMillisecond)
          ->Iterations(reps);
    }
    for (const double gamma : {0.0, 10.0})
      for (const bool warm : {false, true})
        benchmark::RegisterBenchmark(
            (std::string("anim/") + m.name + (gamma > 0 ? "/attract10" : "") + (warm ? "/warm" : "")).c_str(),
            BM_Anim, m.rings, m.sides, warm, gamma)
            ->Unit(benchmark::kMillisecond)
            ->Iterations(1);
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();

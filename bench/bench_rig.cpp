// glTF rigs (mesh/gltf.hpp, deform/rig_skin.hpp), 2 cores: the per-frame cost of posing a rig's
// animation — the skinning transforms at time t (rig_pose_motors: node hierarchy, animation sampling,
// S_j = W_mesh⁻¹ W_j IBM_j as motors) plus SkinDeformer::pose, bound once — for every blend, next to a
// plain Eigen LBS baseline measured in the same run on the same mesh: skinning_matrices(t) and, per
// vertex, Σ w_j (L_j v + t_j) over the same ≤ 4 influences with Eigen 3×4 matrices (OpenMP over
// vertices, as the deformer).
//   BM_rig_pose/<rig>/<blend>   rig 0: CesiumMan (../shared/rigs, 2,338 welded vertices, 19 joints;
//                               skipped without the folder), 1: the procedural limb at 10k vertices,
//                               2: at 100k (8 joints, limb_rig); blend 0 lbs, 1 dlb, 2 log, 3 pivot-log.
// Counters: us_per_frame (median), eigen_lbs_us (the baseline's median of 30 frames), vs_eigen_lbs (ratio),
// motors_us (rig_pose_motors alone), vertices, joints. Frames cycle through 30 times of the animation.
// SPINMOTOR_BENCH_QUICK=1 (bench/run --quick): the 10k limb only.
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <vector>

#include "spinmotor/deform/rig_skin.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/mesh/procedural_rig.hpp"

using namespace spinmotor;

namespace {

const bool kQuick = std::getenv("SPINMOTOR_BENCH_QUICK") != nullptr;

/// The rigs, built once: CesiumMan read from ../shared, the limbs generated.
const GltfRig* rig(int which) {
  static std::map<int, std::unique_ptr<GltfRig>> cache;
  auto& slot = cache[which];
  if (!slot) {
    if (which == 0) {
      const std::filesystem::path p = std::filesystem::path(SPINMOTOR_RIGS_DIR) / "CesiumMan.gltf";
      if (!std::filesystem::exists(p)) return nullptr;
      slot = std::make_unique<GltfRig>(read_gltf(p));
    } else if (which == 1) {
      slot = std::make_unique<GltfRig>(limb_rig({.rings = 200, .sides = 50, .joints = 8}));  // 10,002
    } else {
      slot = std::make_unique<GltfRig>(limb_rig({.rings = 1000, .sides = 100, .joints = 8}));  // 100,002
    }
  }
  return slot.get();
}

/// The plain Eigen LBS baseline: ≤ 4 influences per vertex (the largest, renormalised — what
/// SkinDeformer keeps), 3×4 matrices per joint.
struct EigenLbs {
  std::vector<std::array<int, 4>> joint;
  std::vector<std::array<double, 4>> weight;
  std::vector<Eigen::Matrix<double, 3, 4>> M;
  explicit EigenLbs(const GltfRig& r) {
    const Eigen::Index n = r.mesh.V.rows();
    joint.assign(n, {0, 0, 0, 0});
    weight.assign(n, {0, 0, 0, 0});
    std::vector<std::vector<std::pair<double, int>>> rows(n);
    for (int j = 0; j < r.weights.outerSize(); ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(r.weights, j); it; ++it)
        rows[it.row()].emplace_back(it.value(), j);
    for (Eigen::Index i = 0; i < n; ++i) {
      std::sort(rows[i].begin(), rows[i].end(), [](auto& a, auto& b) { return a.first > b.first; });
      double s = 0;
      for (size_t k = 0; k < std::min<size_t>(4, rows[i].size()); ++k) s += rows[i][k].first;
      for (size_t k = 0; k < std::min<size_t>(4, rows[i].size()); ++k)
        joint[i][k] = rows[i][k].second, weight[i][k] = rows[i][k].first / s;
    }
  }
  void pose(const GltfRig& r, double t, Eigen::MatrixXd& V) {
    const std::vector<Eigen::Matrix4d> S = skinning_matrices(r, 0, t);
    M.resize(S.size());
    for (size_t j = 0; j < S.size(); ++j) M[j] = S[j].topRows<3>();
    const Eigen::Index n = r.mesh.V.rows();
    V.resize(n, 3);
#pragma omp parallel for schedule(static) if (n > 20000)
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::Matrix<double, 3, 4> A = weight[i][0] * M[joint[i][0]];
      for (int k = 1; k < 4; ++k)
        if (weight[i][k] != 0) A.noalias() += weight[i][k] * M[joint[i][k]];
      V.row(i) = (A.leftCols<3>() * r.mesh.V.row(i).transpose() + A.col(3)).transpose();
    }
  }
};

double time_at(const GltfRig& r, int k) {
  const GltfAnimation& a = r.animations[0];
  return a.start + (a.end - a.start) * (k % 30) / 29.0;
}

double us_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
}

void BM_rig_pose(benchmark::State& state) {
  const GltfRig* r = rig(static_cast<int>(state.range(0)));
  if (!r) {
    state.SkipWithError("../shared/rigs/CesiumMan.gltf not found");
    return;
  }
  const SkinBlend blends[] = {SkinBlend::LBS, SkinBlend::Linear, SkinBlend::Log, SkinBlend::PivotLog};
  SkinDeformer d = bind_rig(*r, blends[state.range(1)]);
  Eigen::MatrixXd V, Vb;
  // The baseline: the median of 30 frames (after one warm-up).
  EigenLbs base(*r);
  base.pose(*r, time_at(*r, 0), Vb);
  std::vector<double> base_us, motor_us;
  for (int k = 0; k < 30; ++k) {
    auto t0 = std::chrono::steady_clock::now();
    base.pose(*r, time_at(*r, k), Vb);
    base_us.push_back(us_since(t0));
    benchmark::DoNotOptimize(Vb.data());
    t0 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(rig_pose_motors(*r, 0, time_at(*r, k)).data());
    motor_us.push_back(us_since(t0));
  }
  std::sort(base_us.begin(), base_us.end());
  std::sort(motor_us.begin(), motor_us.end());
  d.pose(rig_pose_motors(*r, 0, time_at(*r, 0)), V);
  std::vector<double> frame_us;
  int k = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    d.pose(rig_pose_motors(*r, 0, time_at(*r, k++)), V);
    benchmark::DoNotOptimize(V.data());
    frame_us.push_back(us_since(t0));
  }
  std::sort(frame_us.begin(), frame_us.end());
  const double us = frame_us[frame_us.size() / 2];  // medians on both sides: robust to a loaded machine
  state.counters["vertices"] = static_cast<double>(r->mesh.V.rows());
  state.counters["joints"] = static_cast<double>(r->num_joints());
  state.counters["us_per_frame"] = us;
  state.counters["eigen_lbs_us"] = base_us[15];
  state.counters["vs_eigen_lbs"] = us / base_us[15];
  state.counters["motors_us"] = motor_us[15];
  const char* rigs[] = {"CesiumMan", "limb-10k", "limb-100k"};
  const char* names[] = {"lbs", "dlb", "log", "pivot-log"};
  state.SetLabel(std::string(rigs[state.range(0)]) + " " + names[state.range(1)]);
}

void rig_args(benchmark::internal::Benchmark* b) {
  for (int r : kQuick ? std::vector<int>{1} : std::vector<int>{0, 1, 2})
    for (int blend = 0; blend < 4; ++blend) b->Args({r, blend});
}
BENCHMARK(BM_rig_pose)->Apply(rig_args)->Unit(benchmark::kMicrosecond)->MinTime(0.5)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

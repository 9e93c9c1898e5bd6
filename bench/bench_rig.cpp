// glTF rigs (mesh/gltf.hpp, deform/gltf_skin.hpp), 2 cores: the per-frame cost of posing a rig's
// animation — RigSkinner::pose: the pose transforms at time t (node hierarchy, animation sampling,
// T_j = W_j IBM_j B⁻¹), morph weights, and SkinDeformer::pose_affine, bound once — for every blend, next
// to a plain Eigen LBS baseline measured in the same run on the same mesh: the joint matrices S_j(t) and,
// per vertex, Σ w_j (L_j v + t_j) over the same influences (every one: the glTF formula) with Eigen 3×4
// matrices (OpenMP over vertices, as the deformer).
//   BM_rig_pose/<rig>/<blend>   rig 0: CesiumMan (../shared/rigs, 2,338 welded vertices, 19 joints;
//                               skipped without the folder), 1: the procedural limb at 10k vertices,
//                               2: at 100k (8 joints, limb_rig); blend 0 lbs, 1 dlb, 2 log, 3 pivot-log.
// Counters: us_per_frame (median), eigen_lbs_us (the baseline's median of 30 frames), vs_eigen_lbs (ratio),
// transforms_us (rig_joint_transforms alone), vertices, joints. Frames cycle through 30 times of the
// animation. SPINMOTOR_BENCH_QUICK=1 (bench/run --quick): the 10k limb only.
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

#include "spinmotor/deform/gltf_animation.hpp"
#include "spinmotor/deform/gltf_skin.hpp"
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

/// The plain Eigen LBS baseline: every influence of a vertex (the rig's rows sum to 1), 3×4 joint
/// matrices S_j = W_j IBM_j applied to POSITION.
struct EigenLbs {
  std::vector<std::vector<std::pair<int, double>>> rows;
  std::vector<Eigen::Matrix<double, 3, 4>> M;
  explicit EigenLbs(const GltfRig& r) : rows(static_cast<size_t>(r.mesh.V.rows())) {
    for (int j = 0; j < r.weights.outerSize(); ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(r.weights, j); it; ++it)
        rows[it.row()].emplace_back(j, it.value());
  }
  void pose(const GltfRig& r, double t, Eigen::MatrixXd& V) {
    const std::vector<Eigen::Matrix4d> S = joint_matrices(r, node_world_matrices(r, 0, t));
    M.resize(S.size());
    for (size_t j = 0; j < S.size(); ++j) M[j] = S[j].topRows<3>();
    const Eigen::Index n = r.mesh.V.rows();
    V.resize(n, 3);
#pragma omp parallel for schedule(static) if (n > 20000)
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::Matrix<double, 3, 4> A = rows[i][0].second * M[rows[i][0].first];
      for (size_t k = 1; k < rows[i].size(); ++k) A.noalias() += rows[i][k].second * M[rows[i][k].first];
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
  const SkinBlend blends[] = {SkinBlend::LBS, SkinBlend::DLB, SkinBlend::Log, SkinBlend::PivotLog};
  RigSkinner d(*r, blends[state.range(1)]);
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
    benchmark::DoNotOptimize(rig_joint_transforms(*r, d.skin(), 0, time_at(*r, k)).data());
    motor_us.push_back(us_since(t0));
  }
  std::sort(base_us.begin(), base_us.end());
  std::sort(motor_us.begin(), motor_us.end());
  d.pose(0, time_at(*r, 0), V);
  std::vector<double> frame_us;
  int k = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    d.pose(0, time_at(*r, k++), V);
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
  state.counters["transforms_us"] = motor_us[15];
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

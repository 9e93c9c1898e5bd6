// bench_snap: the conformal snap (spin/conformal_snap.hpp, Crane et al. 2011 §7.2).
//
// Timing rows (snap/<row>/<mesh>), each edit a closed-form bend of the mesh along its longest
// bounding-box axis (60° over its length):
//   first    bind (validation, vertex ordering, symbolic analysis, cotangent Laplacian factor) + one snap:
//            the baseline of the row below, and what a one-shot `spinmotor snap` costs
//   second   one more snap on the SAME bound ConformalSnap (another edit: 45°): nothing that depends
//            only on the rest mesh is recomputed (no Laplacian refactorization, no symbolic analysis)
// Meshes: spot (spot.obj, 2,930 vertices, 5,856 faces), capsule10k (capsule(0.5, 2, 50, 100): 5,002
// vertices, 10,000 faces), nefertiti (nefertiti.obj, 49,971 vertices, 99,938 faces; not with
// SPINMOTOR_BENCH_QUICK=1).
// Counters: bind_ms, fit_ms (per-face similarities, vertex averages, optimal ρ), eigen_ms (assembly,
// numeric factorization, inverse iteration), poisson_ms (blend, eq. 8, Poisson solve, alignment),
// total_ms, q_before, q_after, rms_to_edit (relative to the edit's bounding-box diagonal), and on
// second rows speedup = first total / second total (same run).
//
// Pose-retention study (retain/<edit>/t=<t>): how much of a large bend the snap keeps as the tradeoff
// t goes 0 → 1 (Fig. 21): sausage (icosphere(4), z × 3) bent 90° along its axis by the closed-form
// bending map of tests/test_snap.cpp, and a procedurally skinned arm (capsule(0.5, 4, 80, 32)
// posed by a two-bone linear blend skin written here: the forearm turned 90° about y at the elbow
// z = 2, weights a smoothstep over z ∈ [1.6, 2.4]). Counters: angle_edit and angle_snap (degrees
// between the end axes: directions between the centroids of the first and second sixth of the rest
// length at each end), kept (angle_snap / angle_edit), rms_to_edit, q_edit, q_snap. A table is printed
// to stderr after the run. The arm is also snapped with rho_smoothing = 20 (its ρ has spikes at the
// elbow crease).
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/conformal_snap.hpp"

using namespace spinmotor;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::Vector3d;

namespace {

const std::string kMeshes = SPINMOTOR_MESHES_DIR;
using Clock = std::chrono::steady_clock;

bool quick() {
  const char* q = std::getenv("SPINMOTOR_BENCH_QUICK");
  return q && std::string(q) == "1";
}

/// Bend by `degrees` along the longest bounding-box axis: that axis is laid on a circular arc of the
/// same length in the plane of the axis and the second-longest one.
MatrixXd bend_longest(const MatrixXd& V, double degrees) {
  const Eigen::RowVector3d lo = V.colwise().minCoeff(), hi = V.colwise().maxCoeff(), ext = hi - lo;
  int a = 0;
  ext.maxCoeff(&a);
  int b = (a + 1) % 3;
  if (ext[(a + 2) % 3] > ext[b]) b = (a + 2) % 3;
  const double L = ext[a], R = L / (degrees * M_PI / 180.0), mid = 0.5 * (lo[a] + hi[a]),
               cb = 0.5 * (lo[b] + hi[b]);
  MatrixXd out = V;
  for (Index i = 0; i < V.rows(); ++i) {
    const double phi = (V(i, a) - mid) / R, x = V(i, b) - cb;
    out(i, b) = cb + R * (1 - std::cos(phi)) + x * std::cos(phi);
    out(i, a) = mid + R * std::sin(phi) - x * std::sin(phi);
  }
  return out;
}

const Mesh& get_mesh(const std::string& name) {
  static std::map<std::string, Mesh> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  Mesh m = name == "spot"        ? read_mesh(kMeshes + "/spot.obj")
           : name == "nefertiti" ? read_mesh(kMeshes + "/nefertiti.obj")
                                 : capsule(0.5, 2.0, 50, 100);
  return cache.emplace(name, std::move(m)).first->second;
}

std::map<std::string, double>& first_total() {
  static std::map<std::string, double> t;
  return t;
}

void report(benchmark::State& state, const Mesh& m, const MatrixXd& edit, const ConformalSnapResult& r,
            double bind_ms, double runs) {
  state.counters["bind_ms"] = bind_ms / runs;
  state.counters["fit_ms"] = r.timings.similarity_fit;
  state.counters["eigen_ms"] = r.timings.eigen;
  state.counters["poisson_ms"] = r.timings.poisson;
  state.counters["q_before"] = quasi_conformal_summary(m.V, m.F, edit).q_mean;
  state.counters["q_after"] = quasi_conformal_summary(m.V, m.F, r.V).q_mean;
  state.counters["rms_to_edit"] = vertex_distances(edit, r.V).rms;
  state.counters["faces"] = static_cast<double>(m.F.rows());
}

void BM_first(benchmark::State& state, std::string name) {
  const Mesh& m = get_mesh(name);
  const MatrixXd edit = bend_longest(m.V, 60.0);
  ConformalSnapResult r;
  double bind = 0, total = 0, runs = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    ConformalSnap cs(m);
    bind += cs.bind_ms();
    r = cs.snap(edit);
    total += ms_since(t0);
    ++runs;
  }
  report(state, m, edit, r, bind, runs);
  state.counters["total_ms"] = total / runs;
  first_total()[name] = total / runs;
}

void BM_second(benchmark::State& state, std::string name) {
  const Mesh& m = get_mesh(name);
  const MatrixXd edit0 = bend_longest(m.V, 60.0), edit = bend_longest(m.V, 45.0);
  ConformalSnap cs(m);
  cs.snap(edit0);  // the interactive session's first pose
  ConformalSnapResult r;
  double total = 0, runs = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    r = cs.snap(edit);
    total += ms_since(t0);
    ++runs;
  }
  report(state, m, edit, r, 0.0, 1.0);
  state.counters["total_ms"] = total / runs;
  auto f = first_total().find(name);
  if (f != first_total().end()) state.counters["speedup"] = f->second / (total / runs);
}

// ---------------------------------------------------------------------------------------------------
// Pose retention.

/// Angle (degrees) between the end axes, from slabs of the rest coordinate z over [z0, z1].
double bend_angle(const MatrixXd& rest, const MatrixXd& V, double z0, double z1) {
  const double d = (z1 - z0) / 6.0;
  Vector3d c[4] = {Vector3d::Zero(), Vector3d::Zero(), Vector3d::Zero(), Vector3d::Zero()};
  int k[4] = {0, 0, 0, 0};
  for (Index i = 0; i < rest.rows(); ++i) {
    const double z = rest(i, 2);
    const int s = z <= z0 + d ? 0 : z <= z0 + 2 * d ? 1 : z >= z1 - d ? 3 : z >= z1 - 2 * d ? 2 : -1;
    if (s >= 0) c[s] += V.row(i).transpose(), ++k[s];
  }
  for (int s = 0; s < 4; ++s) c[s] /= std::max(k[s], 1);
  const Vector3d a = (c[0] - c[1]).normalized(), b = (c[3] - c[2]).normalized();
  return 180.0 - std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / M_PI;
}

struct RetentionCase {
  Mesh rest;
  MatrixXd edit;
  double z0, z1;
};

const RetentionCase& retention_case(const std::string& name) {
  static std::map<std::string, RetentionCase> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  RetentionCase c;
  if (name == "sausage_bend90") {
    c.rest = icosphere(4);
    c.rest.V.col(2) *= 3.0;
    c.z0 = -3, c.z1 = 3;
    const double R = 6.0 / (M_PI / 2);
    c.edit = c.rest.V;
    for (Index i = 0; i < c.edit.rows(); ++i) {
      const double phi = c.rest.V(i, 2) / R, x = c.rest.V(i, 0);
      c.edit(i, 0) = R * (1 - std::cos(phi)) + x * std::cos(phi);
      c.edit(i, 2) = R * std::sin(phi) - x * std::sin(phi);
    }
  } else {  // two-bone LBS arm, elbow at z = 2, forearm turned 90° about y
    c.rest = capsule(0.5, 4.0, 80, 32);
    c.z0 = -0.5, c.z1 = 4.5;
    const Eigen::Matrix3d Rl = Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()).toRotationMatrix();
    const Vector3d joint(0, 0, 2);
    c.edit = c.rest.V;
    for (Index i = 0; i < c.edit.rows(); ++i) {
      const Vector3d p = c.rest.V.row(i).transpose();
      const double s = std::clamp((p.z() - 1.6) / 0.8, 0.0, 1.0), w = s * s * (3 - 2 * s);  // smoothstep
      c.edit.row(i) = ((1 - w) * p + w * (Rl * (p - joint) + joint)).transpose();           // LBS of 2 bones
    }
  }
  return cache.emplace(name, std::move(c)).first->second;
}

struct RetentionRow {
  std::string name;
  double t, angle_edit, angle_snap, rms, q_edit, q_snap;
};
std::vector<RetentionRow>& retention_rows() {
  static std::vector<RetentionRow> rows;
  return rows;
}

void BM_retention(benchmark::State& state, std::string name, double t, int smoothing) {
  const RetentionCase& c = retention_case(name);
  ConformalSnap cs(c.rest, {.tradeoff = t, .rho_smoothing = smoothing});
  ConformalSnapResult r;
  for (auto _ : state) r = cs.snap(c.edit);
  RetentionRow row{smoothing ? name + "_smooth" + std::to_string(smoothing) : name,
                   t,
                   bend_angle(c.rest.V, c.edit, c.z0, c.z1),
                   bend_angle(c.rest.V, r.V, c.z0, c.z1),
                   vertex_distances(c.edit, r.V).rms,
                   quasi_conformal_summary(c.rest.V, c.rest.F, c.edit).q_mean,
                   quasi_conformal_summary(c.rest.V, c.rest.F, r.V).q_mean};
  state.counters["angle_edit"] = row.angle_edit;
  state.counters["angle_snap"] = row.angle_snap;
  state.counters["kept"] = row.angle_snap / row.angle_edit;
  state.counters["rms_to_edit"] = row.rms;
  state.counters["q_edit"] = row.q_edit;
  state.counters["q_snap"] = row.q_snap;
  retention_rows().push_back(row);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::pair<std::string, int>> meshes = {{"spot", 5}, {"capsule10k", 5}};
  if (!quick()) meshes.emplace_back("nefertiti", 2);
  for (const auto& [name, iters] : meshes) {
    benchmark::RegisterBenchmark(("snap/first/" + name).c_str(), BM_first, name)
        ->Iterations(iters)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("snap/second/" + name).c_str(), BM_second, name)
        ->Iterations(iters)
        ->Unit(benchmark::kMillisecond);
  }
  for (const char* name : {"sausage_bend90", "arm_lbs90"})
    for (double t : {0.0, 0.25, 0.5, 0.75, 1.0}) {
      char label[64];
      std::snprintf(label, sizeof label, "retain/%s/t=%.2f", name, t);
      benchmark::RegisterBenchmark(label, BM_retention, std::string(name), t, 0)
          ->Iterations(1)
          ->Unit(benchmark::kMillisecond);
    }
  // The skinned arm's ρ has spikes at the elbow crease: the same with 20 passes of ρ smoothing.
  for (double t : {0.5, 1.0}) {
    char label[64];
    std::snprintf(label, sizeof label, "retain/arm_lbs90_smooth20/t=%.2f", t);
    benchmark::RegisterBenchmark(label, BM_retention, std::string("arm_lbs90"), t, 20)
        ->Iterations(1)
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  if (!retention_rows().empty()) {
    std::fprintf(stderr,
                 "\npose retention (angle between end axes, degrees; RMS relative to the edit's diagonal)\n");
    std::fprintf(stderr, "%-16s %5s %10s %10s %6s %9s %8s %8s\n", "edit", "t", "angle_edit", "angle_snap",
                 "kept", "rms_edit", "Q_edit", "Q_snap");
    for (const RetentionRow& r : retention_rows())
      std::fprintf(stderr, "%-16s %5.2f %10.1f %10.1f %6.2f %9.4f %8.4f %8.4f\n", r.name.c_str(), r.t,
                   r.angle_edit, r.angle_snap, r.angle_snap / r.angle_edit, r.rms, r.q_edit, r.q_snap);
  }
  return 0;
}

// bench_ga: the CGA motor kernels against Eigen in the same run.
//
//   mot_mul          Mot * Mot                          vs  Eigen dual-quaternion product (2-3 Quaterniond *)
//   transform_1M     transform(M, x) over 1M points     vs  q * x + t   and   Isometry3d * x
//   exp / log        motor exp / log                    vs  Quaterniond(AngleAxisd) / AngleAxisd(Quaterniond)
//   blend4_*         4-way blend, Log / PivotLog        vs  Linear (and Linear vs a hand-written Eigen DLB);
//                    distinct motors per vertex (the worst case), and Log with the logs precomputed
//
// Each benchmark reports "ns/op" (per product, point, exp, log or blend) and, where it has a baseline,
// "x_base" = ns/op / baseline ns/op. A summary table with the targets is printed at the end.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <array>
#include <cstdio>
#include <map>
#include <random>
#include <spinmotor/ga.hpp>
#include <string>
#include <vector>

using namespace spinmotor::ga;

namespace {

constexpr int kBatch = 4096;        // motors per iteration for the small kernels (fits in L1/L2)
constexpr int kPoints = 1'000'000;  // points for the transform benchmarks

std::vector<Eigen::Isometry3d> random_isometries(int n, unsigned seed) {
  std::mt19937 g(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<Eigen::Isometry3d> v(static_cast<std::size_t>(n));
  for (auto& iso : v) {
    iso = Eigen::Isometry3d::Identity();
    iso.linear() =
        Eigen::AngleAxisd(u(g), Eigen::Vector3d(nd(g), nd(g), nd(g)).normalized()).toRotationMatrix();
    iso.translation() = Eigen::Vector3d(u(g), u(g), u(g));
  }
  return v;
}

std::vector<Mot> random_motors(int n, unsigned seed) {
  std::vector<Mot> m;
  for (const auto& iso : random_isometries(n, seed)) m.push_back(from_isometry(iso));
  return m;
}

void set_per_op(benchmark::State& state, double ops_per_iteration) {
  state.counters["ops"] = ops_per_iteration;  // read back by the reporter to compute ns/op
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * ops_per_iteration));
}

// ---- products ------------------------------------------------------------------------------------

void ga_mot_mul(benchmark::State& state) {
  const auto a = random_motors(kBatch, 1), b = random_motors(kBatch, 2);
  std::vector<Mot> c(kBatch);
  for (auto _ : state) {
    for (int i = 0; i < kBatch; ++i) c[i] = a[i] * b[i];
    benchmark::DoNotOptimize(c.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kBatch);
}

void eigen_quat_mul(benchmark::State& state) {
  std::vector<Eigen::Quaterniond> a, b, c(kBatch);
  for (const auto& iso : random_isometries(kBatch, 1)) a.emplace_back(iso.linear());
  for (const auto& iso : random_isometries(kBatch, 2)) b.emplace_back(iso.linear());
  for (auto _ : state) {
    for (int i = 0; i < kBatch; ++i) c[i] = a[i] * b[i];
    benchmark::DoNotOptimize(c.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kBatch);
}

struct DualQuat {
  Eigen::Quaterniond r, d;
};

void eigen_dualquat_mul(benchmark::State& state) {
  std::vector<DualQuat> a, b, c(kBatch);
  for (const auto& m : random_motors(kBatch, 1))
    a.push_back({to_dual_quaternion(m).first, to_dual_quaternion(m).second});
  for (const auto& m : random_motors(kBatch, 2))
    b.push_back({to_dual_quaternion(m).first, to_dual_quaternion(m).second});
  for (auto _ : state) {
    for (int i = 0; i < kBatch; ++i) {
      const Eigen::Quaterniond rd = a[i].r * b[i].d, dr = a[i].d * b[i].r;
      c[i].r = a[i].r * b[i].r;
      c[i].d.coeffs() = rd.coeffs() + dr.coeffs();
    }
    benchmark::DoNotOptimize(c.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kBatch);
}

// ---- transform of 1M points -------------------------------------------------------------------------

struct Cloud {
  Eigen::Matrix3Xd p, out;
  Cloud() : p(Eigen::Matrix3Xd::Random(3, kPoints) * 10.0), out(3, kPoints) {}
};
Cloud& cloud() {
  static Cloud c;
  return c;
}

void ga_transform_1M(benchmark::State& state) {
  auto& c = cloud();
  const Mot m = random_motors(1, 3)[0];
  for (auto _ : state) {
    for (Eigen::Index i = 0; i < kPoints; ++i) c.out.col(i) = transform(m, c.p.col(i));
    benchmark::DoNotOptimize(c.out.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kPoints);
}

void eigen_quat_transform_1M(benchmark::State& state) {
  auto& c = cloud();
  const auto iso = random_isometries(1, 3)[0];
  const Eigen::Quaterniond q(iso.linear());
  const Eigen::Vector3d t = iso.translation();
  for (auto _ : state) {
    for (Eigen::Index i = 0; i < kPoints; ++i) c.out.col(i) = q * Eigen::Vector3d(c.p.col(i)) + t;
    benchmark::DoNotOptimize(c.out.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kPoints);
}

void eigen_isometry_transform_1M(benchmark::State& state) {
  auto& c = cloud();
  const auto iso = random_isometries(1, 3)[0];
  for (auto _ : state) {
    for (Eigen::Index i = 0; i < kPoints; ++i) c.out.col(i) = iso * Eigen::Vector3d(c.p.col(i));
    benchmark::DoNotOptimize(c.out.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kPoints);
}

// The generic algebra path for comparison: down(M up(x) ~M) with the full typed sandwich.
void ga_sandwich_point_1M(benchmark::State& state) {
  auto& c = cloud();
  const Mot m = random_motors(1, 3)[0];
  for (auto _ : state) {
    for (Eigen::Index i = 0; i < kPoints; ++i) {
      const Pnt x = sandwich(m, up(c.p.col(i)));
      c.out.col(i) = Eigen::Vector3d(x[0], x[1], x[2]);  // M preserves the weight: x[3] = 1
    }
    benchmark::DoNotOptimize(c.out.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kPoints);
}

// ---- exp / log ------------------------------------------------------------------------------------------

void ga_exp(benchmark::State& state) {
  std::vector<Dll> b;
  for (const auto& m : random_motors(kBatch, 4)) b.push_back(log(m));
  std::vector<Mot> out(kBatch);
  for (auto _ : state) {
    for (int i = 0; i < kBatch; ++i) out[i] = exp(b[i]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kBatch);
}

void ga_log(benchmark::State& state) {
  const auto m = random_motors(kBatch, 4);
  std::vector<Dll> out(kBatch);
  for (auto _ : state) {
    for (int i = 0; i < kBatch; ++i) out[i] = log(m[i]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kBatch);
}

void eigen_angleaxis_to_quat(benchmark::State& state) {
  std::vector<Eigen::AngleAxisd> aa;
  for (const auto& iso : random_isometries(kBatch, 4)) aa.emplace_back(iso.linear());
  std::vector<Eigen::Quaterniond> out(kBatch);
  for (auto _ : state) {
    for (int i = 0; i < kBatch; ++i) out[i] = Eigen::Quaterniond(aa[i]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kBatch);
}

void eigen_quat_to_angleaxis(benchmark::State& state) {
  std::vector<Eigen::Quaterniond> q;
  for (const auto& iso : random_isometries(kBatch, 4)) q.emplace_back(iso.linear());
  std::vector<Eigen::AngleAxisd> out(kBatch);
  for (auto _ : state) {
    for (int i = 0; i < kBatch; ++i) out[i] = Eigen::AngleAxisd(q[i]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kBatch);
}

// ---- 4-way blends (one per "vertex", as in skinning) -------------------------------------------------

struct Rig {
  std::vector<std::array<Mot, 4>> m;
  std::vector<std::array<double, 4>> w;
  Rig() : m(kBatch), w(kBatch) {
    const auto all = random_motors(4 * kBatch, 5);
    std::mt19937 g(6);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < kBatch; ++i) {
      double s = 0.0;
      for (int k = 0; k < 4; ++k) {
        m[i][k] = all[4 * i + k];
        s += (w[i][k] = u(g));
      }
      for (auto& x : w[i]) x /= s;
    }
  }
};
const Rig& rig() {
  static const Rig r;
  return r;
}

void run_blend(benchmark::State& state, Blend mode) {
  const Rig& r = rig();
  std::vector<Mot> out(kBatch);
  for (auto _ : state) {
    for (int i = 0; i < kBatch; ++i) out[i] = blend(r.m[i], r.w[i], mode);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kBatch);
}
void ga_blend4_log(benchmark::State& s) { run_blend(s, Blend::Log); }
void ga_blend4_pivotlog(benchmark::State& s) { run_blend(s, Blend::PivotLog); }
void ga_blend4_linear(benchmark::State& s) { run_blend(s, Blend::DLB); }

// The paper's blend when the motors are shared handles: their logs are computed once, per vertex
// only exp(Σ w_i B_i) remains.
void ga_blend4_shared_logs(benchmark::State& state) {
  const Rig& r = rig();
  std::vector<std::array<Dll, 4>> logs(kBatch);
  for (int i = 0; i < kBatch; ++i)
    for (int k = 0; k < 4; ++k) logs[i][k] = log(r.m[i][k]);
  std::vector<Mot> out(kBatch);
  for (auto _ : state) {
    for (int i = 0; i < kBatch; ++i) out[i] = blend_logs(logs[i], r.w[i]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kBatch);
}

// Dual-quaternion linear blending written directly on Eigen quaternions (the DLB baseline).
void eigen_dlb4(benchmark::State& state) {
  const Rig& r = rig();
  std::vector<std::array<DualQuat, 4>> dq(kBatch);
  for (int i = 0; i < kBatch; ++i)
    for (int k = 0; k < 4; ++k)
      dq[i][k] = {to_dual_quaternion(r.m[i][k]).first, to_dual_quaternion(r.m[i][k]).second};
  std::vector<DualQuat> out(kBatch);
  for (auto _ : state) {
    for (int i = 0; i < kBatch; ++i) {
      const auto& w = r.w[i];
      int p = 0;
      for (int k = 1; k < 4; ++k)
        if (w[k] > w[p]) p = k;
      Eigen::Vector4d rs = Eigen::Vector4d::Zero(), ds = Eigen::Vector4d::Zero();
      for (int k = 0; k < 4; ++k) {
        const double s = dq[i][k].r.coeffs().dot(dq[i][p].r.coeffs()) < 0.0 ? -w[k] : w[k];
        rs += s * dq[i][k].r.coeffs();
        ds += s * dq[i][k].d.coeffs();
      }
      const double inv = 1.0 / rs.norm();
      rs *= inv;
      ds *= inv;
      ds -= rs.dot(ds) * rs;
      out[i].r.coeffs() = rs;
      out[i].d.coeffs() = ds;
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  set_per_op(state, kBatch);
}

// ---- reporting ---------------------------------------------------------------------------------------

struct Target {
  const char* subject;
  const char* baseline;
  double max_ratio;  // 0: no ratio target
  double max_ns;     // 0: no absolute target
};
const Target kTargets[] = {
    {"ga_mot_mul", "eigen_dualquat_mul", 0.0, 10.0},
    {"eigen_dualquat_mul", "eigen_quat_mul", 0.0, 0.0},
    {"ga_transform_1M", "eigen_quat_transform_1M", 1.5, 0.0},
    {"eigen_isometry_transform_1M", "eigen_quat_transform_1M", 0.0, 0.0},
    {"ga_sandwich_point_1M", "eigen_quat_transform_1M", 0.0, 0.0},
    {"ga_exp", "eigen_angleaxis_to_quat", 0.0, 0.0},
    {"ga_log", "eigen_quat_to_angleaxis", 0.0, 0.0},
    {"ga_blend4_log", "ga_blend4_linear", 3.0, 0.0},
    {"ga_blend4_pivotlog", "ga_blend4_linear", 0.0, 0.0},
    {"ga_blend4_linear", "eigen_dlb4", 0.0, 0.0},
    {"ga_blend4_shared_logs", "ga_blend4_linear", 0.0, 0.0},
};

class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    std::vector<Run> copy = runs;
    for (Run& r : copy) {
      const auto it = r.counters.find("ops");
      if (it == r.counters.end() || r.error_occurred) continue;
      const double ns = r.GetAdjustedCPUTime() * to_ns(r.time_unit) / it->second.value;
      const std::string name = r.benchmark_name();
      ns_[name] = ns;
      r.counters["ns/op"] = ns;
      for (const Target& t : kTargets)
        if (name == t.subject && ns_.count(t.baseline)) r.counters["x_base"] = ns / ns_[t.baseline];
    }
    ConsoleReporter::ReportRuns(copy);
  }
  void Summary() const {
    std::printf("\n%-30s %10s   %-28s %10s %8s   %s\n", "subject", "ns/op", "baseline", "ns/op", "ratio",
                "target");
    for (const Target& t : kTargets) {
      if (!ns_.count(t.subject) || !ns_.count(t.baseline)) continue;
      const double a = ns_.at(t.subject), b = ns_.at(t.baseline);
      std::string target = "-";
      if (t.max_ratio > 0)
        target = "ratio <= " + std::to_string(t.max_ratio).substr(0, 3) +
                 (a / b <= t.max_ratio ? "  met" : "  MISSED");
      if (t.max_ns > 0)
        target = "<= " + std::to_string(static_cast<int>(t.max_ns)) + " ns" +
                 (a <= t.max_ns ? "  met" : "  MISSED");
      std::printf("%-30s %10.2f   %-28s %10.2f %8.2f   %s\n", t.subject, a, t.baseline, b, a / b,
                  target.c_str());
    }
  }

 private:
  static double to_ns(benchmark::TimeUnit u) {
    switch (u) {
      case benchmark::kNanosecond:
        return 1.0;
      case benchmark::kMicrosecond:
        return 1e3;
      case benchmark::kMillisecond:
        return 1e6;
      default:
        return 1e9;
    }
  }
  std::map<std::string, double> ns_;
};

}  // namespace

// Baselines are registered before their subjects so that the ratio is known when the subject reports.
BENCHMARK(eigen_quat_mul);
BENCHMARK(eigen_dualquat_mul);
BENCHMARK(ga_mot_mul);
BENCHMARK(eigen_quat_transform_1M)->Unit(benchmark::kMillisecond);
BENCHMARK(eigen_isometry_transform_1M)->Unit(benchmark::kMillisecond);
BENCHMARK(ga_transform_1M)->Unit(benchmark::kMillisecond);
BENCHMARK(ga_sandwich_point_1M)->Unit(benchmark::kMillisecond);
BENCHMARK(eigen_angleaxis_to_quat)->Unit(benchmark::kMicrosecond);
BENCHMARK(ga_exp)->Unit(benchmark::kMicrosecond);
BENCHMARK(eigen_quat_to_angleaxis)->Unit(benchmark::kMicrosecond);
BENCHMARK(ga_log)->Unit(benchmark::kMicrosecond);
BENCHMARK(eigen_dlb4)->Unit(benchmark::kMicrosecond);
BENCHMARK(ga_blend4_linear)->Unit(benchmark::kMicrosecond);
BENCHMARK(ga_blend4_log)->Unit(benchmark::kMicrosecond);
BENCHMARK(ga_blend4_pivotlog)->Unit(benchmark::kMicrosecond);
BENCHMARK(ga_blend4_shared_logs)->Unit(benchmark::kMicrosecond);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.Summary();
  benchmark::Shutdown();
  return 0;
}

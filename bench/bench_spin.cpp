// bench_spin: spin transformations (Crane, Pinkall & Schröder 2011) end to end — bind (validation,
// geometry, ordering, symbolic analysis, Poisson factor) + solve(ρ) (assembly, numeric factorization,
// inverse iterations, Poisson) — on the four meshes of the issue, each with a baseline measured in the
// same run:
//
//   bumpy      SpinXForm's sphere.obj (4,002 vertices, 8,000 faces) + bumpy.tga (image mode)
//   capsule    capsule(0.5, 2, 70, 200): 14,002 vertices, 28,000 faces, centred, max |v| = 1, bumpy.tga
//   nefertiti  nefertiti.obj (49,971 vertices, 99,938 faces), centred, max |v| = 1, no UVs:
//              ρ = 3 sin(6x) sin(6y) sin(6z) per face barycentre
//   sphere400k uv_sphere(316, 632): 199,714 vertices, 399,424 faces, bumpy.tga
//
// Configurations (rows spin/<config>/<mesh>):
//   base_spinxform   the reference code's settings in our pipeline: unweighted A*A, exactly 3 inverse
//                    iterations, real 4n×4n matrix ordered by CHOLMOD's AMD on the full matrix,
//                    supernodal — the baseline every speedup counter refers to
//   ours_spinxform   the same iterations and result with our solver: complex 2n×2n Hermitian form,
//                    METIS on the vertex graph
//   ours             the default: eq. 7, Krylov-accelerated inverse iteration to residual 1e-10
//   study rows       what each choice gives (bumpy and capsule; larger meshes with SPINMOTOR_BENCH_FULL=1):
//                    real_vertex (real form, vertex ordering), amd (vertex AMD instead of METIS),
//                    simplicial (CHOLMOD simplicial), plain_iteration (no Rayleigh–Ritz),
//                    one_thread (OpenMP off for our loops and Eigen)
// Counters: bind_ms, assembly_ms, factor_ms, eigen_ms, poisson_ms, total_ms (= bind + solve, the wall
// time of a one-shot run without file I/O), poisson_setup_ms (Laplacian + factor on the bind's second
// thread, overlapped, not in total_ms), iterations, residual, q_mean, factor_nnz (millions; complex
// entries for the complex form), speedup (base_spinxform total / this total).
// SPINMOTOR_BENCH_QUICK=1 keeps the bumpy sphere only.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/curvature_change.hpp"
#include "spinmotor/spin/spin_transform.hpp"

using namespace spinmotor;

namespace {

const std::string kMeshes = SPINMOTOR_MESHES_DIR;

struct Case {
  Mesh mesh;
  Eigen::VectorXd rho;
};

void normalize_unit(Mesh& m) {
  m.V.rowwise() -= m.V.colwise().mean();
  m.V /= m.V.rowwise().norm().maxCoeff();
}

const Case& get_case(const std::string& name) {
  static std::map<std::string, Case> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  static const GrayscaleImage bumpy = read_grayscale_image(kMeshes + "/spinxform/bumpy.tga");
  Case c;
  if (name == "bumpy") {
    c.mesh = read_mesh(kMeshes + "/spinxform/sphere.obj");
  } else if (name == "capsule") {
    c.mesh = capsule(0.5, 2.0, 70, 200);
  } else if (name == "nefertiti") {
    c.mesh = read_mesh(kMeshes + "/nefertiti.obj");
  } else {
    c.mesh = uv_sphere(316, 632);
  }
  normalize_unit(c.mesh);
  if (c.mesh.has_uv())
    c.rho = face_rho_from_image(c.mesh, bumpy, 5.0);
  else
    c.rho = face_rho_from_function(c.mesh.V, c.mesh.F, [](const Eigen::Vector3d& p) {
      return 3.0 * std::sin(6 * p.x()) * std::sin(6 * p.y()) * std::sin(6 * p.z());
    });
  return cache.emplace(name, std::move(c)).first->second;
}

std::map<std::string, double>& base_total() {
  static std::map<std::string, double> t;
  return t;
}

struct Config {
  std::string name;
  std::function<SpinTransformOptions()> options;
  bool one_thread = false;
};

SpinTransformOptions spinxform_base() {
  SpinTransformOptions o = SpinTransformOptions::spinxform();
  o.complex_form = false;
  o.order_full_matrix = true;
  o.ordering = Ordering::AMD;
  return o;
}

void run(benchmark::State& state, const std::string& mesh_name, const Config& cfg) {
  const Case& c = get_case(mesh_name);
  const SpinTransformOptions o = cfg.options();
  const int threads = omp_get_max_threads();
  if (cfg.one_thread) omp_set_num_threads(1);
  SpinTransformResult r;
  double factor_nnz = 0;
  SpinTimings sum;
  int runs = 0;
  for (auto _ : state) {
    SpinTransform st(c.mesh, o);
    r = st.solve(c.rho);
    factor_nnz = st.factor_nonzeros();
    sum.bind += r.timings.bind;
    sum.assembly += r.timings.assembly;
    sum.factor += r.timings.factor;
    sum.eigen += r.timings.eigen;
    sum.poisson += r.timings.poisson;
    sum.poisson_setup += r.timings.poisson_setup;
    ++runs;
  }
  if (cfg.one_thread) omp_set_num_threads(threads);
  const double total = (sum.bind + sum.solve_total()) / runs;
  state.counters["bind_ms"] = sum.bind / runs;
  state.counters["assembly_ms"] = sum.assembly / runs;
  state.counters["factor_ms"] = sum.factor / runs;
  state.counters["eigen_ms"] = sum.eigen / runs;
  state.counters["poisson_ms"] = sum.poisson / runs;
  state.counters["poisson_setup_ms"] = sum.poisson_setup / runs;
  state.counters["total_ms"] = total;
  state.counters["iterations"] = r.iterations;
  state.counters["residual"] = r.residual;
  state.counters["factor_nnz_M"] = factor_nnz / 1e6;
  state.counters["q_mean"] = quasi_conformal_summary(c.mesh.V, c.mesh.F, r.V).q_mean;
  state.counters["vertices"] = static_cast<double>(c.mesh.V.rows());
  state.counters["faces"] = static_cast<double>(c.mesh.F.rows());
  if (cfg.name == "base_spinxform") base_total()[mesh_name] = total;
  const auto b = base_total().find(mesh_name);
  if (b != base_total().end()) state.counters["speedup"] = b->second / total;
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = std::getenv("SPINMOTOR_BENCH_QUICK") != nullptr;
  const bool full = std::getenv("SPINMOTOR_BENCH_FULL") != nullptr;
  const std::vector<Config> main_rows = {
      {"base_spinxform", spinxform_base},
      {"ours_spinxform", [] { return SpinTransformOptions::spinxform(); }},
      {"ours", [] { return SpinTransformOptions{}; }},
  };
  const std::vector<Config> study_rows = {
      {"real_vertex",
       [] {
         SpinTransformOptions o;
         o.complex_form = false;
         return o;
       }},
      {"amd",
       [] {
         SpinTransformOptions o;
         o.ordering = Ordering::AMD;
         return o;
       }},
      {"simplicial",
       [] {
         SpinTransformOptions o;
         o.supernodal = false;
         return o;
       }},
      {"plain_iteration",
       [] {
         SpinTransformOptions o;
         o.krylov = false;
         o.iterations = 500;
         return o;
       }},
      {"one_thread", [] { return SpinTransformOptions{}; }, true},
  };
  struct M {
    const char* name;
    int iters;
    bool study;
  };
  std::vector<M> meshes = {{"bumpy", 5, true}, {"capsule", 3, true}};
  if (!quick) meshes.push_back({"nefertiti", 1, full}), meshes.push_back({"sphere400k", 1, full});
  for (const M& m : meshes) {
    for (const Config& c : main_rows) {
      if (c.name == "base_spinxform" && std::string(m.name) == "sphere400k" && !full) continue;
      benchmark::RegisterBenchmark(("spin/" + c.name + "/" + m.name).c_str(),
                                   [m, c](benchmark::State& s) { run(s, m.name, c); })
          ->Iterations(m.iters)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
    if (m.study)
      for (const Config& c : study_rows)
        benchmark::RegisterBenchmark(("spin/" + c.name + "/" + m.name).c_str(),
                                     [m, c](benchmark::State& s) { run(s, m.name, c); })
            ->Iterations(m.iters)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

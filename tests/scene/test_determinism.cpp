// Determinism (issue 19): the same input gives bit-identical outputs across runs, and one or two
// OpenMP threads give results that agree to 1e-12 of the bounding-box diagonal, for the three
// solvers whose loops run in parallel: the spin transformation, the conformal snap and ARAP.
//
// The meshes are large enough that every parallel loop they reach actually forks (core/parallel.hpp:
// 20,480 faces ≥ kAssembly, 10,242 vertices ≥ kMotorBlend and kRotationFit); on smaller meshes the
// loops run serially and the comparison would be empty. Between thread counts only the order of the
// reductions (energies, norms) changes, so agreement to rounding is what is expected, not equality.
#include <omp.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <functional>

#include "spinmotor/core/parallel.hpp"
#include "spinmotor/deform/arap.hpp"
#include "spinmotor/ga/constructors.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/spin/spin_transform.hpp"

namespace test_determinism {

using namespace spinmotor;

namespace {

double diagonal(const Eigen::MatrixXd& V) { return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm(); }

/// Runs `f` with `threads` OpenMP threads and restores the previous count.
Eigen::MatrixXd with_threads(int threads, const std::function<Eigen::MatrixXd()>& f) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  Eigen::MatrixXd V = f();
  omp_set_num_threads(before);
  return V;
}

/// Twice with two threads (must be bit-identical), once with one (must agree to 1e-12 of the
/// diagonal). Prints the measured difference.
void check_deterministic(const char* what, const std::function<Eigen::MatrixXd()>& f) {
  const Eigen::MatrixXd a = with_threads(2, f), b = with_threads(2, f), c = with_threads(1, f);
  REQUIRE(a.allFinite());
  CHECK(a == b);
  const double d = (a - c).cwiseAbs().maxCoeff() / diagonal(a);
  std::printf("%s: 2 threads twice bit-identical: %s; 1 vs 2 threads: %.3g of the diagonal\n", what,
              a == b ? "yes" : "NO", d);
  CHECK(d <= 1e-12);
}

/// Smooth ρ on the faces (a bump and a twist of the curvature), the input of a spin transformation.
Eigen::VectorXd smooth_rho(const Mesh& m) {
  Eigen::VectorXd rho(m.F.rows());
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d b = (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))).transpose() / 3;
    rho[f] = 2.0 * std::sin(2 * b.x() + 0.5) * std::cos(1.5 * b.y()) + b.z() * b.z();
  }
  return rho;
}

}  // namespace

TEST_CASE("determinism: spin transformation and conformal snap, 1 vs 2 threads and run to run",
          "[determinism][spin]") {
  REQUIRE(omp_get_num_procs() >= 1);
  const Mesh m = icosphere(5);  // 10,242 vertices, 20,480 faces
  REQUIRE(parallel::worth(m.F.rows(), parallel::kAssembly));
  const Eigen::VectorXd rho = smooth_rho(m);
  check_deterministic("spin transformation", [&] { return spin_transform(m, rho).V; });
  // The snap of a non-conformal edit: a shear and a bend of the sphere.
  Eigen::MatrixXd edit = m.V;
  for (Eigen::Index i = 0; i < edit.rows(); ++i) {
    edit(i, 0) += 0.4 * m.V(i, 1) + 0.2 * m.V(i, 2) * m.V(i, 2);
    edit(i, 2) *= 1.3;
  }
  check_deterministic("conformal snap", [&] { return conformal_snap(m, edit).V; });
}

TEST_CASE("determinism: ARAP, 1 vs 2 threads and run to run", "[determinism][arap]") {
  const Mesh m = tube(0.5, 3.0, 80, 128);  // 10,240 vertices
  REQUIRE(parallel::worth(m.V.rows(), parallel::kRotationFit));
  const double z1 = m.V.col(2).maxCoeff();
  std::vector<int> bottom, top;
  for (int i = 0; i < m.V.rows(); ++i) {
    if (m.V(i, 2) < 0.05 * z1) bottom.push_back(i);
    if (m.V(i, 2) > 0.95 * z1) top.push_back(i);
  }
  const std::vector<Handle> hs = {
      {"bottom", Eigen::Map<Eigen::VectorXi>(bottom.data(), static_cast<Eigen::Index>(bottom.size()))},
      {"top", Eigen::Map<Eigen::VectorXi>(top.data(), static_cast<Eigen::Index>(top.size()))}};
  // The top turned 80° about x and moved sideways: a bend that takes many iterations.
  const std::vector<ga::Mot> motors = {
      ga::Mot(1, 0, 0, 0, 0, 0, 0, 0),
      ga::motor(ga::rotor(Eigen::Vector3d(1, 0, 0), 80 * M_PI / 180), ga::translator({1.0, 0.0, -0.8}))};
  ArapDeformer::Options o;
  o.iterations = 20;
  o.tolerance = 0.0;  // a fixed number of steps in every run
  check_deterministic("ARAP, 20 iterations", [&] {
    ArapDeformer d = ArapDeformer::bind(m, hs, o);
    Eigen::MatrixXd V;
    d.pose(motors, V);
    return V;
  });
}

}  // namespace test_determinism

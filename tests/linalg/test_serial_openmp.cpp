// SerialOpenMPScope (linalg/serial_openmp.hpp): inside it a parallel region that would run on one
// thread is a plain call on the calling thread (counted), with a worksharing loop over the whole range
// and its reduction right; outside it, and on other threads meanwhile, regions keep their teams; a
// CHOLMOD factorization runs its regions that way and stays right.
#include <omp.h>

#include <Eigen/Sparse>
#include <atomic>
#include <catch2/catch.hpp>
#include <thread>
#include <vector>

#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/linalg/serial_openmp.hpp"

namespace test_serial_openmp {

using namespace spinmotor;

namespace {

struct Region {
  int threads = 0;     // omp_get_num_threads() seen inside
  bool caller = true;  // the region's body ran on the calling thread alone
  long long sum = 0;   // Σ i over [1, 1000] by a dynamic-schedule reduction
};

Region run_region(int requested) {
  Region r;
  const std::thread::id me = std::this_thread::get_id();
  std::atomic<bool> caller{true};
  long long sum = 0;
#pragma omp parallel num_threads(requested) reduction(+ : sum)
  {
    if (std::this_thread::get_id() != me) caller = false;  // every thread of a team runs the body
#pragma omp single
    r.threads = omp_get_num_threads();
#pragma omp for schedule(dynamic, 7)
    for (int i = 1; i <= 1000; ++i) sum += i;
  }
  r.sum = sum;
  r.caller = caller.load();
  return r;
}

// The 5-point Laplacian of a k×k grid plus the identity (lower triangle).
Eigen::SparseMatrix<double> grid_matrix(int k) {
  std::vector<Eigen::Triplet<double>> t;
  for (int y = 0; y < k; ++y)
    for (int x = 0; x < k; ++x) {
      const int i = y * k + x;
      t.emplace_back(i, i, 5.0);
      if (x + 1 < k) t.emplace_back(i + 1, i, -1.0);
      if (y + 1 < k) t.emplace_back(i + k, i, -1.0);
    }
  Eigen::SparseMatrix<double> A(k * k, k * k);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

}  // namespace

TEST_CASE("serial OpenMP: inside the scope a region is a plain call, outside it keeps its team",
          "[solvers]") {
  const int team = std::min(2, omp_get_thread_limit());
  const Region outside = run_region(2);
  CHECK(outside.threads == team);
  CHECK(outside.sum == 500500);
  CHECK(outside.caller == (team == 1));

  const std::uint64_t before = serial_openmp_direct_regions();
  {
    const SerialOpenMPScope scope;
    const Region inside = run_region(2);
    CHECK(inside.threads == 1);
    CHECK(inside.caller);
    CHECK(inside.sum == 500500);
    CHECK(serial_openmp_direct_regions() == before + 1);

    // another thread meanwhile: its regions keep their teams (the scope is this thread's)
    Region other;
    std::thread t([&] { other = run_region(2); });
    t.join();
    CHECK(other.threads == team);
    CHECK(other.sum == 500500);
    CHECK(serial_openmp_direct_regions() == before + 1);
    {
      const SerialOpenMPScope nested;
      CHECK(run_region(2).sum == 500500);
    }
    CHECK(serial_openmp_direct_regions() == before + 2);
  }
  // after the scope, regions have their teams again and are no longer counted
  CHECK(run_region(2).threads == team);
  CHECK(serial_openmp_direct_regions() == before + 2);
}

TEST_CASE("serial OpenMP: a supernodal CHOLMOD factorization runs its regions as plain calls", "[solvers]") {
  const Eigen::SparseMatrix<double> A = grid_matrix(100);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  const std::uint64_t before = serial_openmp_direct_regions();
  CholeskySolver s({.ordering = Ordering::METIS, .supernodal = true});
  s.compute(A);
  const std::uint64_t regions = serial_openmp_direct_regions() - before;
  INFO("CHOLMOD regions run as plain calls: " << regions);
  CHECK(regions > 100);  // SuiteSparse 5 opens several per supernode
  const Eigen::VectorXd x = s.solve(b);
  CHECK((A.selfadjointView<Eigen::Lower>() * x - b).norm() / b.norm() < 1e-14);
}

}  // namespace test_serial_openmp

// Stop signals around the orderings (linalg/src/ordering_scope.hpp): METIS installs its own SIGTERM
// handler while it orders and puts the previous one back with System V semantics (one-shot, no
// SA_RESTART). After every ordering the handlers are exactly as before, and a SIGTERM sent to the
// process while METIS runs reaches the project's handler once the ordering is over instead of being
// turned into a failed ordering.
#include <signal.h>
#include <unistd.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <numeric>
#include <thread>
#include <vector>

#include "spinmotor/core/interrupt.hpp"
#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/linalg/graph_ordering.hpp"

namespace test_ordering_signals {

using namespace spinmotor;

namespace {

constexpr int kStop[] = {SIGINT, SIGTERM, SIGHUP};

/// The 5-point Laplacian of a g×g grid plus the identity (SPD), both triangles stored.
Eigen::SparseMatrix<double> grid_matrix(int g) {
  std::vector<Eigen::Triplet<double>> t;
  const auto id = [g](int x, int y) { return y * g + x; };
  for (int y = 0; y < g; ++y)
    for (int x = 0; x < g; ++x) {
      t.emplace_back(id(x, y), id(x, y), 5.0);
      if (x + 1 < g)
        t.emplace_back(id(x, y), id(x + 1, y), -1.0), t.emplace_back(id(x + 1, y), id(x, y), -1.0);
      if (y + 1 < g)
        t.emplace_back(id(x, y), id(x, y + 1), -1.0), t.emplace_back(id(x, y + 1), id(x, y), -1.0);
    }
  Eigen::SparseMatrix<double> A(g * g, g * g);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

struct Handlers {
  struct sigaction sa[3];
};

Handlers current() {
  Handlers h;
  for (int i = 0; i < 3; ++i) sigaction(kStop[i], nullptr, &h.sa[i]);
  return h;
}

bool same(const Handlers& a, const Handlers& b) {
  for (int i = 0; i < 3; ++i)
    if (a.sa[i].sa_handler != b.sa[i].sa_handler || a.sa[i].sa_flags != b.sa[i].sa_flags) return false;
  return true;
}

/// METIS's order of the grid's graph, through graph_ordering.
Eigen::VectorXi metis_order(Eigen::SparseMatrix<double>& A) {
  const auto n = A.rows();
  return graph_ordering(n, {A.outerIndexPtr(), static_cast<std::size_t>(n) + 1},
                        {A.innerIndexPtr(), static_cast<std::size_t>(A.nonZeros())}, Ordering::METIS, "test");
}

bool is_permutation(const Eigen::VectorXi& p) {
  std::vector<int> v(p.begin(), p.end());
  std::sort(v.begin(), v.end());
  for (std::size_t i = 0; i < v.size(); ++i)
    if (v[i] != static_cast<int>(i)) return false;
  return true;
}

}  // namespace

TEST_CASE("orderings leave the stop signals' handlers exactly as they were, METIS's too",
          "[solvers][interrupt]") {
  Eigen::SparseMatrix<double> A = grid_matrix(40);
  const InterruptGuard guard;  // the recording handler, SA_RESTART
  const Handlers before = current();
  REQUIRE((before.sa[1].sa_flags & SA_RESTART) != 0);
  for (const Ordering o : {Ordering::METIS, Ordering::NESDIS, Ordering::AMD, Ordering::Auto}) {
    CholeskySolver s({.ordering = o, .try_natural = true});
    s.compute(A);
    CHECK(same(current(), before));
  }
  CHECK(is_permutation(metis_order(A)));
  CHECK(same(current(), before));  // not one-shot: a second SIGTERM would otherwise end the process
  sigset_t mask;
  pthread_sigmask(SIG_BLOCK, nullptr, &mask);
  for (const int sig : kStop) CHECK(sigismember(&mask, sig) == 0);
  CHECK(interrupted() == 0);
}

TEST_CASE("a SIGTERM sent while METIS orders reaches the project's handler after it, the order is whole",
          "[solvers][interrupt]") {
  Eigen::SparseMatrix<double> A = grid_matrix(250);  // METIS: a few hundred ms
  metis_order(A);                                    // the OpenMP team and OpenBLAS as the run has them
  const InterruptGuard guard;
  std::atomic<bool> ordering{false}, sent{false};
  std::thread sender([&] {
    block_stop_signals_on_this_thread();  // the application's other threads: only the caller takes them
    while (!ordering.load()) std::this_thread::yield();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ::kill(::getpid(), SIGTERM);  // to the process, as from a scheduler
    sent = true;
  });
  ordering = true;
  const Eigen::VectorXi p = metis_order(A);  // METIS returns an error if its handler takes the signal
  const bool during = sent.load();
  sender.join();
  REQUIRE(during);  // the signal came while METIS ran
  CHECK(is_permutation(p));
  CHECK(interrupted() == SIGTERM);  // delivered when the ordering ended
}

}  // namespace test_ordering_signals

// The one CHOLMOD wrapper (linalg/cholesky_solver.hpp) for real symmetric and complex Hermitian
// matrices: agreement with dense factorizations, the partial solves (P, L, Lᴴ, Pᵀ) that Spectra's
// Cholesky mode uses, and the one singularity rule (smallest pivot ≤ 1000·ε·max diagonal) on matrices
// whose pivots are known in closed form; the BLAS thread policy (blas_threads.hpp) under concurrent
// factorizations, and CHOLMOD's OpenMP regions as plain calls (serial_openmp.hpp).
#include <dlfcn.h>
#include <omp.h>
#include <sys/resource.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <complex>
#include <fstream>
#include <map>
#include <numeric>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <type_traits>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/memory_budget.hpp"
#include "spinmotor/linalg/blas_threads.hpp"
#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/linalg/geometric_ordering.hpp"
#include "spinmotor/linalg/serial_openmp.hpp"
#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/mass_matrix.hpp"

namespace test_cholesky {

using namespace spinmotor;
using cd = std::complex<double>;

namespace {

// The tridiagonal A = L D Lᴴ with L unit lower bidiagonal (subdiagonal −e^{iθk}) and D = diag(1, …, 1,
// δ): a path-graph Laplacian whose first vertex is grounded and whose last diagonal is 1 + δ instead
// of 2. Its pivots in the natural order are exactly 1, …, 1, δ; its largest diagonal entry is 2.
template <class Scalar>
Eigen::SparseMatrix<Scalar> path_matrix(int n, double delta) {
  std::vector<Eigen::Triplet<Scalar>> t;
  for (int k = 0; k < n; ++k) {
    t.emplace_back(k, k, Scalar(k == 0 ? 1.0 : k == n - 1 ? 1.0 + delta : 2.0));
    if (k + 1 < n) {
      Scalar off(-1.0);
      if constexpr (!std::is_same_v<Scalar, double>) off = -std::polar(1.0, 0.7 * k);
      t.emplace_back(k + 1, k, off);  // lower triangle only
    }
  }
  Eigen::SparseMatrix<Scalar> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

// Lower triangle of a Hermitian positive definite matrix: the magnetic Laplacian of an icosphere
// (off-diagonal −w_ij e^{iθ_ij}, PSD for any phases) plus a mass shift, and its dense full form.
Eigen::SparseMatrix<cd> magnetic_laplacian(const Mesh& s, double shift, Eigen::MatrixXcd& dense) {
  const Eigen::SparseMatrix<double> A =
      Eigen::SparseMatrix<double>(cotangent_laplacian(s.V, s.F) + shift * mass_matrix(s.V, s.F));
  std::vector<Eigen::Triplet<cd>> t;
  for (int j = 0; j < A.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it)
      if (it.row() > j)
        t.emplace_back(static_cast<int>(it.row()), j, it.value() * std::polar(1.0, 0.3 * (it.row() - j)));
      else if (it.row() == j)
        t.emplace_back(j, j, it.value());
  Eigen::SparseMatrix<cd> H(A.rows(), A.cols());
  H.setFromTriplets(t.begin(), t.end());
  H.makeCompressed();
  const Eigen::MatrixXcd Lo = Eigen::MatrixXcd(H);
  dense = Lo + Lo.adjoint();
  dense.diagonal() = Lo.diagonal();
  return H;
}

template <class Scalar>
void check_singularity_rule() {
  using Solver = BasicCholeskySolver<Scalar>;
  for (auto ordering : {Ordering::Natural, Ordering::AMD})
    for (bool super : {true, false}) {
      INFO("supernodal " << super << ", ordering " << static_cast<int>(ordering));
      Solver accepted({ordering, super});
      // δ = 1e-11 > 1000·ε·2 = 4.4e-13: accepted, and the solve is right.
      const Eigen::SparseMatrix<Scalar> A = path_matrix<Scalar>(40, 1e-11);
      REQUIRE_NOTHROW(accepted.compute(A));
      const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> B =
          Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>::Ones(40, 2);
      const auto X = accepted.solve(B);
      // Backward stable: residual ≲ n·ε·‖A‖·‖X‖ although cond(A) ~ 1e13.
      const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> AX =
          A.template selfadjointView<Eigen::Lower>() * X;
      CHECK((AX - B).cwiseAbs().maxCoeff() < 1e-12 * X.cwiseAbs().maxCoeff());
      // δ = 1e-14 < 4.4e-13: rejected as numerically singular.
      Solver rejected({ordering, super});
      try {
        rejected.compute(path_matrix<Scalar>(40, 1e-14));
        FAIL("δ = 1e-14 was accepted");
      } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Numerical);
        CHECK_THAT(std::string(e.what()), Catch::Contains("CholeskySolver") &&
                                              Catch::Contains("numerically singular") &&
                                              Catch::Contains("smallest pivot"));
      }
      CHECK_FALSE(rejected.factorized());
    }
}

}  // namespace

TEST_CASE("Cholesky: pivots 1,…,1,δ are accepted for δ = 1e-11 and rejected for δ = 1e-14 (real)",
          "[solvers]") {
  check_singularity_rule<double>();
}

TEST_CASE("Cholesky: pivots 1,…,1,δ are accepted for δ = 1e-11 and rejected for δ = 1e-14 (complex)",
          "[solvers]") {
  check_singularity_rule<cd>();
}

TEST_CASE("Cholesky: complex Hermitian solves agree with a dense LLᴴ, for every ordering and both factors",
          "[solvers]") {
  const Mesh s = icosphere(2);
  Eigen::MatrixXcd dense;
  const Eigen::SparseMatrix<cd> H = magnetic_laplacian(s, 0.5, dense);
  const Eigen::Index n = H.rows();
  Eigen::MatrixXcd B(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) B.row(i) << cd(s.V(i, 0), s.V(i, 1)), cd(1.0, 0.0), cd(0.0, s.V(i, 2));
  const Eigen::MatrixXcd Xref = dense.llt().solve(B);
  // The same matrix stored in full (the strict upper triangle the conjugate of the lower one): read
  // from its upper triangle under a permuting ordering, and it must give the same solution.
  Eigen::SparseMatrix<cd> Hfull = Eigen::SparseMatrix<cd>(H.adjoint());
  Hfull += Eigen::SparseMatrix<cd>(H.triangularView<Eigen::StrictlyLower>());
  Hfull.makeCompressed();
  REQUIRE((Eigen::MatrixXcd(Hfull) - dense).cwiseAbs().maxCoeff() == 0.0);
  for (auto ordering : {Ordering::Auto, Ordering::Natural, Ordering::AMD, Ordering::METIS, Ordering::NESDIS})
    for (bool super : {true, false})
      for (const Eigen::SparseMatrix<cd>* A : {&H, static_cast<const Eigen::SparseMatrix<cd>*>(&Hfull)}) {
        INFO("supernodal " << super << ", ordering " << static_cast<int>(ordering) << ", stored in full "
                           << (A == &Hfull));
        ComplexCholeskySolver c({ordering, super});
        c.compute(*A);
        const Eigen::MatrixXcd X = c.solve(B);
        CHECK((X - Xref).cwiseAbs().maxCoeff() < 1e-11 * Xref.cwiseAbs().maxCoeff());
        // One column at a time equals the block.
        for (int k = 0; k < 3; ++k)
          CHECK((c.solve(B.col(k)) - X.col(k)).cwiseAbs().maxCoeff() <
                1e-13 * X.col(k).cwiseAbs().maxCoeff());
      }
}

TEST_CASE("Cholesky: the partial solves compose to A⁻¹ and L⁻¹P is a square root (real and complex)",
          "[solvers]") {
  const Mesh s = icosphere(2);
  Eigen::MatrixXcd dense;
  const Eigen::SparseMatrix<cd> H = magnetic_laplacian(s, 0.5, dense);
  const Eigen::SparseMatrix<double> A =
      Eigen::SparseMatrix<double>(cotangent_laplacian(s.V, s.F) + 0.5 * mass_matrix(s.V, s.F));
  const Eigen::MatrixXd Ad = Eigen::MatrixXd(A);
  const Eigen::Index n = A.rows();
  Eigen::MatrixXd B(n, 2);
  B << s.V.col(0), Eigen::VectorXd::Ones(n);
  const Eigen::MatrixXcd Bc = B.cast<cd>() + cd(0, 1) * Eigen::MatrixXd(s.V.leftCols(2)).cast<cd>();
  for (auto ordering : {Ordering::Natural, Ordering::AMD})
    for (bool super : {true, false}) {
      INFO("supernodal " << super << ", ordering " << static_cast<int>(ordering));
      {
        CholeskySolver c({ordering, super});
        using S = CholeskySolver::System;
        c.compute(A);
        const Eigen::MatrixXd Y = c.solve(c.solve(B, S::P), S::L);  // L⁻¹ P B
        const Eigen::MatrixXd X = c.solve(c.solve(Y, S::Lt), S::Pt);
        CHECK((Ad * X - B).cwiseAbs().maxCoeff() < 1e-10);
        // (L⁻¹PB)ᵀ(L⁻¹PB) = Bᵀ A⁻¹ B.
        const Eigen::MatrixXd G = B.transpose() * c.solve(B);
        CHECK((Y.transpose() * Y - G).cwiseAbs().maxCoeff() < 1e-10 * G.cwiseAbs().maxCoeff());
      }
      {
        ComplexCholeskySolver c({ordering, super});
        using S = ComplexCholeskySolver::System;
        c.compute(H);
        const Eigen::MatrixXcd Y = c.solve(c.solve(Bc, S::P), S::L);
        const Eigen::MatrixXcd X = c.solve(c.solve(Y, S::Lt), S::Pt);
        CHECK((dense * X - Bc).cwiseAbs().maxCoeff() < 1e-10);
        const Eigen::MatrixXcd G = Bc.adjoint() * c.solve(Bc);
        CHECK((Y.adjoint() * Y - G).cwiseAbs().maxCoeff() < 1e-10 * G.cwiseAbs().maxCoeff());
      }
    }
}

TEST_CASE("Cholesky: complex misuse and indefinite matrices are reported", "[solvers]") {
  ComplexCholeskySolver c;
  CHECK_THROWS_WITH(c.solve(Eigen::MatrixXcd::Ones(3, 1)), Catch::Contains("before a successful factorize"));
  Eigen::SparseMatrix<cd> I(3, 3);
  I.setIdentity();
  I.makeCompressed();
  c.compute(I);
  CHECK_THROWS_WITH(c.solve(Eigen::MatrixXcd::Ones(2, 1)), Catch::Contains("right-hand side has 2 rows"));
  Eigen::SparseMatrix<cd> N = I;
  N.coeffRef(1, 1) = -1.0;
  for (bool super : {true, false}) {
    ComplexCholeskySolver d({Ordering::Natural, super});
    CHECK_THROWS_WITH(d.compute(N), Catch::Contains("not positive definite"));
  }
  N.coeffRef(1, 1) = cd(std::nan(""), 0.0);
  CHECK_THROWS_WITH(c.factorize(N), Catch::Contains("not finite"));
}

TEST_CASE("Cholesky: a factor over the memory limit is refused after the symbolic analysis, naming its size",
          "[solvers][memory]") {
  struct Reset {
    ~Reset() { set_memory_limit(0); }
  } reset;
  const Mesh s = icosphere(4);  // 2,562 vertices
  const Eigen::SparseMatrix<double> A =
      Eigen::SparseMatrix<double>(cotangent_laplacian(s.V, s.F) + 0.5 * mass_matrix(s.V, s.F));
  CholeskySolver fits;
  fits.compute(A);
  // The estimate: a value and an index per factor nonzero, 64 bytes per column.
  const double bytes = fits.factor_nonzeros() * 16 + 64.0 * A.rows();
  set_memory_limit(static_cast<std::uint64_t>(bytes) + 1);
  CholeskySolver just;
  CHECK_NOTHROW(just.compute(A));
  set_memory_limit(static_cast<std::uint64_t>(bytes / 2));
  CholeskySolver over;
  try {
    over.compute(A);
    FAIL("no refusal");
  } catch (const Error& e) {
    const std::string m = e.what();
    INFO(m);
    CHECK(e.kind() == Error::Kind::BadInput);
    CHECK(m.find("the Cholesky factor of a 2562x2562 matrix (") != std::string::npos);
    CHECK(m.find("needs an estimated " + format_bytes(static_cast<std::uint64_t>(bytes))) !=
          std::string::npos);
    CHECK(m.find("the limit is " + format_bytes(static_cast<std::uint64_t>(bytes / 2))) != std::string::npos);
  }
  // Nothing is left half-analyzed: solving is refused, and a new compute() under the default works.
  CHECK_THROWS_AS(over.solve(Eigen::VectorXd::Ones(A.rows())), Error);
  set_memory_limit(0);
  CHECK_NOTHROW(over.compute(A));
}

TEST_CASE("geometric_nested_dissection: a permutation of the free unknowns with less fill than row order",
          "[solvers][ordering]") {
  // The 5-point Laplacian (+ I) of a 64×64 grid; the first grid row is excluded (constrained). Row-major
  // order is a band of width 64: nnz(L) ≈ 64 n. Nested dissection of a 2D grid gives O(n log n).
  constexpr int k = 64, n = k * k;
  Eigen::MatrixXd P(n, 3);
  std::vector<Eigen::Triplet<double>> t;
  for (int y = 0; y < k; ++y)
    for (int x = 0; x < k; ++x) {
      const int i = y * k + x;
      P.row(i) << x, y, 0.0;
      t.emplace_back(i, i, 5.0);
      if (x + 1 < k) t.emplace_back(i, i + 1, -1.0), t.emplace_back(i + 1, i, -1.0);
      if (y + 1 < k) t.emplace_back(i, i + k, -1.0), t.emplace_back(i + k, i, -1.0);
    }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  std::vector<char> excluded(n, 0);
  for (int x = 0; x < k; ++x) excluded[x] = 1;
  const std::vector<int> order =
      geometric_nested_dissection(P, std::span<const int>(A.outerIndexPtr(), n + 1),
                                  std::span<const int>(A.innerIndexPtr(), A.nonZeros()), excluded);
  // exactly the free unknowns, each once
  REQUIRE(order.size() == static_cast<std::size_t>(n - k));
  std::vector<int> seen(n, 0);
  for (int v : order) {
    REQUIRE(v >= k);
    REQUIRE(v < n);
    ++seen[v];
  }
  CHECK(std::count(seen.begin() + k, seen.end(), 1) == n - k);
  // A_FF in that order against A_FF in row order, both factorized as given (natural ordering)
  const auto fill = [&](const std::vector<int>& rows) {
    std::vector<int> pos(n, -1);
    for (std::size_t r = 0; r < rows.size(); ++r) pos[rows[r]] = static_cast<int>(r);
    std::vector<Eigen::Triplet<double>> f;
    for (int j = 0; j < n; ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it)
        if (pos[it.row()] >= 0 && pos[j] >= 0) f.emplace_back(pos[it.row()], pos[j], it.value());
    Eigen::SparseMatrix<double> B(static_cast<Eigen::Index>(rows.size()),
                                  static_cast<Eigen::Index>(rows.size()));
    B.setFromTriplets(f.begin(), f.end());
    CholeskySolver s({.ordering = Ordering::Natural});
    s.analyze(B);
    return s.factor_nonzeros();
  };
  std::vector<int> row_order(n - k);
  std::iota(row_order.begin(), row_order.end(), k);
  const double band = fill(row_order), nd = fill(order);
  INFO("nnz(L): row order " << band << ", nested dissection " << nd);
  CHECK(band > 60.0 * (n - k));  // the band, as expected
  CHECK(nd < 0.6 * band);
  CHECK_THROWS_AS(
      geometric_nested_dissection(P.leftCols(2), std::span<const int>(A.outerIndexPtr(), n + 1),
                                  std::span<const int>(A.innerIndexPtr(), A.nonZeros()), excluded),
      Error);
}

/// The 7-point Laplacian (+ 0.01 I, SPD) of the grid nodes `at`, numbered as given (lower triangle).
Eigen::SparseMatrix<double> seven_point(const std::vector<std::array<int, 3>>& at) {
  std::map<std::array<int, 3>, int> index;
  for (int i = 0; i < static_cast<int>(at.size()); ++i) index[at[i]] = i;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < static_cast<int>(at.size()); ++i) {
    t.emplace_back(i, i, 6.01);
    for (int a = 0; a < 3; ++a)
      for (int step : {-1, 1}) {
        auto q = at[i];
        q[a] += step;
        if (const auto it = index.find(q); it != index.end() && it->second < i)
          t.emplace_back(i, it->second, -1.0);
      }
  }
  Eigen::SparseMatrix<double> A(static_cast<Eigen::Index>(at.size()), static_cast<Eigen::Index>(at.size()));
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST_CASE("grid_nested_dissection: a permutation with about METIS's factorization flops, ball, slab, shell",
          "[solvers][ordering]") {
  // A ball of radius 14 (11k nodes; diagonal separators win), a 48×48×3 slab (6.9k nodes; axis
  // separators across the thin plate win) and a spherical shell 3 nodes thick (radius 11 to 14: the
  // region a cage's interior can be near its surface; many planes cut it into pieces). The
  // factorization flops of the 7-point system numbered in that order, as given (natural ordering),
  // against METIS and AMD on the row-major numbering.
  for (const int shape : {0, 1, 2}) {
    std::vector<std::array<int, 3>> at;
    constexpr int r = 14;
    if (shape != 1) {
      for (int x = -r; x <= r; ++x)
        for (int y = -r; y <= r; ++y)
          for (int z = -r; z <= r; ++z)
            if (const int d = x * x + y * y + z * z; d < r * r && (shape == 0 || d >= 11 * 11))
              at.push_back({x, y, z});
    } else {
      for (int x = 0; x < 48; ++x)
        for (int y = 0; y < 48; ++y)
          for (int z = 0; z < 3; ++z) at.push_back({x, y, z});
    }
    const std::vector<int> order = grid_nested_dissection(at);
    REQUIRE(order.size() == at.size());
    std::vector<int> seen(at.size(), 0);
    for (int v : order) {
      REQUIRE(v >= 0);
      REQUIRE(v < static_cast<int>(at.size()));
      ++seen[static_cast<std::size_t>(v)];
    }
    CHECK(std::count(seen.begin(), seen.end(), 1) == static_cast<std::ptrdiff_t>(at.size()));
    std::vector<std::array<int, 3>> renumbered;
    for (int v : order) renumbered.push_back(at[static_cast<std::size_t>(v)]);
    const auto flops = [](const Eigen::SparseMatrix<double>& A, Ordering o) {
      CholeskySolver s({.ordering = o});
      s.analyze(A);
      return s.factor_flops();
    };
    const double nd = flops(seven_point(renumbered), Ordering::Natural),
                 metis = flops(seven_point(at), Ordering::METIS), amd = flops(seven_point(at), Ordering::AMD);
    INFO((shape == 0   ? "ball"
          : shape == 1 ? "slab"
                       : "shell")
         << ": " << at.size() << " nodes; flops: grid ND " << nd << ", METIS " << metis << ", AMD " << amd);
    if (shape == 0) {  // 1.07× METIS here, 0.85× on the 121k-node ball of the cage bench (METIS is seeded)
      CHECK(nd <= 1.1 * metis);
      CHECK(nd < 0.5 * amd);  // minimum degree has no view of a 3D grid's separators
    } else if (shape == 1) {  // a plate: nearly 2D, where AMD does well too
      CHECK(nd <= metis);
      CHECK(nd <= amd);
    } else {  // a shell: planes cut it into rings and caps; 1.26× METIS, 0.77× AMD
      CHECK(nd <= 1.3 * metis);
      CHECK(nd <= amd);
    }
  }
  CHECK(grid_nested_dissection(std::vector<std::array<int, 3>>{}).empty());
}

TEST_CASE("Cholesky: many right-hand sides solved in blocks on several threads equal one-column solves",
          "[solvers]") {
  // A 32³ grid (27k unknowns, ~3M factor nonzeros) and 48 columns: factor nonzeros × columns above
  // the threshold from which solve() splits the columns among the cores (6 per core at least).
  std::vector<std::array<int, 3>> at;
  for (int x = 0; x < 32; ++x)
    for (int y = 0; y < 32; ++y)
      for (int z = 0; z < 32; ++z) at.push_back({x, y, z});
  const Eigen::SparseMatrix<double> A = seven_point(at);
  CholeskySolver s;
  s.compute(A);
  REQUIRE(s.factor_nonzeros() * 48 > 1e8);
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), 48);
  const Eigen::MatrixXd X = s.solve(B);
  const Eigen::SparseMatrix<double> full = Eigen::SparseMatrix<double>(A.selfadjointView<Eigen::Lower>());
  double worst = 0, residual = 0;
  for (Eigen::Index j = 0; j < B.cols(); ++j) {
    const Eigen::VectorXd x = s.solve(B.col(j));  // one column: never split
    worst = std::max(worst, (X.col(j) - x).norm() / x.norm());
    residual = std::max(residual, (full * X.col(j) - B.col(j)).norm() / B.col(j).norm());
  }
  INFO("largest difference " << worst << ", largest relative residual " << residual);
  CHECK(worst <= 1e-14);
  CHECK(residual <= 1e-12);
}

}  // namespace test_cholesky

namespace test_cholesky_threads {

using namespace spinmotor;

namespace {

/// Threads of this process (/proc/self/status), or -1 where it cannot be read.
int thread_count() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("Threads:", 0) == 0) return std::stoi(line.substr(8));
  return -1;
}

/// The 5-point Laplacian of a k×k grid plus the identity (lower triangle): SPD, nested-dissection
/// fronts of ~k rows, large enough for OpenBLAS to run its dgemm calls threaded.
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
  A.makeCompressed();
  return A;
}

/// CPU time (user + system) this process has used, in milliseconds.
double process_cpu_ms() {
  rusage r{};
  getrusage(RUSAGE_SELF, &r);
  return 1e3 * static_cast<double>(r.ru_utime.tv_sec + r.ru_stime.tv_sec) +
         1e-3 * static_cast<double>(r.ru_utime.tv_usec + r.ru_stime.tv_usec);
}

double relative_residual(const Eigen::SparseMatrix<double>& A, const Eigen::MatrixXd& X,
                         const Eigen::MatrixXd& B) {
  const Eigen::MatrixXd AX = A.selfadjointView<Eigen::Lower>() * X;
  return (AX - B).norm() / B.norm();
}

/// A parallel region asking for `requested` threads: the team size it got, whether only the calling
/// thread ran its body, and a dynamic-schedule reduction (Σ i over [1, 1000]).
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

/// Whether the linalg library is a shared object in this process (CI's sanitizer build) rather than
/// linked into the test executable. Asked of the dynamic linker, not of a compile definition: this
/// file's object serves both builds (tests/CMakeLists.txt, SPINMOTOR_TEST_OBJECTS_FROM).
bool linalg_is_shared_object() {
  Dl_info info{};
  REQUIRE(dladdr(reinterpret_cast<const void*>(&serial_openmp_direct_regions), &info) != 0);
  REQUIRE(info.dli_fname != nullptr);
  return std::string_view(info.dli_fname).find("libspinmotor_linalg.so") != std::string_view::npos;
}

}  // namespace

// blas_threads.hpp: the end of a ScopedBlasThreads joins OpenBLAS's workers (no thread left behind,
// none spinning: an idle OpenBLAS worker yields in a loop for ~0.13 s before it sleeps, which shows
// as CPU time while this thread sleeps), and factorizations on another thread meanwhile neither
// deadlock nor go wrong: a worker stopped under a threaded call would leave it waiting forever
// (ctest's timeout) or its result unfinished.
TEST_CASE("BLAS threads: a threaded scope leaves no worker behind, concurrent factorizations stay right",
          "[solvers]") {
  const bool openblas = use_single_threaded_blas();
  const Eigen::SparseMatrix<double> A = grid_matrix(120), C = grid_matrix(90);
  const Eigen::MatrixXd B = Eigen::MatrixXd::Ones(A.rows(), 3), D = Eigen::MatrixXd::Ones(C.rows(), 2);
  {
    CholeskySolver warm({.ordering = Ordering::AMD, .supernodal = true});
    warm.compute(C);
    CHECK(relative_residual(C, warm.solve(D), D) < 1e-12);  // any pool of threads started here
    const int before = thread_count();
    {
      const ScopedBlasThreads two(2);
      CholeskySolver s({.ordering = Ordering::METIS, .supernodal = true});
      s.compute(A);
      CHECK(relative_residual(A, s.solve(B), B) < 1e-12);
    }
    INFO("OpenBLAS: " << openblas);
    CHECK(thread_count() == before);
    const double cpu0 = process_cpu_ms();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    CHECK(process_cpu_ms() - cpu0 < 50.0);  // a spinning worker would take ~130 ms of it
  }
  std::atomic<bool> stop{false};
  std::atomic<int> other_rounds{0};
  double other_worst = 0;
  std::thread other([&] {
    CholeskySolver s({.ordering = Ordering::AMD, .supernodal = true});
    while (!stop.load()) {
      s.compute(C);
      other_worst = std::max(other_worst, relative_residual(C, s.solve(D), D));
      other_rounds.fetch_add(1);
    }
  });
  double worst = 0;
  for (int round = 0; round < 12; ++round) {
    const ScopedBlasThreads two(2);
    CholeskySolver s({.ordering = Ordering::METIS, .supernodal = true});
    s.compute(A);
    worst = std::max(worst, relative_residual(A, s.solve(B), B));
  }
  stop = true;
  other.join();
  CHECK(worst < 1e-12);
  CHECK(other_rounds.load() > 0);
  CHECK(other_worst < 1e-12);
}

// serial_openmp.hpp: inside a SerialOpenMPScope a region that would run on one thread is a plain
// call on the calling thread (counted); outside it, and on other threads meanwhile, regions keep their
// teams; a CHOLMOD factorization runs its regions that way and stays right.
TEST_CASE("serial OpenMP: inside the scope a region is a plain call, outside it keeps its team",
          "[solvers]") {
  const int team = std::min(2, omp_get_thread_limit());
  const Region outside = run_region(2);
  CHECK(outside.threads == team);
  CHECK(outside.sum == 500500);
  CHECK(outside.caller == (team == 1));

  // Counted only where CHOLMOD and this test bind to the library's GOMP_parallel (programs linked
  // statically; not the shared-library build, where libgomp comes first): otherwise libgomp serializes.
  const std::uint64_t counted = serial_openmp_interposed() ? 1 : 0;
  INFO("GOMP_parallel interposed: " << counted);
  const bool shared = linalg_is_shared_object();
  INFO("linalg is a shared object: " << shared);
  if (!shared) REQUIRE(counted == 1);
  const std::uint64_t before = serial_openmp_direct_regions();
  {
    const SerialOpenMPScope scope;
    const Region inside = run_region(2);
    CHECK(inside.threads == 1);
    CHECK(inside.caller);
    CHECK(inside.sum == 500500);
    CHECK(serial_openmp_direct_regions() == before + counted);

    // another thread meanwhile: its regions keep their teams (the scope is this thread's)
    Region other;
    std::thread t([&] { other = run_region(2); });
    t.join();
    CHECK(other.threads == team);
    CHECK(other.sum == 500500);
    CHECK(serial_openmp_direct_regions() == before + counted);
    {
      const SerialOpenMPScope nested;
      CHECK(run_region(2).sum == 500500);
    }
    CHECK(serial_openmp_direct_regions() == before + 2 * counted);
  }
  // after the scope, regions have their teams again and are no longer counted
  CHECK(run_region(2).threads == team);
  CHECK(serial_openmp_direct_regions() == before + 2 * counted);
}

TEST_CASE("serial OpenMP: a supernodal CHOLMOD factorization runs its regions as plain calls", "[solvers]") {
  const Eigen::SparseMatrix<double> A = grid_matrix(100);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  const std::uint64_t before = serial_openmp_direct_regions();
  CholeskySolver s({.ordering = Ordering::METIS, .supernodal = true});
  s.compute(A);
  const std::uint64_t regions = serial_openmp_direct_regions() - before;
  INFO("CHOLMOD regions run as plain calls: " << regions);
  if (serial_openmp_interposed())
    CHECK(regions > 100);  // SuiteSparse 5 opens several per supernode
  else
    CHECK(regions == 0);
  const Eigen::VectorXd x = s.solve(b);
  CHECK((A.selfadjointView<Eigen::Lower>() * x - b).norm() / b.norm() < 1e-14);
}

}  // namespace test_cholesky_threads

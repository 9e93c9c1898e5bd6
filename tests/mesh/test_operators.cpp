// Discrete operators (mesh/cotangent_laplacian.hpp, mean_value_laplacian.hpp, mass_matrix.hpp,
// face_geometry.hpp, gradient.hpp): closed forms, invariants and an independent triplet assembly.
#include <Eigen/SparseCore>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/gradient.hpp"
#include "spinmotor/mesh/mass_matrix.hpp"
#include "spinmotor/mesh/mean_value_laplacian.hpp"
#include "spinmotor/mesh/topology.hpp"

namespace test_operators {

using namespace spinmotor;
using Eigen::MatrixXd;
using Eigen::MatrixXi;
using Eigen::VectorXd;
using SpMat = Eigen::SparseMatrix<double>;

namespace {

// A 12×9 planar grid whose interior vertices are moved randomly in the plane (up to 0.3 cells), so
// that it has obtuse triangles, negative cotangent weights and no symmetry.
Mesh perturbed_grid(unsigned seed = 7) {
  Mesh g = grid(Eigen::Vector2d(2.2, 1.6), Eigen::Vector2i(12, 9));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  const double hx = 2.2 / 11, hy = 1.6 / 8;
  const Eigen::VectorXi in = interior_vertices(g.F, g.V.rows());
  for (Eigen::Index k = 0; k < in.size(); ++k) {
    g.V(in[k], 0) += u(rng) * hx;
    g.V(in[k], 1) += u(rng) * hy;
  }
  return g;
}

// Reference cotangent Laplacian: triplets from corner angles (std::tan), a computation independent
// of the direct compressed assembly under test.
SpMat reference_cotan(const MatrixXd& V, const MatrixXi& F) {
  const MatrixXd T = corner_angles(V, F);
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int i = F(f, (c + 1) % 3), j = F(f, (c + 2) % 3);
      const double w = 0.5 / std::tan(T(f, c));
      t.emplace_back(i, j, -w);
      t.emplace_back(j, i, -w);
      t.emplace_back(i, i, w);
      t.emplace_back(j, j, w);
    }
  SpMat L(V.rows(), V.rows());
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

double max_abs(const SpMat& A) {
  double r = 0;
  for (Eigen::Index k = 0; k < A.outerSize(); ++k)
    for (SpMat::InnerIterator it(A, k); it; ++it) r = std::max(r, std::abs(it.value()));
  return r;
}

bool same_pattern(const SpMat& A, const SpMat& B) {
  if (A.rows() != B.rows() || A.cols() != B.cols() || A.nonZeros() != B.nonZeros()) return false;
  for (Eigen::Index j = 0; j <= A.outerSize(); ++j)
    if (A.outerIndexPtr()[j] != B.outerIndexPtr()[j]) return false;
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k)
    if (A.innerIndexPtr()[k] != B.innerIndexPtr()[k]) return false;
  return true;
}

}  // namespace

TEST_CASE("cotangent Laplacian: symmetric, zero row sums, PSD sign, matches triplet reference",
          "[operators]") {
  for (const Mesh& m : {icosphere(3), perturbed_grid(), uv_sphere(12, 26, 1.5)}) {
    const SpMat L = cotangent_laplacian(m.V, m.F);
    REQUIRE(L.rows() == m.V.rows());
    REQUIRE(L.isCompressed());
    const double scale = max_abs(L);
    CHECK(max_abs(SpMat(L - SpMat(L.transpose()))) <= 1e-15 * scale);
    const VectorXd rowsum = L * VectorXd::Ones(L.rows());
    CHECK(rowsum.cwiseAbs().maxCoeff() <= 1e-13 * scale);
    CHECK(max_abs(SpMat(L - reference_cotan(m.V, m.F))) <= 1e-12 * scale);
    // Positive semi-definite convention: diagonal ≥ 0, and xᵀLx > 0 for a non-constant x.
    CHECK(L.diagonal().minCoeff() >= 0.0);
    const VectorXd x = m.V.col(0);
    CHECK(x.dot(L * x) > 0.0);
  }
}

TEST_CASE("cotangent Laplacian annihilates linear functions at interior vertices of a planar mesh",
          "[operators]") {
  const Mesh g = perturbed_grid();
  const SpMat L = cotangent_laplacian(g.V, g.F);
  // The perturbation makes some cotangent weights negative: the test covers obtuse triangles.
  bool negative_weight = false;
  for (Eigen::Index k = 0; k < L.outerSize(); ++k)
    for (SpMat::InnerIterator it(L, k); it; ++it)
      if (it.row() != it.col() && it.value() > 0) negative_weight = true;
  CHECK(negative_weight);
  const VectorXd u = 0.7 * g.V.col(0) - 1.3 * g.V.col(1) + VectorXd::Constant(g.V.rows(), 0.4);
  const VectorXd Lu = L * u;
  const Eigen::VectorXi in = interior_vertices(g.F, g.V.rows());
  const Eigen::VectorXi bd = boundary_vertices(g.F, g.V.rows());
  double interior = 0, boundary = 0;
  for (Eigen::Index k = 0; k < in.size(); ++k) interior = std::max(interior, std::abs(Lu[in[k]]));
  for (Eigen::Index k = 0; k < bd.size(); ++k) boundary = std::max(boundary, std::abs(Lu[bd[k]]));
  CHECK(interior < 1e-13);
  CHECK(boundary > 1e-3);  // the boundary rows carry the flux (Neumann term): not annihilated
}

TEST_CASE("icosphere area converges to 4πr² with order 2, mass sums to the area", "[operators]") {
  const double r = 1.3;
  double err[3];
  for (int k = 0; k < 3; ++k) {
    const Mesh s = icosphere(3 + k, r);
    const double area = face_areas(s.V, s.F).sum();
    err[k] = 4 * M_PI * r * r - area;
    CHECK(err[k] > 0);  // inscribed polyhedron
    for (MassType t : {MassType::Barycentric, MassType::Voronoi}) {
      const SpMat M = mass_matrix(s.V, s.F, t);
      CHECK(M.nonZeros() == s.V.rows());
      CHECK(M.diagonal().minCoeff() > 0);
      CHECK(std::abs(M.diagonal().sum() - area) <= 1e-13 * area);
    }
  }
  const double order34 = std::log2(err[0] / err[1]), order45 = std::log2(err[1] / err[2]);
  INFO("observed orders " << order34 << ", " << order45);
  CHECK(order34 == Approx(2.0).margin(0.05));
  CHECK(order45 == Approx(2.0).margin(0.05));
}

TEST_CASE("Voronoi mass: mixed area on obtuse triangles, Voronoi area on acute ones", "[operators]") {
  // Obtuse at corner 2: A/2 there, A/4 at the others (Meyer et al. 2003, Fig. 4).
  MatrixXd V(3, 3);
  V << 0, 0, 0, 4, 0, 0, 2, 0.5, 0;
  MatrixXi F(1, 3);
  F << 0, 1, 2;
  const VectorXd a = vertex_areas(V, F, MassType::Voronoi);
  CHECK(a[2] == Approx(0.5).epsilon(1e-15));
  CHECK(a[0] == Approx(0.25).epsilon(1e-15));
  CHECK(a[1] == Approx(0.25).epsilon(1e-15));
  // Equilateral triangle of side 1: circumcentric areas are A/3 each.
  V << 0, 0, 0, 1, 0, 0, 0.5, std::sqrt(3.0) / 2, 0;
  const VectorXd e = vertex_areas(V, F, MassType::Voronoi);
  for (int i = 0; i < 3; ++i) CHECK(e[i] == Approx(std::sqrt(3.0) / 12).epsilon(1e-14));
  // Right triangle: the circumcentre is the hypotenuse midpoint; the right-angle corner gets A/2.
  V << 0, 0, 0, 2, 0, 0, 0, 2, 0;
  const VectorXd rt = vertex_areas(V, F, MassType::Voronoi);
  CHECK(rt[0] == Approx(1.0).epsilon(1e-15));
  CHECK(rt[1] == Approx(0.5).epsilon(1e-15));
  // The perturbed grid has obtuse faces; the mixed areas still sum to the area.
  const Mesh g = perturbed_grid();
  CHECK(vertex_areas(g.V, g.F).sum() == Approx(face_areas(g.V, g.F).sum()).epsilon(1e-14));
}

TEST_CASE("mean curvature normal: M⁻¹ L V → 2HN on the icosphere", "[operators]") {
  const double r = 2.0;
  double prev = 1.0;
  for (int level = 2; level <= 5; ++level) {
    const Mesh s = icosphere(level, r);
    const SpMat L = cotangent_laplacian(s.V, s.F);
    const VectorXd mass = vertex_areas(s.V, s.F, MassType::Voronoi);
    const MatrixXd HN = (mass.cwiseInverse().asDiagonal() * (L * s.V)).eval();
    const MatrixXd exact = (2.0 / r) * s.V / r;  // H = 1/r, N = x/r
    const double err = (HN - exact).rowwise().norm().maxCoeff() / (2.0 / r);
    INFO("level " << level << ": max relative error " << err);
    CHECK(err < prev / 1.9);  // observed: first order in h (0.0167, 0.0083, 0.0042, 0.0021)
    prev = err;
    // Pointing outward: the mean curvature normal has positive component along x everywhere.
    CHECK((HN.cwiseProduct(s.V).rowwise().sum().array() > 0).all());
  }
  CHECK(prev < 5e-3);
}

TEST_CASE(
    "gradient and divergence: −D·G equals the cotangent Laplacian, linear functions have exact gradients",
    "[operators]") {
  for (const Mesh& m : {icosphere(2, 0.8), perturbed_grid()}) {
    const SpMat G = gradient(m.V, m.F), D = divergence(m.V, m.F);
    REQUIRE(G.rows() == 3 * m.F.rows());
    REQUIRE(G.cols() == m.V.rows());
    REQUIRE(D.rows() == m.V.rows());
    REQUIRE(D.cols() == 3 * m.F.rows());
    const SpMat L = cotangent_laplacian(m.V, m.F);
    CHECK(max_abs(SpMat(SpMat(-D * G) - L)) <= 1e-13 * max_abs(L));
    // Gradients lie in the face planes.
    const VectorXd gx = G * m.V.col(0);
    const MatrixXd N = face_normals(m.V, m.F);
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) CHECK(std::abs(gx.segment<3>(3 * f).dot(N.row(f))) < 1e-12);
  }
  // On a planar mesh the gradient of u = a·x is a on every face, in the per-face row layout.
  const Mesh g = perturbed_grid();
  const Eigen::Vector3d a(0.3, -1.7, 0.0);
  const VectorXd gu = gradient(g.V, g.F) * (g.V * a);
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>> per_face(gu.data(),
                                                                                             g.F.rows(), 3);
  CHECK((per_face.rowwise() - a.transpose()).cwiseAbs().maxCoeff() < 1e-13);
}

TEST_CASE("face geometry: unit outward normals, angles sum to π, cotangents agree with the angles",
          "[operators]") {
  const Mesh s = icosphere(2);
  const MatrixXd N = face_normals(s.V, s.F);
  CHECK((N.rowwise().norm().array() - 1.0).abs().maxCoeff() < 1e-15);
  for (Eigen::Index f = 0; f < s.F.rows(); ++f) {
    const Eigen::RowVector3d centroid = (s.V.row(s.F(f, 0)) + s.V.row(s.F(f, 1)) + s.V.row(s.F(f, 2))) / 3;
    CHECK(N.row(f).dot(centroid) > 0);
  }
  const Mesh g = perturbed_grid();
  const MatrixXd T = corner_angles(g.V, g.F), C = cotangents(g.V, g.F), E = face_edge_lengths(g.V, g.F);
  CHECK((T.rowwise().sum().array() - M_PI).abs().maxCoeff() < 1e-14);
  CHECK((C - T.array().tan().inverse().matrix()).cwiseAbs().maxCoeff() < 1e-12);
  // Law of cosines with the edge lengths.
  for (Eigen::Index f = 0; f < g.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const double a = E(f, c), b = E(f, (c + 1) % 3), d = E(f, (c + 2) % 3);
      CHECK(a * a == Approx(b * b + d * d - 2 * b * d * std::cos(T(f, c))).epsilon(1e-12));
    }
}

TEST_CASE("mean-value Laplacian: positive weights, zero row sums, linear precision, not symmetric",
          "[operators]") {
  const Mesh g = perturbed_grid();
  const SpMat L = mean_value_laplacian(g.V, g.F);
  const SpMat Lc = cotangent_laplacian(g.V, g.F);
  CHECK(same_pattern(L, Lc));
  // Off-diagonal entries −w_ij < 0 everywhere, even where cotangent weights are negative.
  for (Eigen::Index k = 0; k < L.outerSize(); ++k)
    for (SpMat::InnerIterator it(L, k); it; ++it)
      if (it.row() != it.col()) CHECK(it.value() < 0);
  const double scale = max_abs(L);
  CHECK((L * VectorXd::Ones(L.rows())).cwiseAbs().maxCoeff() <= 1e-13 * scale);
  CHECK(max_abs(SpMat(L - SpMat(L.transpose()))) > 1e-3 * scale);
  // Mean value coordinates reproduce planar positions: (L·V)_i = 0 at interior vertices.
  const MatrixXd LV = L * g.V;
  const Eigen::VectorXi in = interior_vertices(g.F, g.V.rows());
  for (Eigen::Index k = 0; k < in.size(); ++k) CHECK(LV.row(in[k]).norm() < 1e-12 * scale);
  // Closed form on one face of the regular grid: a right isosceles corner (θ = π/2, tan = 1) next
  // to an edge of length h gets weight 1/h from that face.
  MatrixXd V(3, 3);
  V << 0, 0, 0, 2, 0, 0, 0, 2, 0;
  MatrixXi F(1, 3);
  F << 0, 1, 2;
  const SpMat T = mean_value_laplacian(V, F);
  CHECK(T.coeff(0, 1) == Approx(-0.5).epsilon(1e-15));                     // tan(π/4)/2
  CHECK(T.coeff(1, 0) == Approx(-std::tan(M_PI / 8) / 2).epsilon(1e-14));  // 45° corner
  CHECK(T.coeff(1, 2) == Approx(-std::tan(M_PI / 8) / std::sqrt(8.0)).epsilon(1e-14));
}

TEST_CASE("operators reject degenerate faces, bad indices and non-finite vertices, naming them",
          "[operators]") {
  Mesh g = grid(Eigen::Vector2d(1, 1), Eigen::Vector2i(3, 3));
  // Collapse face 5 by moving its corner onto the opposite edge's line: make it collinear.
  const int f = 5;
  const int a = g.F(f, 0), b = g.F(f, 1), c = g.F(f, 2);
  g.V.row(c) = 0.5 * (g.V.row(a) + g.V.row(b));
  const std::string face = "face " + std::to_string(f) + " ";
  // Faces before 5 may share vertex c without being degenerate; the first degenerate one is named.
  const MatrixXd A = face_areas(g.V, g.F).transpose();
  for (Eigen::Index k = 0; k < f; ++k) REQUIRE(A(0, k) > 1e-3);
  CHECK_THROWS_WITH(cotangent_laplacian(g.V, g.F), Catch::Contains(face) && Catch::Contains("degenerate"));
  CHECK_THROWS_WITH(mean_value_laplacian(g.V, g.F), Catch::Contains(face));
  CHECK_THROWS_WITH(mass_matrix(g.V, g.F, MassType::Voronoi), Catch::Contains(face));
  CHECK_THROWS_WITH(gradient(g.V, g.F), Catch::Contains(face));
  CHECK_THROWS_WITH(divergence(g.V, g.F), Catch::Contains(face));
  CHECK_THROWS_WITH(face_normals(g.V, g.F), Catch::Contains(face));
  CHECK_THROWS_WITH(cotangents(g.V, g.F), Catch::Contains(face));
  CHECK_NOTHROW(mass_matrix(g.V, g.F, MassType::Barycentric));
  CHECK(face_areas(g.V, g.F)[f] == Approx(0).margin(1e-16));
  CHECK(corner_angles(g.V, g.F).row(f).maxCoeff() == Approx(M_PI));
  try {
    cotangent_laplacian(g.V, g.F);
  } catch (const Error& e) {
    CHECK(e.kind() == Error::Kind::BadInput);
  }

  Mesh h = grid(Eigen::Vector2d(1, 1), Eigen::Vector2i(3, 3));
  h.F(4, 1) = 9;  // 9 vertices: index 9 is out of range
  CHECK_THROWS_WITH(cotangent_laplacian(h.V, h.F),
                    Catch::Contains("face 4 ") && Catch::Contains("out of range"));
  h = grid(Eigen::Vector2d(1, 1), Eigen::Vector2i(3, 3));
  h.V(6, 2) = std::nan("");
  CHECK_THROWS_WITH(mass_matrix(h.V, h.F), Catch::Contains("vertex 6 ") && Catch::Contains("non-finite"));
  CHECK_THROWS_WITH(face_areas(h.V, MatrixXi(h.F.leftCols(2))), Catch::Contains("3 columns"));
}

TEST_CASE("unreferenced vertices keep an explicit zero diagonal and zero mass", "[operators]") {
  Mesh g = grid(Eigen::Vector2d(1, 1), Eigen::Vector2i(3, 3));
  g.V.conservativeResize(10, 3);
  g.V.row(9) << 5, 5, 5;
  const SpMat L = cotangent_laplacian(g.V, g.F);
  CHECK(L.rows() == 10);
  CHECK(L.col(9).nonZeros() == 1);
  CHECK(L.coeff(9, 9) == 0.0);
  CHECK(vertex_areas(g.V, g.F)[9] == 0.0);
}

}  // namespace test_operators

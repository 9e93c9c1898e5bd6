// Spin transformations (Crane, Pinkall & Schröder 2011, §5–§6): identity for ρ = 0, the reference
// SpinXForm case, convergence under refinement, boundary tangents (§5.7), input errors.
#include <unistd.h>

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "shared_data.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "spinmotor/spin/curvature_change.hpp"
#include "spinmotor/spin/scalar_expression.hpp"
#include "spinmotor/spin/spin_transform.hpp"

namespace test_spin {

using namespace spinmotor;

namespace {

const std::string kSpinDir = std::string(SPINMOTOR_MESHES_DIR) + "/spinxform/";

Mesh bumpy_closed(int level) {
  Mesh m = icosphere(level);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    const Eigen::Vector3d p = m.V.row(i);
    m.V.row(i) *= 1.0 + 0.15 * std::sin(3 * p.x()) * std::cos(2 * p.y()) + 0.1 * p.z();
  }
  return m;
}

// Unit disk in z = 0: a centre vertex and `rings` rings, ring k with 6k vertices, faces CCW seen from +z.
Mesh unit_disk(int rings) {
  Mesh m;
  std::vector<Eigen::Vector3d> V{Eigen::Vector3d::Zero()};
  std::vector<int> start{0};
  for (int k = 1; k <= rings; ++k) {
    start.push_back(static_cast<int>(V.size()));
    const int nk = 6 * k;
    for (int j = 0; j < nk; ++j) {
      const double t = 2 * M_PI * j / nk;
      V.emplace_back(std::cos(t) * k / rings, std::sin(t) * k / rings, 0.0);
    }
  }
  std::vector<Eigen::Vector3i> F;
  for (int j = 0; j < 6; ++j) F.emplace_back(0, 1 + j, 1 + (j + 1) % 6);
  for (int k = 1; k < rings; ++k) {
    // Merge walk between ring k (6k vertices) and ring k+1 (6k+6) by angle.
    const int a0 = start[k], na = 6 * k, b0 = start[k + 1], nb = 6 * (k + 1);
    int i = 0, j = 0;
    while (i < na || j < nb) {
      const double ta = 2 * M_PI * (i + 1) / na, tb = 2 * M_PI * (j + 1) / nb;
      if (j < nb && (i >= na || tb <= ta)) {
        F.emplace_back(a0 + i % na, b0 + j % nb, b0 + (j + 1) % nb);
        ++j;
      } else {
        F.emplace_back(a0 + i % na, b0 + j % nb, a0 + (i + 1) % na);
        ++i;
      }
    }
  }
  m.V.resize(V.size(), 3);
  for (std::size_t i = 0; i < V.size(); ++i) m.V.row(i) = V[i].transpose();
  m.F.resize(F.size(), 3);
  for (std::size_t f = 0; f < F.size(); ++f) m.F.row(f) = F[f].transpose();
  return m;
}

}  // namespace

TEST_CASE("rho = 0 returns a similarity of the input (Q = 1, positions equal after alignment)", "[spin]") {
  SECTION("closed mesh, each eigenproblem and both matrix forms") {
    const Mesh m = bumpy_closed(2);
    const Eigen::VectorXd rho = Eigen::VectorXd::Zero(m.F.rows());
    for (const auto problem :
         {SpinEigenProblem::Standard, SpinEigenProblem::Unweighted, SpinEigenProblem::Generalized})
      for (const bool complex : {true, false}) {
        SpinTransformOptions o;
        o.problem = problem;
        o.complex_form = complex;
        const SpinTransformResult r = spin_transform(m, rho, o);
        const QuasiConformalSummary q = quasi_conformal_summary(m.V, m.F, r.V);
        const VertexDistances d = vertex_distances(m.V, r.V, Alignment::Similarity);
        INFO("problem " << static_cast<int>(problem) << " complex " << complex << " iterations "
                        << r.iterations);
        CHECK(q.q_max - 1.0 < 1e-8);
        CHECK(d.rms < 1e-8);
        CHECK(std::abs(r.eigenvalue) < 1e-8);
        // KeepArea: same total area and vertex mean as the input.
        CHECK(face_areas(r.V, m.F).sum() == Approx(face_areas(m.V, m.F).sum()).epsilon(1e-12));
        CHECK((r.V.colwise().mean() - m.V.colwise().mean()).norm() < 1e-12);
      }
  }
  SECTION("flat disk with free boundary") {
    // On a flat disk ρ = 0 has more exact solutions than the constants (linear λ: the conformal maps
    // of the plane keep H = 0), so the smallest eigenvalue is multiple; the start vector's projection
    // is returned. For the unweighted problem the all-ones start is itself a solution: the identity.
    const Mesh m = unit_disk(8);
    SpinTransformOptions o;
    o.problem = SpinEigenProblem::Unweighted;
    const SpinTransformResult r = spin_transform(m, Eigen::VectorXd::Zero(m.F.rows()), o);
    CHECK(quasi_conformal_summary(m.V, m.F, r.V).q_max - 1.0 < 1e-8);
    CHECK(vertex_distances(m.V, r.V, Alignment::Similarity).rms < 1e-8);
    // For eq. 7 the start projects partly onto the other solutions: still planar and conformal.
    const SpinTransformResult s = spin_transform(m, Eigen::VectorXd::Zero(m.F.rows()));
    CHECK(quasi_conformal_summary(m.V, m.F, s.V).q_max - 1.0 < 1e-3);
    CHECK(s.V.col(2).cwiseAbs().maxCoeff() < 1e-8);
  }
}

TEST_CASE("reference case: SpinXForm's sphere.obj + bumpy.tga", "[spin][reference]") {
  SPINMOTOR_REQUIRE_MESHES();
  const Mesh m = read_mesh(kSpinDir + "sphere.obj");
  const Mesh ref = read_mesh(kSpinDir + "bumpy_reference.obj");
  REQUIRE(m.V.rows() == 4002);
  REQUIRE(m.F.rows() == 8000);
  const Eigen::VectorXd rho = face_rho_from_image(m, read_grayscale_image(kSpinDir + "bumpy.tga"), 5.0);

  // The reference code's settings: A*A λ = γ λ without M_V, 3 inverse iterations from the all-ones
  // real quaternions, last vertex pinned, output centred with max |v| = 1.
  const SpinTransformResult compat = spin_transform(m, rho, SpinTransformOptions::spinxform());
  const VertexDistances dc = vertex_distances(ref.V, compat.V, Alignment::None);
  const QuasiConformalSummary qc = quasi_conformal_summary(m.V, m.F, compat.V);
  WARN("SpinXForm-compatible: RMS to bumpy_reference.obj "
       << dc.rms << " (max " << dc.max << ") of the bbox diagonal, Q_mean " << qc.q_mean << ", Q_max "
       << qc.q_max);
  CHECK(compat.iterations == 3);
  CHECK(dc.rms <= 1e-3);
  CHECK(dc.rms <= 1e-5);  // in fact it matches to the reference file's 6 significant digits
  CHECK(qc.q_mean <= 1.052);
  CHECK(qc.q_mean == Approx(1.0516).margin(5e-4));  // the README's figure for bumpy_reference.obj

  // Converged default (eq. 7), normalised the same way for the comparison.
  SpinTransformOptions o;
  o.scale = SpinScale::UnitMaxNorm;
  const SpinTransformResult conv = spin_transform(m, rho, o);
  const VertexDistances dd = vertex_distances(ref.V, conv.V, Alignment::None);
  const QuasiConformalSummary qd = quasi_conformal_summary(m.V, m.F, conv.V);
  WARN("converged standard problem (7): " << conv.iterations << " iterations, residual " << conv.residual
                                          << ", RMS to the reference " << dd.rms << " (max " << dd.max
                                          << "), Q_mean " << qd.q_mean << ", Q_max " << qd.q_max);
  CHECK(conv.residual < o.tolerance);
  CHECK(qd.q_mean < qc.q_mean);  // converging lowers the conformal error
  CHECK(dd.max < 1.5e-2);        // README: a converged eigenvector differs by up to 1.5e-2
  CHECK(dd.rms > 10 * dc.rms);   // and it is not the 3-iteration result

  // Converged unweighted problem: the limit of the reference's own iteration.
  SpinTransformOptions u = o;
  u.problem = SpinEigenProblem::Unweighted;
  const SpinTransformResult unw = spin_transform(m, rho, u);
  const VertexDistances du = vertex_distances(ref.V, unw.V, Alignment::None);
  WARN("converged unweighted problem: RMS to the reference "
       << du.rms << ", Q_mean " << quasi_conformal_summary(m.V, m.F, unw.V).q_mean);
  CHECK(unw.residual < u.tolerance);
}

TEST_CASE("the real 4x4-block and complex 2x2-block forms give the same transformation", "[spin]") {
  const Mesh m = bumpy_closed(2);
  const Eigen::VectorXd rho = face_rho_from_function(
      m.V, m.F, [](const Eigen::Vector3d& p) { return 4.0 * std::sin(4 * p.x()) * std::cos(3 * p.z()); });
  for (const auto problem : {SpinEigenProblem::Standard, SpinEigenProblem::Generalized}) {
    SpinTransformOptions o;
    o.problem = problem;
    const SpinTransformResult c = spin_transform(m, rho, o);
    o.complex_form = false;
    const SpinTransformResult r = spin_transform(m, rho, o);
    CHECK(c.eigenvalue == Approx(r.eigenvalue).epsilon(1e-9));
    CHECK(vertex_distances(r.V, c.V, Alignment::None).rms < 1e-8);
    // Plain inverse iteration converges to the same pair, with more iterations.
    o.complex_form = true;
    o.krylov = false;
    o.iterations = 200;
    const SpinTransformResult p = spin_transform(m, rho, o);
    CHECK(p.iterations >= c.iterations);
    CHECK(p.eigenvalue == Approx(c.eigenvalue).epsilon(1e-8));
    CHECK(vertex_distances(p.V, c.V, Alignment::None).rms < 1e-7);
  }
}

TEST_CASE("convergence: Q_mean - 1 decreases about linearly with the mean edge length (Fig. 12)",
          "[spin][convergence]") {
  // A fixed smooth bump pattern ρ(x) on icospheres of three refinements.
  auto rho_of = [](const Eigen::Vector3d& p) {
    return 6.0 * std::sin(3 * p.x()) * std::sin(3 * p.y()) * std::sin(3 * p.z());
  };
  std::vector<double> h, err;
  for (int level : {2, 3, 4}) {
    const Mesh m = icosphere(level);
    const SpinTransformResult r = spin_transform(m, face_rho_from_function(m.V, m.F, rho_of));
    const QuasiConformalSummary q = quasi_conformal_summary(m.V, m.F, r.V);
    const EdgeTopology t = edge_topology(m.F);
    double len = 0;
    for (Eigen::Index e = 0; e < t.E.rows(); ++e) len += (m.V.row(t.E(e, 0)) - m.V.row(t.E(e, 1))).norm();
    h.push_back(len / t.E.rows());
    err.push_back(q.q_mean - 1.0);
  }
  const double slope = std::log(err[2] / err[0]) / std::log(h[2] / h[0]);
  WARN("mean edge length " << h[0] << ", " << h[1] << ", " << h[2] << "; Q_mean - 1 " << err[0] << ", "
                           << err[1] << ", " << err[2] << "; log-log slope " << slope);
  CHECK(err[1] < err[0]);
  CHECK(err[2] < err[1]);
  CHECK(slope > 0.7);
  CHECK(slope < 2.5);
}

TEST_CASE("boundary tangents (§5.7): a flat disk bends as prescribed", "[spin][boundary]") {
  const Mesh m = unit_disk(16);
  const auto loops = boundary_loops(m.F);
  REQUIRE(loops.size() == 1);
  const std::vector<int>& loop = loops[0];
  const double h = 0.25;  // target boundary curve (cos t, sin t, h cos 2t): a saddle
  SpinBoundaryTangents bt;
  bt.vertices.resize(loop.size());
  bt.targets.resize(loop.size(), 3);
  for (std::size_t k = 0; k < loop.size(); ++k) {
    // Tangent of the target curve halfway along the outgoing edge (the discrete T of §7.4).
    const int i = loop[k], j = loop[(k + 1) % loop.size()];
    const double ti = std::atan2(m.V(i, 1), m.V(i, 0)), tj = std::atan2(m.V(j, 1), m.V(j, 0));
    double tm = 0.5 * (ti + tj);
    if (std::abs(tj - ti) > M_PI) tm += M_PI;
    bt.vertices[k] = i;
    bt.targets.row(k) << -std::sin(tm), std::cos(tm), -2 * h * std::sin(2 * tm);
  }
  SpinTransformOptions o;
  o.boundary = bt;
  const SpinTransformResult r = spin_transform(m, Eigen::VectorXd::Zero(m.F.rows()), o);
  const QuasiConformalSummary q = quasi_conformal_summary(m.V, m.F, r.V);
  // Output boundary edge directions against the prescribed tangents.
  double mean_angle = 0, max_angle = 0;
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const Eigen::Vector3d e = (r.V.row(loop[(k + 1) % loop.size()]) - r.V.row(loop[k])).transpose();
    const Eigen::Vector3d t = bt.targets.row(k).transpose();
    const double ang = std::acos(std::clamp(e.normalized().dot(t.normalized()), -1.0, 1.0));
    mean_angle += ang / loop.size();
    max_angle = std::max(max_angle, ang);
  }
  // Out-of-plane shape: the boundary's height against h cos 2t after a similarity fit to the curve.
  Eigen::MatrixXd target(loop.size(), 3), got(loop.size(), 3);
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const double t = std::atan2(m.V(loop[k], 1), m.V(loop[k], 0));
    target.row(k) << std::cos(t), std::sin(t), h * std::cos(2 * t);
    got.row(k) = r.V.row(loop[k]);
  }
  const Similarity fit = umeyama_fit(got, target, true);
  const double curve_rms = std::sqrt((fit.apply(got) - target).rowwise().squaredNorm().mean());
  WARN("boundary: Q_mean " << q.q_mean << ", Q_max " << q.q_max << ", tangent angle error mean "
                           << mean_angle * 180 / M_PI << " deg, max " << max_angle * 180 / M_PI
                           << " deg, boundary curve RMS to (cos t, sin t, h cos 2t) " << curve_rms);
  CHECK(q.q_mean <= 1.02);
  CHECK(mean_angle * 180 / M_PI < 2.0);
  CHECK(curve_rms < 0.16 * h);  // tangents fix the curve up to its speed |λ|², not its exact shape
  // The prescription matters: with the tangents left in the plane the disk stays flat.
  SpinTransformOptions flat = o;
  flat.boundary.targets.col(2).setZero();
  const SpinTransformResult rf = spin_transform(m, Eigen::VectorXd::Zero(m.F.rows()), flat);
  CHECK(rf.V.col(2).cwiseAbs().maxCoeff() < 1e-8);
  CHECK(r.V.col(2).maxCoeff() - r.V.col(2).minCoeff() > h);
}

TEST_CASE("bad input gives clear errors", "[spin][errors]") {
  auto message = [](auto&& f) -> std::string {
    try {
      f();
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  Mesh m = icosphere(1);
  const Eigen::VectorXd rho0 = Eigen::VectorXd::Zero(m.F.rows());
  SECTION("degenerate face") {
    Mesh d = m;
    d.V.row(d.F(3, 2)) = 0.5 * (d.V.row(d.F(3, 0)) + d.V.row(d.F(3, 1)));  // collinear corners
    CHECK_THAT(message([&] { spin_transform(d, rho0); }), Catch::Contains("degenerate"));
  }
  SECTION("non-manifold") {
    Mesh d = m;
    d.F.conservativeResize(m.F.rows() + 1, 3);
    d.F.row(m.F.rows()) << m.F(0, 0), m.F(0, 1), m.F(5, 2);  // a third face on edge (F00, F01)
    CHECK_THAT(message([&] { spin_transform(d, Eigen::VectorXd::Zero(d.F.rows())); }),
               Catch::Contains("manifold"));
  }
  SECTION("empty") {
    Mesh e;
    e.V.resize(0, 3);
    e.F.resize(0, 3);
    CHECK_FALSE(message([&] { spin_transform(e, Eigen::VectorXd()); }).empty());
  }
  SECTION("image without texture coordinates") {
    Mesh d = m;
    d.UV.resize(0, 2);
    d.FUV.resize(0, 3);
    GrayscaleImage img;
    img.width = img.height = 2;
    img.pixels = Eigen::VectorXf::Constant(4, 128.f);
    CHECK_THAT(message([&] { face_rho_from_image(d, img); }), Catch::Contains("texture coordinates"));
  }
  SECTION("unreadable image") {
    CHECK_THAT(message([&] { read_grayscale_image(kSpinDir + "sphere.obj"); }),
               Catch::Contains("sphere.obj"));
  }
  SECTION("TGAs read whole, and refused when cut short (uncompressed and run-length)") {
    // A 3 × 2, 8-bit grayscale TGA of type `type` with pixel bytes `body`, less its last `drop` bytes,
    // written to a scratch file. Origin bottom-left: rows bottom-up, as in GrayscaleImage.
    std::vector<std::filesystem::path> files;
    auto tga = [&](int type, std::initializer_list<int> body, std::size_t drop) {
      std::string t(18, '\0');
      t[2] = static_cast<char>(type);
      t[12] = 3;
      t[14] = 2;
      t[16] = 8;
      for (const int v : body) t.push_back(static_cast<char>(v));
      files.push_back(
          std::filesystem::temp_directory_path() /
          ("spinmotor_test_tga_" + std::to_string(::getpid()) + "_" + std::to_string(files.size()) + ".tga"));
      std::ofstream(files.back(), std::ios::binary) << t.substr(0, t.size() - drop);
      return files.back();
    };
    const std::initializer_list<int> raw = {10, 20, 30, 40, 50, 60};
    // type 11: a run of 2 × 10, a literal 30, then 3 literals 40, 50, 60 (a different first row)
    const std::initializer_list<int> rle = {0x81, 10, 0x00, 30, 0x02, 40, 50, 60};
    const GrayscaleImage a = read_grayscale_image(tga(3, raw, 0)), b = read_grayscale_image(tga(11, rle, 0));
    REQUIRE((a.width == 3 && a.height == 2 && b.width == 3 && b.height == 2));
    CHECK(a.pixels == Eigen::Vector<float, 6>(10, 20, 30, 40, 50, 60));
    CHECK(b.pixels == Eigen::Vector<float, 6>(10, 10, 30, 40, 50, 60));
    const std::string raw_cut = message([&] { read_grayscale_image(tga(3, raw, 2)); });
    const std::string rle_cut =
        message([&] { read_grayscale_image(tga(11, rle, 1)); });  // in the last packet
    const std::string rle_early = message([&] { read_grayscale_image(tga(11, rle, 4)); });  // before it
    for (const auto& f : files) std::filesystem::remove(f);
    CHECK_THAT(raw_cut, Catch::Contains("spinmotor_test_tga_") &&
                            Catch::Contains("needs 24 bytes, the file has 22") &&
                            Catch::Contains("truncated"));
    CHECK_THAT(rle_cut, Catch::Contains("ends inside a packet, after 3 of its 6 pixels"));
    CHECK_THAT(rle_early, Catch::Contains("ends after 3 of its 6 pixels"));
  }
  SECTION("rho of the wrong size or not finite") {
    CHECK_THAT(message([&] { spin_transform(m, Eigen::VectorXd::Zero(3)); }), Catch::Contains("faces"));
    Eigen::VectorXd bad = rho0;
    bad[7] = std::nan("");
    CHECK_THAT(message([&] { spin_transform(m, bad); }), Catch::Contains("face 7"));
  }
  SECTION("generalized problem on an open mesh, tangents off the boundary") {
    const Mesh d = unit_disk(3);
    SpinTransformOptions o;
    o.problem = SpinEigenProblem::Generalized;
    CHECK_THAT(message([&] { spin_transform(d, Eigen::VectorXd::Zero(d.F.rows()), o); }),
               Catch::Contains("closed"));
    SpinTransformOptions b;
    b.boundary.vertices = Eigen::VectorXi::Constant(1, 0);  // the centre
    b.boundary.targets = Eigen::RowVector3d(1, 0, 0);
    CHECK_THAT(message([&] { spin_transform(d, Eigen::VectorXd::Zero(d.F.rows()), b); }),
               Catch::Contains("not on the boundary"));
  }
}

TEST_CASE("scalar expressions: the nesting and depth limits refuse what would overflow the stack",
          "[spin][rho]") {
  // Found by fuzz_expression (fuzz/regressions/fuzz_expression/): 1200 nested parentheses overflowed the
  // parser's stack under ASan; a long sum overflows evaluation (one level per term) without them.
  const Eigen::Vector3d p(1, 2, 3);
  auto repeat = [](const std::string& s, int n) {
    std::string out;
    for (int i = 0; i < n; ++i) out += s;
    return out;
  };
  CHECK(parse_scalar_expression(repeat("(", 100) + "x" + repeat(")", 100))(p) == 1.0);
  CHECK_THROWS_WITH(parse_scalar_expression(repeat("(", 101) + "x" + repeat(")", 101)),
                    Catch::Contains("nested more than 100 levels"));
  CHECK_THROWS_WITH(parse_scalar_expression(repeat("-", 300000) + "x"), Catch::Contains("nested more than"));
  // "0" + repeat(...) would trip GCC 12's -Wrestrict false positive (bug 105329): built by appending.
  std::string sum999 = "0", sum300k = "0";
  sum999 += repeat("+x", 999);
  sum300k += repeat("+x", 300000);
  CHECK(parse_scalar_expression(sum999)(p) == 999.0);
  CHECK_THROWS_WITH(parse_scalar_expression(sum300k), Catch::Contains("more than 1000 levels of operations"));
}

TEST_CASE("rho inputs: per vertex, scalar expression, image sampling", "[spin][rho]") {
  SPINMOTOR_REQUIRE_MESHES();
  const Mesh m = icosphere(2);
  // Per vertex → faces: the mean of the corners.
  Eigen::VectorXd rv(m.V.rows());
  for (Eigen::Index i = 0; i < rv.size(); ++i) rv[i] = static_cast<double>(i);
  const Eigen::VectorXd rf = face_rho_from_vertices(m.F, rv);
  CHECK(rf[7] == Approx((m.F(7, 0) + m.F(7, 1) + m.F(7, 2)) / 3.0));
  // Expressions: value, precedence (-x^2 = -(x^2), 2^3^2 = 2^9), functions, r.
  const auto g = parse_scalar_expression("5 * sin(3*x) * cos(2*y) - 0.5*z^2 + r/2");
  const Eigen::Vector3d p(0.3, -0.2, 0.7);
  CHECK(g(p) == Approx(5 * std::sin(0.9) * std::cos(-0.4) - 0.5 * 0.49 + p.norm() / 2));
  CHECK(parse_scalar_expression("-x^2")(p) == Approx(-0.09));
  CHECK(parse_scalar_expression("2^3^2")(p) == Approx(512.0));
  CHECK(parse_scalar_expression("sqrt(abs(-4)) + exp(0) + pi - pi + 1e-3")(p) == Approx(3.001));
  auto message = [](const std::string& text) -> std::string {
    try {
      parse_scalar_expression(text);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  CHECK_THAT(message("sin(x"), Catch::Contains("expected ')'"));
  CHECK_THAT(message("foo(x)"), Catch::Contains("unknown name 'foo'"));
  CHECK_THAT(message("x +* y"), Catch::Contains("at 4"));
  const Eigen::VectorXd re = face_rho_from_function(m.V, m.F, g);
  const Eigen::Vector3d c = (m.V.row(m.F(5, 0)) + m.V.row(m.F(5, 1)) + m.V.row(m.F(5, 2))).transpose() / 3.0;
  CHECK(re[5] == Approx(g(c)));
  CHECK_THROWS_AS(face_rho_from_function(m.V, m.F, parse_scalar_expression("log(x - 10)")), Error);
  // Image sampling: bilinear at (u·w, v·h), no half-pixel offset, clamped; mid grey → ρ = 0.
  GrayscaleImage img;
  img.width = 2;
  img.height = 2;
  img.pixels.resize(4);
  img.pixels << 0.f, 255.f, 51.f, 102.f;  // row 0 (bottom): 0, 255; row 1: 51, 102
  CHECK(img.sample(0.5, 0.0) == Approx(127.5));
  CHECK(img.sample(0.0, 0.5) == Approx(25.5));
  CHECK(img.sample(0.5, 0.5) == Approx((0 + 255 + 51 + 102) / 4.0));
  CHECK(img.sample(-3.0, 7.0) == Approx(51.0));  // clamped to the corner (0, 1)
  CHECK(img.sample_uv(1.0, 1.0) == Approx(102.0));
  Mesh t = m;
  t.UV = Eigen::MatrixXd::Constant(1, 2, 0.25);  // every corner samples (0.5, 0.5)
  t.FUV = Eigen::MatrixXi::Zero(m.F.rows(), 3);
  const Eigen::VectorXd ri = face_rho_from_image(t, img, 5.0);
  CHECK(ri[0] == Approx((2.0 * 102.0 / 255.0 - 1.0) * 5.0));
  // A coordinate that is not finite is an Error (a NaN's conversion to int would be UB).
  CHECK(img.sample(1e300, -1e300) == Approx(255.0));  // far outside: clamped to the corner (1, 0)
  CHECK_THROWS_WITH(img.sample(std::nan(""), 0.5), Catch::Contains("not finite"));
  CHECK_THROWS_WITH(img.sample(0.5, INFINITY), Catch::Contains("not finite"));
  t.UV(0, 1) = std::nan("");
  CHECK_THROWS_WITH(face_rho_from_image(t, img, 5.0), Catch::Contains("face 0 has texture coordinate 0"));
  // The reference image's corner pixels, as stored in the TGA file (bottom row first).
  const GrayscaleImage bumpy =
      read_grayscale_image(std::string(SPINMOTOR_MESHES_DIR) + "/spinxform/bumpy.tga");
  CHECK(bumpy.width == 512);
  CHECK(bumpy.height == 512);
  std::ifstream raw(std::string(SPINMOTOR_MESHES_DIR) + "/spinxform/bumpy.tga", std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(raw)), std::istreambuf_iterator<char>());
  // Uncompressed 8-bit grayscale, no id field, origin bottom-left (+ a 26-byte TGA 2.0 footer).
  REQUIRE(bytes.size() >= 18 + 512 * 512);
  int mismatches = 0, flipped = 0;
  for (int y = 0; y < 512; y += 3)
    for (int x = 0; x < 512; x += 5) {
      const unsigned char b = static_cast<unsigned char>(bytes[18 + x + 512 * y]);
      mismatches += bumpy.at(x, y) != b;
      flipped += bumpy.at(x, 511 - y) != b;
    }
  CHECK(mismatches == 0);
  CHECK(flipped > 1000);  // the test can tell the two row orders apart
}

}  // namespace test_spin

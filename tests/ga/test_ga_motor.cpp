// Motors: isometry / dual-quaternion interop, exp / log / sqrt / sclerp robustness, blending, and the
// geometric constructors (plane, sphere, line), checked against Eigen and closed forms.
#include <Eigen/Geometry>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <spinmotor/ga.hpp>
#include <vector>

namespace test_ga_motor {

using namespace spinmotor::ga;
using Eigen::Vector3d;

namespace {

const double kPi = std::acos(-1.0);

double max_abs(const Mot& a) {
  double m = 0.0;
  for (double v : a.c) m = std::max(m, std::abs(v));
  return m;
}
double max_abs(const Dll& a) {
  double m = 0.0;
  for (double v : a.c) m = std::max(m, std::abs(v));
  return m;
}
double max_abs(const Eigen::Matrix4d& a) {  // (a loop: Eigen's AVX-512 maxCoeff trips a GCC 12 warning)
  double m = 0.0;
  for (int i = 0; i < 16; ++i) m = std::max(m, std::abs(a.data()[i]));
  return m;
}
/// max |a - b| or max |a + b|, whichever is smaller: M and -M are the same motion.
double diff_up_to_sign(const Mot& a, const Mot& b) { return std::min(max_abs(a - b), max_abs(a + b)); }

Vector3d random_unit(std::mt19937& g) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Vector3d(n(g), n(g), n(g)).normalized();
}

Eigen::Isometry3d random_isometry(std::mt19937& g, double tscale = 3.0) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = Eigen::AngleAxisd(kPi * u(g), random_unit(g)).toRotationMatrix();
  iso.translation() = tscale * Vector3d(u(g), u(g), u(g));
  return iso;
}

Mot random_motor(std::mt19937& g, double tscale = 3.0) { return from_isometry(random_isometry(g, tscale)); }

/// The rotation by `angle` about `axis`, then translation by t: T R (rotor from cos/sin directly).
Mot screw(const Vector3d& axis, double angle, const Vector3d& t) {
  return motor(rotor(axis, angle), translator(t));
}

}  // namespace

TEST_CASE("transform, to_isometry and from_isometry agree with Eigen", "[ga][motor][interop]") {
  std::mt19937 g(1);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int t = 0; t < 200; ++t) {
    const Eigen::Isometry3d iso = random_isometry(g), iso2 = random_isometry(g);
    const Mot m = from_isometry(iso), m2 = from_isometry(iso2);
    const Vector3d x(u(g), u(g), u(g));
    // transform == Isometry3d * x == down(M up(x) ~M)
    CHECK((transform(m, x) - iso * x).norm() < 1e-13);
    CHECK((transform(m, x) - down(sandwich(m, up(x)))).norm() < 1e-13);
    CHECK((transform(m, x) - to_isometry(m) * x).norm() < 1e-13);
    // round trips up to sign
    CHECK(max_abs(Eigen::Matrix4d(to_isometry(m).matrix() - iso.matrix())) < 1e-14);
    CHECK(diff_up_to_sign(from_isometry(to_isometry(m)), m) < 1e-15);
    // composition: motors compose like isometries (M1 M2 applies M2 first)
    CHECK(diff_up_to_sign(m * m2, from_isometry(iso * iso2)) < 1e-14);
    CHECK((transform(m * m2, x) - iso * (iso2 * x)).norm() < 1e-13);
    // unit motor: M ~M = 1
    const auto n = m * ~m;
    CHECK(std::abs(n[0] - 1.0) < 1e-15);
    CHECK(max_abs(cast<Mot>(n) - Mot(1, 0, 0, 0, 0, 0, 0, 0)) < 1e-15);
    // inverse
    CHECK((transform(inverse(m), transform(m, x)) - x).norm() < 1e-13);
  }
  // translator and rotor pieces
  const Vector3d tv(1, -2, 0.5), x(0.3, 0.2, -0.7);
  CHECK((transform(Mot(translator(tv)), x) - (x + tv)).norm() == 0.0);
  CHECK((transform(Mot(rotor(Vector3d(0, 0, 1), kPi / 2)), Vector3d(1, 0, 0)) - Vector3d(0, 1, 0)).norm() <
        1e-15);
  // bad input
  Eigen::Isometry3d scaled = Eigen::Isometry3d::Identity();
  scaled.linear() *= 2.0;
  CHECK_THROWS_AS(from_isometry(scaled), spinmotor::Error);
  Eigen::Isometry3d mirror = Eigen::Isometry3d::Identity();
  mirror.linear()(0, 0) = -1.0;
  CHECK_THROWS_AS(from_isometry(mirror), spinmotor::Error);
}

TEST_CASE("motors are unit dual quaternions with dual = ½ t real", "[ga][motor][interop]") {
  std::mt19937 g(2);
  for (int t = 0; t < 100; ++t) {
    const Eigen::Isometry3d iso = random_isometry(g);
    const Mot m = from_isometry(iso);
    const auto [qr, qd] = to_dual_quaternion(m);
    const Eigen::Quaterniond q(iso.linear());
    const Eigen::Vector3d tr = iso.translation();
    const Eigen::Quaterniond tq(0.0, tr.x(), tr.y(), tr.z());
    const double s = qr.coeffs().dot(q.coeffs()) < 0 ? -1.0 : 1.0;
    CHECK((qr.coeffs() - s * q.coeffs()).norm() < 1e-15);
    const Eigen::Quaterniond half_tq = tq * qr;  // ½ t q_r, computed by Eigen
    CHECK((qd.coeffs() - 0.5 * half_tq.coeffs()).norm() < 1e-14);
    CHECK(from_dual_quaternion(qr, qd) == m);
    // the DQ product is the motor product
    const Mot m2 = random_motor(g);
    const auto [pr, pd] = to_dual_quaternion(m2);
    const Eigen::Quaterniond rr = qr * pr;
    Eigen::Quaterniond dd = qr * pd;
    dd.coeffs() += (qd * pr).coeffs();
    CHECK(max_abs(from_dual_quaternion(rr, dd) - m * m2) < 1e-15);
  }
}

TEST_CASE("exp(log(M)) = ±M to 1e-13 over rotation angles 1e-12 .. 2π - 1e-8, both signs",
          "[ga][motor][log]") {
  std::mt19937 g(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> angles;
  for (double a = 1e-12; a < 6.0; a *= 1.7) angles.push_back(a);
  for (double a :
       {kPi / 2, kPi - 1e-9, kPi, kPi + 1e-9, 1.5 * kPi, 2 * kPi - 1e-3, 2 * kPi - 1e-6, 2 * kPi - 1e-8})
    angles.push_back(a);
  double worst = 0.0, worst_rot_only = 0.0;
  int n = 0;
  for (double a : angles)
    for (int rep = 0; rep < 8; ++rep) {
      const Vector3d axis = random_unit(g);
      const Vector3d t = rep == 0 ? Vector3d(Vector3d::Zero()) : Vector3d(4.0 * Vector3d(u(g), u(g), u(g)));
      for (double sign : {1.0, -1.0}) {
        const Mot m = sign * screw(axis, a, t);
        const Dll b = log(m);
        const double e = diff_up_to_sign(exp(b), m);
        worst = std::max(worst, e);
        if (rep == 0) worst_rot_only = std::max(worst_rot_only, e);
        // log(M) = log(-M), and the short way round: |ω| = half the rotation angle ≤ π/2
        CHECK(max_abs(log(-m) - b) == 0.0);
        CHECK(std::hypot(b[0], b[1], b[2]) <= kPi / 2 + 1e-15);
        ++n;
      }
    }
  INFO("motors tested: " << n << ", worst rotation-only " << worst_rot_only);
  CHECK(worst <= 1e-13);
  CHECK(worst_rot_only <= 1e-15);
}

TEST_CASE("exp_lanes and transform_lanes equal exp and transform lane by lane", "[ga][motor][lanes]") {
  // Blocks of 4 generators: all with φ ≤ 1.6 (the series on lanes), and blocks with one or more lanes
  // beyond (std::sin and std::cos lane by lane), then the point transform of the result.
  std::mt19937 g(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  using L4 = detail::Lanes<4>;
  double worst_exp = 0.0, worst_point = 0.0;
  int series_blocks = 0, fallback_blocks = 0;
  for (int blk = 0; blk < 400; ++blk) {
    Dll b[4];
    Vector3d p[4];
    double phi_max = 0.0;
    for (int l = 0; l < 4; ++l) {
      const double phi = (blk % 3 == 0 && l == blk % 4) ? 1.6 + 1.5 * std::abs(u(g)) : 1.6 * std::abs(u(g));
      const Vector3d w = phi * random_unit(g), v = 5.0 * Vector3d(u(g), u(g), u(g));
      b[l] = Dll(w.z(), w.y(), w.x(), v.x(), v.y(), v.z());
      p[l] = 10.0 * Vector3d(u(g), u(g), u(g));
      phi_max = std::max(phi_max, phi);
    }
    (phi_max <= 1.6 ? series_blocks : fallback_blocks)++;
    L4 bl[6], ml[8], pl[3], ql[3];
    for (int l = 0; l < 4; ++l) {
      for (int c = 0; c < 6; ++c) bl[c][l] = b[l][static_cast<std::size_t>(c)];
      for (int c = 0; c < 3; ++c) pl[c][l] = p[l][c];
    }
    detail::exp_lanes(bl, ml);
    detail::transform_lanes(ml, pl, ql);
    for (int l = 0; l < 4; ++l) {
      const Mot e = exp(b[l]);
      Mot el;
      for (int c = 0; c < 8; ++c) el[static_cast<std::size_t>(c)] = ml[c][l];
      worst_exp = std::max(worst_exp, max_abs(el - e));
      worst_point =
          std::max(worst_point, (Vector3d(ql[0][l], ql[1][l], ql[2][l]) - transform(e, p[l])).norm());
    }
  }
  INFO("blocks on the series: " << series_blocks << ", with a lane beyond φ = 1.6: " << fallback_blocks);
  CHECK(series_blocks > 100);
  CHECK(fallback_blocks > 100);
  // one Horner chain on lanes against exp()'s two chains in φ⁴: a few ulps of the motor's size (~5)
  CHECK(worst_exp <= 1e-14);
  CHECK(worst_point <= 1e-13);
}

TEST_CASE("pure translations of length 1e-12 .. 1e6 round-trip exactly", "[ga][motor][log]") {
  std::mt19937 g(4);
  for (double len = 1e-12; len <= 1e6; len *= 10.0)
    for (int rep = 0; rep < 5; ++rep) {
      const Vector3d t = len * random_unit(g);
      const Mot m = translator(t);
      const Dll b = log(m);
      CHECK(max_abs(b - Dll(0, 0, 0, -0.5 * t.x(), -0.5 * t.y(), -0.5 * t.z())) == 0.0);
      CHECK(max_abs(exp(b) - m) == 0.0);
      CHECK(max_abs(exp(log(-m)) - m) == 0.0);
      CHECK((translation(exp(b)) - t).norm() <= 1e-15 * len);
    }
}

TEST_CASE("small rotations are not lost (Versor's exp drops |B| < 1e-4)", "[ga][motor][log]") {
  // A rotation by 2e-5 rad about z combined with a translation: exp must keep the rotation.
  for (double half : {1e-4, 5e-5, 1e-6, 1e-9}) {
    const Dll b(-half, 0, 0, 0.3, -0.2, 0.1);  // ω = (0, 0, -half): rotation by 2·half about z
    const Mot m = exp(b);
    const Eigen::Quaterniond q(Eigen::AngleAxisd(2 * half, Vector3d::UnitZ()));
    CHECK(std::abs(rotor_part(m).z() - q.z()) <= 3e-16 * std::abs(q.z()));
    CHECK(std::abs(rotor_part(m).w() - q.w()) <= 1e-16);
    CHECK(max_abs(log(m) - b) <= 1e-16);
  }
}

TEST_CASE("log of a rotation is -½θ n to full relative precision (Versor loses ~1e-6 near 0)",
          "[ga][motor][log]") {
  std::mt19937 g(10);
  for (double angle : {3.0, 1.0, 1e-3, 1e-6, 1e-9, 1e-12, 1e-200}) {
    const Vector3d n = random_unit(g);
    const Dll b = log(Mot(rotor(n, angle)));
    const Vector3d w(b[2], b[1], b[0]);  // ω = (e23, e31, e12) components
    INFO("angle " << angle);
    CHECK((w + 0.5 * angle * n).norm() <= 1e-15 * 0.5 * angle);  // a few ulp
    CHECK(max_abs(Dll(0, 0, 0, b[3], b[4], b[5])) == 0.0);
  }
}

TEST_CASE("log(exp(B)) = B for rotation angles below π, and screws", "[ga][motor][log]") {
  std::mt19937 g(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int t = 0; t < 2000; ++t) {
    // half-angle |ω| from 1e-10 to π/2 - 1e-6 (rotation angle < π)
    const double half =
        t % 4 == 0 ? 1e-10 * std::pow(1e8, 0.5 * (u(g) + 1)) : (kPi / 2 - 1e-6) * std::abs(u(g));
    const Vector3d w = half * random_unit(g);
    const Vector3d v = 5.0 * Vector3d(u(g), u(g), u(g));
    const Dll b(w.z(), w.y(), w.x(), v.x(), v.y(), v.z());
    worst = std::max(worst, max_abs(log(exp(b)) - b) / std::max(1.0, max_abs(b)));
  }
  CHECK(worst <= 1e-13);
  // exp of a pure rotation generator is the rotor; exp of a translation generator the translator
  const Vector3d axis(1, 2, 2);
  const Mot r = exp(Dll(0.5 * line(Vector3d::Zero(), axis)));  // ½θ L* with θ = 1
  // (two code paths for the same closed form: equal up to rounding, ≤ 2 ulp of the O(1) components;
  // bit-equality held on one CPU and not on another, where -march=native contracts different FMAs)
  CHECK(max_abs(r - Mot(rotor(axis, 1.0))) <= 4.5e-16);
  // rotor exp/log
  const Biv bv(0.1, -0.4, 0.7);
  CHECK(max_abs(Mot(exp(bv)) - exp(Dll(bv))) <= 4.5e-16);
  CHECK(std::abs(log(exp(bv))[1] - bv[1]) < 1e-15);
  CHECK(std::abs(log(-exp(bv))[2] - bv[2]) < 1e-15);
}

TEST_CASE("sqrt(M) sqrt(M) = M and sclerp endpoints", "[ga][motor][sqrt]") {
  std::mt19937 g(6);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int t = 0; t < 500; ++t) {
    const double angle = t < 10 ? kPi : 2 * kPi * std::abs(u(g));  // includes 180°
    const Mot m = screw(random_unit(g), angle, 4.0 * Vector3d(u(g), u(g), u(g)));
    const Mot s = sqrt(m);
    const Mot expect = std::signbit(m[0]) ? -m : m;  // the same motion, scalar part ≥ 0
    worst = std::max(worst, max_abs(s * s - expect));
    CHECK(max_abs(s - exp(0.5 * log(m))) < 1e-13);  // the half-way motor along the log
  }
  CHECK(worst < 1e-14);
  const Mot tr = translator(Vector3d(2, 4, -6));
  CHECK(max_abs(sqrt(tr) - Mot(translator(Vector3d(1, 2, -3)))) == 0.0);

  for (int t = 0; t < 100; ++t) {
    const Mot a = random_motor(g), b = random_motor(g);
    CHECK(max_abs(sclerp(a, b, 0.0) - a) == 0.0);
    CHECK(diff_up_to_sign(sclerp(a, b, 1.0), b) < 1e-14);
    const Mot h = sclerp(a, b, 0.5);
    CHECK(diff_up_to_sign(h * ~a * h, b) < 1e-13);  // the mid point: (h ~a)² = b ~a
  }
}

TEST_CASE("normalize makes M ~M = 1", "[ga][motor]") {
  std::mt19937 g(7);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  for (int t = 0; t < 100; ++t) {
    Mot m = random_motor(g);
    for (auto& v : m.c) v += u(g);  // off the motor manifold
    const auto n = normalize(m) * ~normalize(m);
    CHECK(std::abs(n[0] - 1.0) < 1e-15);
    CHECK(max_abs(cast<Mot>(n) - Mot(1, 0, 0, 0, 0, 0, 0, 0)) < 1e-14);
  }
  CHECK_THROWS_AS(normalize(Mot(0, 0, 0, 0, 1, 2, 3, 0)), spinmotor::Error);
  CHECK_THROWS_AS(log(Mot(0, 0, 0, 0, 1, 2, 3, 0)), spinmotor::Error);
}

TEST_CASE("blend: weight 1 reproduces, PivotLog is frame invariant, Linear survives antipodes",
          "[ga][blend]") {
  std::mt19937 g(8);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int t = 0; t < 50; ++t) {
    std::array<Mot, 4> m;
    for (auto& x : m) x = random_motor(g);
    m[2] = -m[2];  // a negative scalar part must not matter
    for (std::size_t k = 0; k < 4; ++k) {
      std::array<double, 4> w{};
      w[k] = 1.0;
      CHECK(diff_up_to_sign(blend(m, w, Blend::Log), m[k]) < 1e-13);
      CHECK(max_abs(blend(m, w, Blend::PivotLog) - m[k]) < 1e-15);
      CHECK(diff_up_to_sign(blend(m, w, Blend::DLB), m[k]) < 1e-15);
    }
    // PivotLog: blend(A M_i B) = A blend(M_i) B
    std::array<double, 4> w{u(g), u(g), u(g), u(g)};
    const double sum = w[0] + w[1] + w[2] + w[3];
    for (double& x : w) x /= sum;
    const Mot a = random_motor(g), b = random_motor(g);
    std::array<Mot, 4> am, mb;
    for (std::size_t i = 0; i < 4; ++i) am[i] = a * m[i], mb[i] = m[i] * b;
    const Mot ref = blend(m, w, Blend::PivotLog);
    CHECK(diff_up_to_sign(blend(am, w, Blend::PivotLog), a * ref) < 1e-12);
    CHECK(diff_up_to_sign(blend(mb, w, Blend::PivotLog), ref * b) < 1e-12);
    // precomputed logs give the same blend
    const std::array<Dll, 4> logs{log(m[0]), log(m[1]), log(m[2]), log(m[3])};
    CHECK(max_abs(blend_logs(logs, w) - blend(m, w, Blend::Log)) < 1e-15);
    // five motors: four lanes read straight from the motors, then a partly filled chunk
    const std::array<Mot, 5> m5{m[0], m[1], m[2], m[3], a};
    const std::array<double, 5> w5{0.5 * w[0], 0.5 * w[1], 0.5 * w[2], 0.5 * w[3], 0.5};
    const std::array<Dll, 5> logs5{logs[0], logs[1], logs[2], logs[3], log(a)};
    CHECK(max_abs(blend_logs(logs5, w5) - blend(m5, w5, Blend::Log)) < 1e-15);
    // a zero weight keeps its motor out of the arithmetic, even one that is not a motor
    const std::array<Mot, 4> broken{m[0], Mot(0, 0, 0, 0, 1, 2, 3, 0), m[2], m[3]};
    const std::array<double, 4> skip{w[0] + w[1], 0.0, w[2], w[3]};
    const std::array<Dll, 4> logs_skip{logs[0], Dll(), logs[2], logs[3]};
    CHECK(max_abs(blend_logs(logs_skip, skip) - blend(broken, skip, Blend::Log)) < 1e-15);
    // Log blend of two motors is the paper's exp((1-α) B1 + α B2)
    const std::array<Mot, 2> two{m[0], m[1]};
    const std::array<double, 2> w2{0.3, 0.7};
    CHECK(max_abs(blend(two, w2, Blend::Log) - exp(0.3 * log(m[0]) + 0.7 * log(m[1]))) < 1e-15);
    // Linear is DLB: compare with an Eigen dual-quaternion implementation
    Eigen::Quaterniond r0, d0;
    Eigen::Vector4d rs = Eigen::Vector4d::Zero(), ds = Eigen::Vector4d::Zero();
    const std::size_t piv = static_cast<std::size_t>(std::max_element(w.begin(), w.end()) - w.begin());
    const Eigen::Quaterniond rp = to_dual_quaternion(m[piv]).first;
    for (std::size_t i = 0; i < 4; ++i) {
      const auto [ri, di] = to_dual_quaternion(m[i]);
      const double s = ri.coeffs().dot(rp.coeffs()) < 0 ? -w[i] : w[i];
      rs += s * ri.coeffs();
      ds += s * di.coeffs();
    }
    const double rn = rs.norm();
    rs /= rn;
    ds /= rn;
    ds -= rs.dot(ds) * rs;  // make the dual part orthogonal to the real part
    r0.coeffs() = rs;
    d0.coeffs() = ds;
    CHECK(max_abs(blend(m, w, Blend::DLB) - from_dual_quaternion(r0, d0)) < 1e-14);
  }
  // Antipodal inputs: M and -M, and 180° rotations about opposite axes (the same motion, but on
  // opposite sides of the log's cut locus), never give NaN. Log averages the two logs ±(π/2) ẑ to a
  // pure translation there, the known limitation of the paper's blend that PivotLog and Linear avoid.
  const Mot m = screw(Vector3d(0, 0, 1), kPi, Vector3d(1, 2, 3));
  const Mot mo = screw(Vector3d(0, 0, -1), kPi, Vector3d(1, 2, 3));
  const std::array<double, 2> half{0.5, 0.5};
  for (const auto& pair : {std::array<Mot, 2>{m, -m}, std::array<Mot, 2>{m, mo}}) {
    for (Blend mode : {Blend::DLB, Blend::Log, Blend::PivotLog}) {
      const Mot r = blend(pair, half, mode);
      INFO("mode " << int(mode) << " r = " << r);
      CHECK(std::isfinite(max_abs(r)));
      if (mode != Blend::Log || pair[1] == -m) CHECK(diff_up_to_sign(r, m) < 1e-14);
    }
  }
  CHECK(
      (rotor_part(blend(std::array<Mot, 2>{m, mo}, half, Blend::Log)).coeffs() - Eigen::Vector4d(1, 0, 0, 0))
          .norm() < 1e-15);
  // bad input
  const std::array<Mot, 2> two{m, m};
  const std::array<double, 1> one{1.0};
  CHECK_THROWS_AS(blend(two, one, Blend::Log), spinmotor::Error);
  const std::array<double, 2> cancel{1.0, -1.0};
  CHECK_THROWS_AS(blend(two, cancel, Blend::DLB), spinmotor::Error);
  const std::array<double, 2> nan{0.5, std::nan("")};
  for (Blend mode : {Blend::DLB, Blend::Log, Blend::PivotLog})
    CHECK_THROWS_AS(blend(two, nan, mode), spinmotor::Error);
}

TEST_CASE("plane, sphere and line constructors", "[ga][constructors]") {
  std::mt19937 g(9);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int t = 0; t < 100; ++t) {
    const Vector3d n(u(g), u(g), u(g)), c(u(g), u(g), u(g)), x(u(g), u(g), u(g)), p(u(g), u(g), u(g));
    const double d = u(g), r = std::abs(u(g));
    // plane: up(x)·π = n̂·x - d, the signed distance
    CHECK(scalar(up(x), plane(n, d)) == Approx(n.normalized().dot(x) - d).margin(1e-13));
    // sphere: up(x)·σ = ½(r² - |x-c|²), zero on the sphere
    CHECK(scalar(up(x), sphere(c, r)) == Approx(0.5 * (r * r - (x - c).squaredNorm())).margin(1e-12));
    CHECK(std::abs(scalar(up(c + r * random_unit(g)), sphere(c, r))) < 1e-12);
    // line: points of the line lie on it (X ∧ L = 0), and exp(½θ L*) rotates by θ about it
    const Vector3d dir = random_unit(g);
    const Dll l = line(p, 2.0 * dir);
    const Lin L = undual(l);
    CHECK(max_abs(cast<Mot>(Sca(0.0))) == 0.0);
    const auto on = up(p + u(g) * dir) ^ L;
    for (double v : on.c) CHECK(std::abs(v) < 1e-12);
    const double th = u(g);
    const Mot rot = exp(Dll(0.5 * th * l));
    const Eigen::Isometry3d iso =
        Eigen::Translation3d(p) * Eigen::AngleAxisd(th, dir) * Eigen::Translation3d(-p);
    CHECK((transform(rot, x) - iso * x).norm() < 1e-12);
    // a transformed dual plane / sphere / line is the same object moved
    const Mot m = random_motor(g);
    CHECK(max_abs(Mot(sandwich(m, l)) - Mot(line(transform(m, p), to_isometry(m).linear() * dir))) < 1e-13);
    CHECK(max_abs(Mot(Dll(0, 0, 0, 0, 0, 0))) == 0.0);
    const Sph s2 = sandwich(m, sphere(c, r));
    CHECK((down(s2) - transform(m, c)).norm() < 1e-12);
  }
  CHECK_THROWS_AS(plane(Vector3d::Zero(), 1.0), spinmotor::Error);
  CHECK_THROWS_AS(line(Vector3d::Zero(), Vector3d::Zero()), spinmotor::Error);
}

}  // namespace test_ga_motor

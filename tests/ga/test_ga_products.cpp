// Typed CGA products against a slow dense 32-component reference written here, in the orthonormal
// basis (e1, e2, e3, e+, e-) with e+² = 1, e-² = -1, o = ½(e- - e+), inf = e- + e+. The reference
// multiplies blades by sorting vector index lists (counting swaps, contracting equal neighbours with
// the metric), so it shares no code with ga/algebra.hpp.
#include <array>
#include <catch2/catch.hpp>
#include <random>
#include <spinmotor/ga.hpp>
#include <tuple>
#include <vector>

namespace test_ga_products {

using namespace spinmotor::ga;

namespace {

// ---- dense reference ---------------------------------------------------------------------------
constexpr double kMetric[5] = {1.0, 1.0, 1.0, 1.0, -1.0};  // e1 e2 e3 e+ e-

struct Dense {
  std::array<double, 32> c{};
};

// e_a e_b = sign e_(a xor b): concatenate index lists, bubble sort, contract equal neighbours.
double blade_product_sign(unsigned a, unsigned b) {
  std::vector<int> v;
  for (int i = 0; i < 5; ++i)
    if ((a >> i) & 1u) v.push_back(i);
  for (int i = 0; i < 5; ++i)
    if ((b >> i) & 1u) v.push_back(i);
  double sign = 1.0;
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t k = 0; k + 1 < v.size(); ++k) {
      if (v[k] > v[k + 1]) {
        std::swap(v[k], v[k + 1]);
        sign = -sign;
        changed = true;
      } else if (v[k] == v[k + 1]) {
        sign *= kMetric[v[k]];
        v.erase(v.begin() + static_cast<long>(k), v.begin() + static_cast<long>(k) + 2);
        changed = true;
        break;
      }
    }
  }
  return sign;
}

int popcount(unsigned m) { return __builtin_popcount(m); }

enum class P { Gp, Op, Lc, Sc };

Dense product(P p, const Dense& a, const Dense& b) {
  Dense r;
  for (unsigned i = 0; i < 32; ++i)
    for (unsigned j = 0; j < 32; ++j) {
      if (a.c[i] == 0.0 || b.c[j] == 0.0) continue;
      if (p == P::Op && (i & j) != 0) continue;   // orthogonal blades: e_A ∧ e_B = e_A e_B if disjoint
      if (p == P::Lc && (i & ~j) != 0) continue;  // e_A ⌋ e_B = e_A e_B if A ⊆ B
      if (p == P::Sc && (i ^ j) != 0) continue;   // scalar part
      r.c[i ^ j] += blade_product_sign(i, j) * a.c[i] * b.c[j];
    }
  return r;
}

Dense add(const Dense& a, const Dense& b, double s = 1.0) {
  Dense r;
  for (int i = 0; i < 32; ++i)
    r.c[static_cast<std::size_t>(i)] =
        a.c[static_cast<std::size_t>(i)] + s * b.c[static_cast<std::size_t>(i)];
  return r;
}

// The null-basis vectors in the orthonormal basis.
Dense null_vector(int v) {
  Dense d;
  if (v < 3) {
    d.c[1u << v] = 1.0;
  } else if (v == 3) {  // o = ½(e- - e+)
    d.c[16] = 0.5;
    d.c[8] = -0.5;
  } else {  // inf = e- + e+
    d.c[16] = 1.0;
    d.c[8] = 1.0;
  }
  return d;
}

// The null-basis blade with mask m: outer product of its vectors in increasing bit order.
Dense null_blade(unsigned m) {
  Dense d;
  d.c[0] = 1.0;
  for (int v = 0; v < 5; ++v)
    if ((m >> v) & 1u) d = product(P::Op, d, null_vector(v));
  return d;
}

template <class T>
Dense to_dense(const T& x) {
  Dense d;
  for (std::size_t i = 0; i < T::size; ++i) {
    const Basis bb = T::basis[i];
    const Dense bl = null_blade(mask_of(bb));
    d = add(d, bl, orientation_of(bb) * x.c[i]);
  }
  return d;
}

double max_diff(const Dense& a, const Dense& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < 32; ++i) m = std::max(m, std::abs(a.c[i] - b.c[i]));
  return m;
}

template <class T>
T random_mv(std::mt19937& g) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  T x;
  for (auto& v : x.c) v = u(g);
  return x;
}

using Named = std::tuple<Sca, Vec, Biv, Tri, Pss, Pnt, Pln, Lin, Dll, Drv, Rot, Trs, Mot, Par, Cir>;
constexpr std::size_t kNamed = std::tuple_size_v<Named>;

struct PairStats {
  double worst = 0.0;  // largest |typed - dense| over all pairs, trials and products
  int blades_never_nonzero = 0;
  int checked_pairs = 0;
};

// For one product: compare with the dense reference and record which result blades were ever non-zero.
template <class R>
void check_one(const R& typed, const Dense& ref, std::array<double, 32>& seen, double& worst) {
  worst = std::max(worst, max_diff(to_dense(typed), ref));
  for (std::size_t k = 0; k < R::size; ++k) seen[k] = std::max(seen[k], std::abs(typed.c[k]));
}

template <class A, class B>
void check_pair(std::mt19937& g, int trials, PairStats& st) {
  using RG = decltype(gp(A{}, B{}));
  using RO = decltype(op(A{}, B{}));
  using RL = decltype(lc(A{}, B{}));
  std::array<double, 32> sg{}, so{}, sl{};
  for (int t = 0; t < trials; ++t) {
    const A a = random_mv<A>(g);
    const B b = random_mv<B>(g);
    const Dense da = to_dense(a), db = to_dense(b);
    check_one(gp(a, b), product(P::Gp, da, db), sg, st.worst);
    check_one(op(a, b), product(P::Op, da, db), so, st.worst);
    check_one(lc(a, b), product(P::Lc, da, db), sl, st.worst);
    st.worst = std::max(st.worst, std::abs(scalar(a, b) - product(P::Sc, da, db).c[0]));
  }
  // Minimality: every blade of each result type is non-zero for some random input.
  for (std::size_t k = 0; k < RG::size; ++k) st.blades_never_nonzero += sg[k] < 1e-6;
  for (std::size_t k = 0; k < RO::size; ++k) st.blades_never_nonzero += so[k] < 1e-6;
  for (std::size_t k = 0; k < RL::size; ++k) st.blades_never_nonzero += sl[k] < 1e-6;
  ++st.checked_pairs;
}

template <std::size_t... I, std::size_t... J>
void check_all_pairs(std::mt19937& g, int trials, PairStats& st, std::index_sequence<I...>) {
  (
      [&]<std::size_t i>() {
        [&]<std::size_t... j>(std::index_sequence<j...>) {
          (check_pair<std::tuple_element_t<i, Named>, std::tuple_element_t<j, Named>>(g, trials, st), ...);
        }
        (std::make_index_sequence<kNamed>{});
      }.template operator()<I>(),
      ...);
}

}  // namespace

TEST_CASE("typed gp, op, lc, scalar equal the dense reference for all pairs of named types",
          "[ga][products]") {
  std::mt19937 g(12345);
  PairStats st;
  check_all_pairs(g, 6, st, std::make_index_sequence<kNamed>{});
  CHECK(st.checked_pairs == static_cast<int>(kNamed * kNamed));
  CHECK(st.worst < 1e-13);
  CHECK(st.blades_never_nonzero == 0);  // result types hold no blade that is always zero
}

TEST_CASE("product result types are the named types", "[ga][products]") {
  STATIC_REQUIRE(std::is_same_v<decltype(Mot{} * Mot{}), Mot>);
  STATIC_REQUIRE(std::is_same_v<decltype(Rot{} * Rot{}), Rot>);
  STATIC_REQUIRE(std::is_same_v<decltype(Trs{} * Rot{}), Mot>);
  STATIC_REQUIRE(std::is_same_v<decltype(Trs{} * Trs{}), Trs>);
  STATIC_REQUIRE(std::is_same_v<decltype(Vec{} * Vec{}), Rot>);
  STATIC_REQUIRE(std::is_same_v<decltype(Vec{} ^ Vec{}), Biv>);
  STATIC_REQUIRE(std::is_same_v<decltype(Pnt{} * Pnt{}), Bst>);
  STATIC_REQUIRE(std::is_same_v<decltype(Pnt{} ^ Pnt{}), Par>);
  STATIC_REQUIRE(std::is_same_v<decltype(Pnt{} ^ Pnt{} ^ Pnt{}), Cir>);
  STATIC_REQUIRE(std::is_same_v<decltype((Pnt{} ^ Vec{}) ^ Drv{}), decltype((Pnt{} ^ Vec{}) ^ Drv{})>);
  STATIC_REQUIRE(std::is_same_v<decltype(dual(Lin{})), Dll>);
  STATIC_REQUIRE(std::is_same_v<decltype(undual(Dll{})), Lin>);
  STATIC_REQUIRE(std::is_same_v<decltype(lc(Vec{}, Biv{})), Vec>);
  STATIC_REQUIRE(std::is_same_v<decltype(Dll{} + Dll{}), Dll>);
  STATIC_REQUIRE(decltype(Rot{} + Trs{})::size == 7);  // no e123∞: not a Mot
  STATIC_REQUIRE(std::is_same_v<decltype(Pnt{} * MV<blade::o>{}), decltype(Pnt{} * MV<blade::o>{})>);
  STATIC_REQUIRE(Mot::size == 8 && Dll::size == 6 && Rot::size == 4 && Pnt::size == 5);
  STATIC_REQUIRE(sizeof(Rot) == 4 * sizeof(double) && sizeof(Mot) == 8 * sizeof(double));
  // o o = inf inf = 0: the product of two null basis vectors of the same kind has no blades at all.
  STATIC_REQUIRE(decltype(MV<blade::o>{} * MV<blade::o>{})::size == 0);
}

TEST_CASE("unary operations, dual and grade selection match the dense reference", "[ga][products]") {
  std::mt19937 g(7);
  // The pseudoscalar is I = e1 e2 e3 e+ e- = o ∧ e1 ∧ e2 ∧ e3 ∧ inf, I² = -1.
  Dense I;
  I.c[31] = 1.0;
  CHECK(max_diff(to_dense(Pss{1.0}), I) == 0.0);
  CHECK(max_diff(to_dense((MV<blade::o>{1.0} ^ Tri{1.0}) ^ MV<blade::ni>{1.0}), I) < 1e-15);
  CHECK(scalar(Pss{1.0}, Pss{1.0}) == -1.0);
  Dense Iinv = I;
  Iinv.c[31] = -1.0;
  for (int t = 0; t < 20; ++t) {
    const auto a = random_mv<Bst>(g);
    const auto m = random_mv<Mot>(g);
    const auto c = random_mv<Cir>(g);
    const auto p = random_mv<Pnt>(g);
    // reverse: grade k times (-1)^{k(k-1)/2}; in the dense basis that is the same rule
    auto dense_grade_sign = [](const Dense& d, auto sign) {
      Dense r;
      for (unsigned i = 0; i < 32; ++i) r.c[i] = sign(popcount(i)) * d.c[i];
      return r;
    };
    auto rev = [](int k) { return (k * (k - 1) / 2) % 2 ? -1.0 : 1.0; };
    auto inv = [](int k) { return k % 2 ? -1.0 : 1.0; };
    auto cnj = [](int k) { return (k * (k + 1) / 2) % 2 ? -1.0 : 1.0; };
    CHECK(max_diff(to_dense(reverse(c)), dense_grade_sign(to_dense(c), rev)) < 1e-15);
    CHECK(max_diff(to_dense(~m), dense_grade_sign(to_dense(m), rev)) < 1e-15);
    CHECK(max_diff(to_dense(involute(p)), dense_grade_sign(to_dense(p), inv)) < 1e-15);
    CHECK(max_diff(to_dense(conjugate(c)), dense_grade_sign(to_dense(c), cnj)) < 1e-15);
    CHECK(max_diff(to_dense(dual(c)), product(P::Gp, to_dense(c), Iinv)) < 1e-14);
    CHECK(max_diff(to_dense(undual(dual(c))), to_dense(c)) < 1e-14);
    CHECK(max_diff(to_dense(dual(undual(m))), to_dense(m)) < 1e-14);
    // grade selection
    const auto a2 = grade<2>(a);
    STATIC_REQUIRE(std::is_same_v<decltype(a2), const Par>);
    CHECK(max_diff(to_dense(a2 + Sca{a[0]}), to_dense(a)) < 1e-15);
    CHECK(grade<0>(a)[0] == a[0]);
    // sums, differences, scalar multiples
    CHECK(max_diff(to_dense(p - 2.0 * c), add(to_dense(p), to_dense(c), -2.0)) < 1e-14);
    // norm2 is <a ~a>_0
    CHECK(norm2(m) == Approx(product(P::Sc, to_dense(m), to_dense(~m)).c[0]).margin(1e-14));
  }
}

TEST_CASE("the null metric: o·inf = -1, up(x)·up(y) = -½|x-y|², down(up(x)) = x", "[ga][metric]") {
  const MV<blade::o> o{1.0};
  const MV<blade::ni> inf{1.0};
  CHECK(scalar(o, inf) == -1.0);
  CHECK(scalar(inf, o) == -1.0);
  CHECK(scalar(o, o) == 0.0);
  CHECK(scalar(inf, inf) == 0.0);
  CHECK(scalar(Vec(1, 0, 0), Vec(1, 0, 0)) == 1.0);
  std::mt19937 g(3);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  for (int t = 0; t < 100; ++t) {
    const Eigen::Vector3d x(u(g), u(g), u(g)), y(u(g), u(g), u(g));
    CHECK(scalar(up(x), up(y)) == Approx(-0.5 * (x - y).squaredNorm()).epsilon(1e-13));
    CHECK(std::abs(scalar(up(x), up(x))) < 1e-12);             // null
    CHECK(scalar(up(x), inf) == -1.0);                         // normalised: -X·inf = 1
    CHECK((down(up(x)) - x).norm() == 0.0);                    // exact
    CHECK((down(3.5 * up(x)) - x).norm() < 1e-14 * x.norm());  // weighted point
  }
  CHECK_THROWS_AS(down(Pnt(1, 2, 3, 0, 4)), spinmotor::Error);
}

TEST_CASE("Rot is the quaternion algebra: i = e32, j = e13, k = e21, and agrees with Eigen",
          "[ga][quaternion]") {
  const Quat one(1, 0, 0, 0), i(0, 1, 0, 0), j(0, 0, 1, 0), k(0, 0, 0, 1);
  CHECK(i == cast<Quat>(MV<blade::e32>{1.0}));
  CHECK(j == cast<Quat>(MV<blade::e13>{1.0}));
  CHECK(k == cast<Quat>(MV<blade::e21>{1.0}));
  CHECK(i * i == -one);
  CHECK(j * j == -one);
  CHECK(k * k == -one);
  CHECK(i * j == k);
  CHECK(j * k == i);
  CHECK(k * i == j);
  CHECK(i * j * k == -one);
  // R = cos(θ/2) - sin(θ/2) e12 (rotation by θ about z) is cos(θ/2) + sin(θ/2) k.
  const double th = 0.8;
  const Rot r = cast<Rot>(Sca(std::cos(th / 2)) - std::sin(th / 2) * MV<blade::e12>{1.0});
  CHECK(r.w() == std::cos(th / 2));
  CHECK(r.z() == std::sin(th / 2));
  CHECK(r.x() == 0.0);
  CHECK(r.y() == 0.0);

  std::mt19937 g(11);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int t = 0; t < 100; ++t) {
    const Eigen::Quaterniond p = Eigen::Quaterniond(n(g), n(g), n(g), n(g)).normalized();
    const Eigen::Quaterniond q = Eigen::Quaterniond(n(g), n(g), n(g), n(g)).normalized();
    const Eigen::Vector3d v(n(g), n(g), n(g));
    const Quat gp_ = from_quaterniond(p) * from_quaterniond(q);  // the geometric product ...
    const Eigen::Quaterniond pq = p * q;                         // ... is the Hamilton product
    CHECK((gp_.coeffs() - Eigen::Vector4d(pq.w(), pq.x(), pq.y(), pq.z())).cwiseAbs().maxCoeff() < 1e-15);
    // R x ~R (the GA sandwich on a vector) = q v q̄ = Eigen's q * v
    const Eigen::Vector3d ga_rot = to_eigen(sandwich(from_quaterniond(p), vec(v)));
    CHECK((ga_rot - p * v).norm() < 1e-14 * v.norm());
    CHECK((rotate(from_quaterniond(p), v) - p * v).norm() < 1e-14 * v.norm());
    // conjugate = reverse, norm, inverse
    const Quat a = 2.5 * from_quaterniond(p);
    CHECK((conj(a).coeffs() - 2.5 * Eigen::Vector4d(p.w(), -p.x(), -p.y(), -p.z())).norm() < 1e-15);
    CHECK(norm2(a) == Approx(6.25).epsilon(1e-14));
    CHECK(((a * inverse(a)) - one).coeffs().norm() < 1e-15);
    // imaginary quaternions
    CHECK(imaginary(v).vec() == v);
    CHECK(imaginary(v).w() == 0.0);
    CHECK((to_quaterniond(from_quaterniond(p)).coeffs() - p.coeffs()).norm() == 0.0);
    // rotor from axis-angle = Eigen::AngleAxisd
    const double angle = 3.0 * n(g);
    const Eigen::Vector3d axis(n(g), n(g), n(g));
    const Eigen::Quaterniond e(Eigen::AngleAxisd(angle, axis.normalized()));
    CHECK((rotor(axis, angle).coeffs() - Eigen::Vector4d(e.w(), e.x(), e.y(), e.z())).norm() < 1e-15);
  }
  CHECK_THROWS_AS(rotor(Eigen::Vector3d::Zero(), 1.0), spinmotor::Error);
  CHECK(rotor(Eigen::Vector3d::Zero(), 0.0) == one);
}

}  // namespace test_ga_products

#pragma once
// spinmotor/ga/algebra.hpp — the compile-time core of CGA G(4,1) (paper §II.B).
//
// Basis vectors e1, e2, e3 (Euclidean, square +1) and the null pair o (origin), inf (infinity) with
// o·o = inf·inf = 0, o·inf = -1. A basis blade is a 5-bit mask over (e1, e2, e3, o, inf) = bits 0..4
// and denotes the outer product of its vectors in that order (e.g. 0b10011 = e1 ∧ e2 ∧ inf). Because
// o and inf are the two highest bits, every blade is (Euclidean blade) ∧ (one of 1, o, inf, o∧inf),
// and the geometric product of two blades is at most two blades (o inf = -1 + o∧inf); see
// detail::blade_gp below, which is the whole metric of the algebra.
//
// A multivector type MV<B...> is a compile-time list of *basis elements*: a blade mask plus an
// orientation bit (kNeg), so that a type may store e.g. e31 = -e13 or the quaternion units
// i = e32, j = e13, k = e21 directly. The coefficients are a std::array<double, N> (no heap).
// Products (products.hpp) compute, at compile time, the set of blades that can be non-zero and return
// the *canonical* type for that set: a named type of types.hpp when one is registered for that set,
// otherwise the blades in increasing mask order with positive orientation.
#include <Eigen/Core>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

// Everything in ga is small and meant to be inlined into straight-line code; the product bodies are
// forced inline so that the per-term coefficients (±1) fold into adds and subtracts.
// SPINMOTOR_GA_PURE marks the value-returning ones: discarding a product is always a mistake.
#if defined(__GNUC__)
#define SPINMOTOR_GA_INLINE [[gnu::always_inline]] inline
#define SPINMOTOR_GA_PURE [[nodiscard, gnu::always_inline]] inline
#else
#define SPINMOTOR_GA_INLINE inline
#define SPINMOTOR_GA_PURE [[nodiscard]] inline
#endif

namespace spinmotor::ga {

/// A basis element: bits 0..4 the blade mask, bit 7 set when the element is the negated blade.
using Basis = std::uint8_t;
inline constexpr Basis kNeg = 0x80;

/// The blade mask (bits 0..4) of a basis element.
[[nodiscard]] constexpr unsigned mask_of(Basis b) { return b & 31u; }
/// +1 or -1: the orientation of a basis element relative to its blade.
[[nodiscard]] constexpr int orientation_of(Basis b) { return (b & kNeg) ? -1 : 1; }
/// The grade of a blade mask (number of vectors in it).
[[nodiscard]] constexpr int grade_of(unsigned mask) { return std::popcount(mask); }

/// Named basis elements. `o` is the origin, `ni` is infinity (inf); e31 = -e13, e32 = -e23, e21 = -e12.
namespace blade {
inline constexpr Basis s = 0, e1 = 1, e2 = 2, e3 = 4, o = 8, ni = 16;
inline constexpr Basis e12 = 3, e13 = 5, e23 = 6, e123 = 7;
inline constexpr Basis e31 = kNeg | e13, e32 = kNeg | e23, e21 = kNeg | e12;
inline constexpr Basis e1o = 9, e2o = 10, e3o = 12, e1ni = 17, e2ni = 18, e3ni = 20, oni = 24;
inline constexpr Basis e12ni = 19, e13ni = 21, e23ni = 22, e31ni = kNeg | 21, e123ni = 23;
inline constexpr Basis e1oni = 25, e2oni = 26, e3oni = 28;
inline constexpr Basis oe1ni = kNeg | 25, oe2ni = kNeg | 26, oe3ni = kNeg | 28;  // o∧e_i∧inf = -e_i∧o∧inf
/// The unit pseudoscalar I = o ∧ e1 ∧ e2 ∧ e3 ∧ inf = e1 e2 e3 e+ e- (I² = -1); as a mask: -e123∧o∧inf.
inline constexpr Basis I5 = kNeg | 31;
}  // namespace blade

namespace detail {

/// Sign of reordering the vectors of e_a e_b into increasing order (pairs i in a, j in b with i > j).
[[nodiscard]] constexpr int reorder_sign(unsigned a, unsigned b) {
  int swaps = 0;
  for (a >>= 1; a != 0; a >>= 1) swaps += std::popcount(a & b);
  return (swaps & 1) ? -1 : 1;
}

/// At most two signed blades: the result of multiplying two basis blades.
struct Terms {
  int n = 0;
  int coef[2] = {0, 0};
  unsigned mask[2] = {0, 0};
  constexpr void push(int c, unsigned m) {
    coef[n] = c;
    mask[n] = m;
    ++n;
  }
};

/// The geometric product of two basis blades (masks) in the null basis.
/// a = A_E ∧ A_N with A_E Euclidean and A_N ∈ {1, o, inf, E = o∧inf} (o, inf anticommute with e_i, E
/// commutes with them), so  a b = (-1)^{|A_N||B_E|} (A_E B_E)(A_N B_N)  and A_N B_N is read from the
/// 4×4 table of the null pair: o o = inf inf = 0, o inf = -1 + E, inf o = -1 - E, o E = o, E o = -o,
/// E inf = inf, inf E = -inf, E E = 1.
[[nodiscard]] constexpr Terms blade_gp(unsigned a, unsigned b) {
  const unsigned ae = a & 7u, an = a >> 3, be = b & 7u, bn = b >> 3;
  int sign = reorder_sign(ae, be);
  if ((std::popcount(an) * std::popcount(be)) & 1) sign = -sign;
  const unsigned e = ae ^ be;
  Terms t;
  auto put = [&](int c, unsigned n) { t.push(sign * c, e | (n << 3)); };
  constexpr unsigned one = 0, O = 1, N = 2, E = 3;
  if (an == one) {
    put(1, bn);
  } else if (bn == one) {
    put(1, an);
  } else if (an == O && bn == N) {
    put(-1, one), put(1, E);
  } else if (an == O && bn == E) {
    put(1, O);
  } else if (an == N && bn == O) {
    put(-1, one), put(-1, E);
  } else if (an == N && bn == E) {
    put(-1, N);
  } else if (an == E && bn == O) {
    put(-1, O);
  } else if (an == E && bn == N) {
    put(1, N);
  } else if (an == E && bn == E) {
    put(1, one);
  }  // o o = inf inf = 0
  return t;
}

/// Which bilinear product of blades.
enum class Op { Geometric, Outer, LeftContraction, RightContraction, Scalar };

/// A bilinear product of two basis blades, as signed blades.
[[nodiscard]] constexpr Terms blade_product(Op op, unsigned a, unsigned b) {
  if (op == Op::Outer) {  // metric-free: e_a ∧ e_b = sign · e_(a|b), zero when they share a vector
    Terms t;
    if ((a & b) == 0) t.push(reorder_sign(a, b), a | b);
    return t;
  }
  const Terms g = blade_gp(a, b);
  if (op == Op::Geometric) return g;
  // For blades, A⌋B = <AB>_{|B|-|A|}, A⌊B = <AB>_{|A|-|B|}, A*B = <AB>_0 (null-basis blades are blades).
  int keep = 0;
  if (op == Op::LeftContraction) keep = grade_of(b) - grade_of(a);
  if (op == Op::RightContraction) keep = grade_of(a) - grade_of(b);
  Terms t;
  if (keep < 0) return t;
  for (int k = 0; k < g.n; ++k)
    if (grade_of(g.mask[k]) == keep) t.push(g.coef[k], g.mask[k]);
  return t;
}

template <std::size_t N>
[[nodiscard]] constexpr bool masks_unique(const std::array<Basis, N>& b) {
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = i + 1; j < N; ++j)
      if (mask_of(b[i]) == mask_of(b[j])) return false;
  return true;
}

}  // namespace detail

template <Basis... B>
struct MV;

/// The quaternion layout: w + x i + y j + z k with i = e32, j = e13, k = e21 (see types.hpp, Rot).
using QuatLayout = MV<blade::s, blade::e32, blade::e13, blade::e21>;

/// A multivector of G(4,1) holding the listed basis elements; N doubles, zero-initialised.
template <Basis... B>
struct MV {
  static constexpr std::size_t size = sizeof...(B);
  static constexpr std::array<Basis, size> basis{B...};
  /// Bit m set iff blade mask m is one of the basis elements.
  static constexpr std::uint32_t blade_set = (0u | ... | (std::uint32_t{1} << mask_of(B)));
  static_assert(detail::masks_unique(basis), "a multivector type lists each blade once");

  std::array<double, size> c{};

  constexpr MV() = default;
  /// Component-wise construction, in the order of the basis list.
  template <class... T>
  requires(sizeof...(T) == size && size > 0 && (std::is_arithmetic_v<T> && ...)) constexpr MV(T... v)
      : c{static_cast<double>(v)...} {}
  /// Exact embedding of a type whose blades are a subset of ours (missing blades are zero).
  template <Basis... A>
  requires((MV<A...>::blade_set & ~blade_set) == 0 && !std::is_same_v<MV<A...>, MV<B...>>) SPINMOTOR_GA_INLINE
      constexpr MV(const MV<A...>& a)
      : MV(a, std::make_index_sequence<size>{}) {}

  /// Position of a blade mask in the basis list, or -1.
  static constexpr int index_of(unsigned mask) {
    for (std::size_t i = 0; i < size; ++i)
      if (mask_of(basis[i]) == mask) return static_cast<int>(i);
    return -1;
  }

  constexpr double& operator[](std::size_t i) { return c[i]; }
  constexpr const double& operator[](std::size_t i) const { return c[i]; }
  double* data() { return c.data(); }
  const double* data() const { return c.data(); }

  /// The coefficient of basis element X (e.g. get<blade::e31>()), 0 when the type does not hold it.
  template <Basis X>
  [[nodiscard]] constexpr double get() const {
    constexpr int i = index_of(mask_of(X));
    if constexpr (i < 0) {
      return 0.0;
    } else if constexpr (orientation_of(basis[i]) == orientation_of(X)) {
      return c[i];
    } else {
      return -c[i];
    }
  }

  // ---- quaternion view, only for Rot (= Quat): q = w + x i + y j + z k, i = e32, j = e13, k = e21 ----
  static constexpr bool is_quaternion = std::is_same_v<MV<B...>, QuatLayout>;
  [[nodiscard]] constexpr double w() const requires is_quaternion { return c[0]; }
  [[nodiscard]] constexpr double x() const requires is_quaternion { return c[1]; }
  [[nodiscard]] constexpr double y() const requires is_quaternion { return c[2]; }
  [[nodiscard]] constexpr double z() const requires is_quaternion { return c[3]; }
  constexpr double& w() requires is_quaternion { return c[0]; }
  constexpr double& x() requires is_quaternion { return c[1]; }
  constexpr double& y() requires is_quaternion { return c[2]; }
  constexpr double& z() requires is_quaternion { return c[3]; }
  /// The imaginary part (x, y, z).
  Eigen::Vector3d vec() const requires is_quaternion { return {c[1], c[2], c[3]}; }
  /// The four components (w, x, y, z), real part first (the project's n×4 layout).
  Eigen::Vector4d coeffs() const requires is_quaternion { return {c[0], c[1], c[2], c[3]}; }

 private:
  template <Basis... A, std::size_t... i>
  SPINMOTOR_GA_INLINE constexpr MV(const MV<A...>& a, std::index_sequence<i...>)
      : c{a.template get<basis[i]>()...} {}
};

/// Bit set of the blades of a multivector type.
template <class T>
inline constexpr std::uint32_t blade_set_v = T::blade_set;

/// canonical<Set>::type: the type a product returns when its non-zero blades are Set. Named types
/// register themselves (types.hpp); any other set gets its blades in increasing mask order.
namespace detail {
[[nodiscard]] constexpr Basis nth_blade(std::uint32_t set, std::size_t n) {
  for (unsigned m = 0; m < 32; ++m)
    if ((set >> m) & 1u) {
      if (n == 0) return static_cast<Basis>(m);
      --n;
    }
  return 0;
}
template <std::uint32_t Set, std::size_t... I>
auto default_layout(std::index_sequence<I...>) -> MV<nth_blade(Set, I)...>;
}  // namespace detail

template <std::uint32_t Set>
struct canonical {
  using type = decltype(detail::default_layout<Set>(std::make_index_sequence<std::popcount(Set)>{}));
};
template <std::uint32_t Set>
using canonical_t = typename canonical<Set>::type;

}  // namespace spinmotor::ga

#pragma once
// spinmotor/ga/products.hpp — products and unary operations on typed multivectors (paper §II.A).
//
//   gp(a, b)  a * b   geometric product            op(a, b)  a ^ b   outer product
//   lc(a, b)          left contraction a⌋b         rc(a, b)          right contraction a⌊b
//   scalar(a, b)      scalar product <a b>_0 (a double)
//   reverse(a) ~a     involute(a)  conjugate(a)    grade<k>(a)   dual(a) undual(a)
//   norm2(a) = <a ~a>_0 (signed)   norm(a) = sqrt|norm2(a)|   inverse(a) of a versor
//   cast<T>(a)        projection onto the blades of T     sandwich(V, X) = V X ~V cast to X's type
//
// A product's result type holds exactly the blades whose coefficient is a non-zero bilinear form of
// the inputs; it is computed at compile time (detail::product_table) together with the list of
// (input i, input j, output k, sign) terms, and the product is unrolled over that list: straight-line
// multiply-adds on the coefficient arrays, no loops over blades at run time, no heap.
#include <cmath>
#include <ostream>

#include "spinmotor/ga/types.hpp"

namespace spinmotor::ga {

namespace detail {

/// One term of a product: r[k] (+|-)= a[i] * b[j]; `first` marks the first term written to r[k].
struct Entry {
  std::uint8_t i = 0, j = 0, k = 0;
  bool neg = false, first = false;
};

template <std::size_t NA, std::size_t NB>
constexpr std::uint32_t product_set(Op p, const std::array<Basis, NA>& a, const std::array<Basis, NB>& b) {
  std::uint32_t set = 0;
  for (std::size_t i = 0; i < NA; ++i)
    for (std::size_t j = 0; j < NB; ++j) {
      const Terms t = blade_product(p, mask_of(a[i]), mask_of(b[j]));
      for (int k = 0; k < t.n; ++k) set |= std::uint32_t{1} << t.mask[k];
    }
  return set;
}

template <std::size_t NA, std::size_t NB>
[[nodiscard]] constexpr std::size_t product_count(Op p, const std::array<Basis, NA>& a,
                                                  const std::array<Basis, NB>& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < NA; ++i)
    for (std::size_t j = 0; j < NB; ++j)
      n += static_cast<std::size_t>(blade_product(p, mask_of(a[i]), mask_of(b[j])).n);
  return n;
}

/// The terms of a product, grouped by output component (so the first of each group can assign).
template <std::size_t L, std::size_t NA, std::size_t NB, std::size_t NR>
constexpr std::array<Entry, L> product_entries(Op p, const std::array<Basis, NA>& a,
                                               const std::array<Basis, NB>& b,
                                               const std::array<Basis, NR>& r) {
  std::array<Entry, L> e{};
  std::size_t n = 0;
  for (std::size_t k = 0; k < NR; ++k) {
    bool first = true;
    for (std::size_t i = 0; i < NA; ++i)
      for (std::size_t j = 0; j < NB; ++j) {
        const Terms t = blade_product(p, mask_of(a[i]), mask_of(b[j]));
        for (int q = 0; q < t.n; ++q) {
          if (t.mask[q] != mask_of(r[k])) continue;
          const int sign = t.coef[q] * orientation_of(a[i]) * orientation_of(b[j]) * orientation_of(r[k]);
          e[n++] = Entry{static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(j),
                         static_cast<std::uint8_t>(k), sign < 0, first};
          first = false;
        }
      }
  }
  return e;
}

template <Op P, class A, class B>
struct product_table;

template <Op P, Basis... A, Basis... B>
struct product_table<P, MV<A...>, MV<B...>> {
  using R = canonical_t<product_set(P, MV<A...>::basis, MV<B...>::basis)>;
  static constexpr std::size_t count = product_count(P, MV<A...>::basis, MV<B...>::basis);
  static constexpr std::array<Entry, count> entries =
      product_entries<count>(P, MV<A...>::basis, MV<B...>::basis, R::basis);
};

template <class R, class X, class Y>
SPINMOTOR_GA_INLINE constexpr void step(R& r, const X& x, const Y& y, Entry e) noexcept {
  const double v = x.c[e.i] * y.c[e.j];
  if (e.first) {
    r.c[e.k] = e.neg ? -v : v;
  } else if (e.neg) {
    r.c[e.k] -= v;
  } else {
    r.c[e.k] += v;
  }
}

template <class T, class X, class Y, std::size_t... t>
SPINMOTOR_GA_PURE constexpr typename T::R run_terms(const X& x, const Y& y,
                                                    std::index_sequence<t...>) noexcept {
  typename T::R r;
  (step(r, x, y, T::entries[t]), ...);
  return r;
}

template <Op P, Basis... A, Basis... B>
SPINMOTOR_GA_PURE constexpr auto product(const MV<A...>& x, const MV<B...>& y) noexcept {
  using T = product_table<P, MV<A...>, MV<B...>>;
  return run_terms<T>(x, y, std::make_index_sequence<T::count>{});
}

struct ReverseSign {  // (-1)^{k(k-1)/2}
  static constexpr double of(int k) { return (k & 2) ? -1.0 : 1.0; }
};
struct InvoluteSign {  // (-1)^k
  static constexpr double of(int k) { return (k & 1) ? -1.0 : 1.0; }
};
struct ConjugateSign {  // (-1)^{k(k+1)/2}
  static constexpr double of(int k) { return ((k + 1) & 2) ? -1.0 : 1.0; }
};

/// Each coefficient times S::of(grade of its blade) (a compile-time ±1) times s.
template <class S, Basis... A, std::size_t... i>
SPINMOTOR_GA_PURE constexpr MV<A...> grade_signs(const MV<A...>& a, double s,
                                                 std::index_sequence<i...>) noexcept {
  MV<A...> r;
  ((r.c[i] = S::of(grade_of(mask_of(MV<A...>::basis[i]))) * (s * a.c[i])), ...);
  return r;
}
template <class S, Basis... A>
SPINMOTOR_GA_PURE constexpr MV<A...> grade_signs(const MV<A...>& a) noexcept {
  return grade_signs<S>(a, 1.0, std::make_index_sequence<sizeof...(A)>{});
}
struct NoSign {
  static constexpr double of(int) { return 1.0; }
};
template <Basis... A>
SPINMOTOR_GA_PURE constexpr MV<A...> scaled(const MV<A...>& a, double s) noexcept {
  return grade_signs<NoSign>(a, s, std::make_index_sequence<sizeof...(A)>{});
}

template <Basis X, class A, class B>
SPINMOTOR_GA_PURE constexpr double sum_coef(const A& a, const B& b, double sb) noexcept {
  if constexpr (A::index_of(mask_of(X)) < 0) {
    return sb * b.template get<X>();
  } else if constexpr (B::index_of(mask_of(X)) < 0) {
    return a.template get<X>();
  } else {
    return a.template get<X>() + sb * b.template get<X>();
  }
}

template <class R, Basis... A, Basis... B, std::size_t... k>
SPINMOTOR_GA_PURE constexpr R sum(const MV<A...>& a, const MV<B...>& b, double sb,
                                  std::index_sequence<k...>) {
  R r;
  ((r.c[k] = sum_coef<R::basis[k]>(a, b, sb)), ...);
  return r;
}
template <class R, Basis... A, Basis... B>
SPINMOTOR_GA_PURE constexpr R sum(const MV<A...>& a, const MV<B...>& b, double sb) noexcept {
  return sum<R>(a, b, sb, std::make_index_sequence<R::size>{});
}

template <class T, Basis... A, std::size_t... k>
SPINMOTOR_GA_PURE constexpr T cast_impl(const MV<A...>& a, std::index_sequence<k...>) noexcept {
  T r;
  ((r.c[k] = a.template get<T::basis[k]>()), ...);
  return r;
}

template <int K>
constexpr std::uint32_t grade_subset(std::uint32_t set) {
  std::uint32_t r = 0;
  for (unsigned m = 0; m < 32; ++m)
    if (((set >> m) & 1u) && grade_of(m) == K) r |= std::uint32_t{1} << m;
  return r;
}

}  // namespace detail

// ---- bilinear products ------------------------------------------------------------------------------

/// Geometric product.
template <Basis... A, Basis... B>
SPINMOTOR_GA_PURE constexpr auto gp(const MV<A...>& a, const MV<B...>& b) noexcept {
  return detail::product<detail::Op::Geometric>(a, b);
}
/// Outer (wedge) product.
template <Basis... A, Basis... B>
SPINMOTOR_GA_PURE constexpr auto op(const MV<A...>& a, const MV<B...>& b) noexcept {
  return detail::product<detail::Op::Outer>(a, b);
}
/// Left contraction a⌋b (Dorst): the grade |b|-|a| part of a b for blades.
template <Basis... A, Basis... B>
SPINMOTOR_GA_PURE constexpr auto lc(const MV<A...>& a, const MV<B...>& b) noexcept {
  return detail::product<detail::Op::LeftContraction>(a, b);
}
/// Right contraction a⌊b: the grade |a|-|b| part of a b for blades.
template <Basis... A, Basis... B>
SPINMOTOR_GA_PURE constexpr auto rc(const MV<A...>& a, const MV<B...>& b) noexcept {
  return detail::product<detail::Op::RightContraction>(a, b);
}
/// Scalar product <a b>_0.
template <Basis... A, Basis... B>
SPINMOTOR_GA_PURE constexpr double scalar(const MV<A...>& a, const MV<B...>& b) noexcept {
  return detail::product<detail::Op::Scalar>(a, b).template get<blade::s>();
}

template <Basis... A, Basis... B>
SPINMOTOR_GA_PURE constexpr auto operator*(const MV<A...>& a, const MV<B...>& b) noexcept {
  return gp(a, b);
}
/// Outer product. Mind C++ precedence: ^ binds weaker than + and ==, so write (a ^ b).
template <Basis... A, Basis... B>
SPINMOTOR_GA_PURE constexpr auto operator^(const MV<A...>& a, const MV<B...>& b) noexcept {
  return op(a, b);
}

// ---- linear operations --------------------------------------------------------------------------------

template <Basis... A, Basis... B>
SPINMOTOR_GA_PURE constexpr auto operator+(const MV<A...>& a, const MV<B...>& b) noexcept {
  return detail::sum<canonical_t<MV<A...>::blade_set | MV<B...>::blade_set>>(a, b, 1.0);
}
template <Basis... A, Basis... B>
SPINMOTOR_GA_PURE constexpr auto operator-(const MV<A...>& a, const MV<B...>& b) noexcept {
  return detail::sum<canonical_t<MV<A...>::blade_set | MV<B...>::blade_set>>(a, b, -1.0);
}
template <Basis... A>
SPINMOTOR_GA_PURE constexpr MV<A...> operator-(const MV<A...>& a) noexcept {
  return detail::scaled(a, -1.0);
}
template <Basis... A>
SPINMOTOR_GA_PURE constexpr MV<A...> operator*(double s, const MV<A...>& a) noexcept {
  return detail::scaled(a, s);
}
template <Basis... A>
SPINMOTOR_GA_PURE constexpr MV<A...> operator*(const MV<A...>& a, double s) noexcept {
  return s * a;
}
template <Basis... A>
SPINMOTOR_GA_PURE constexpr MV<A...> operator/(const MV<A...>& a, double s) noexcept {
  return (1.0 / s) * a;
}
/// a += b, for b whose blades are among a's.
template <Basis... A, Basis... B>
requires((MV<B...>::blade_set & ~MV<A...>::blade_set) == 0) constexpr MV<A...>& operator+=(
    MV<A...>& a, const MV<B...>& b) {
  return a = detail::sum<MV<A...>>(a, b, 1.0);
}
template <Basis... A, Basis... B>
requires((MV<B...>::blade_set & ~MV<A...>::blade_set) == 0) constexpr MV<A...>& operator-=(
    MV<A...>& a, const MV<B...>& b) {
  return a = detail::sum<MV<A...>>(a, b, -1.0);
}
template <Basis... A>
SPINMOTOR_GA_PURE constexpr MV<A...>& operator*=(MV<A...>& a, double s) noexcept {
  return a = s * a;
}
template <Basis... A>
SPINMOTOR_GA_PURE constexpr bool operator==(const MV<A...>& a, const MV<A...>& b) noexcept {
  return a.c == b.c;
}

/// Projection onto the blades of T (blades T lacks are dropped, blades a lacks are zero).
template <class T, Basis... A>
SPINMOTOR_GA_PURE constexpr T cast(const MV<A...>& a) noexcept {
  return detail::cast_impl<T>(a, std::make_index_sequence<T::size>{});
}

/// The grade-K part.
template <int K, Basis... A>
SPINMOTOR_GA_PURE constexpr auto grade(const MV<A...>& a) noexcept {
  return cast<canonical_t<detail::grade_subset<K>(MV<A...>::blade_set)>>(a);
}

// ---- involutions, duality, norms -------------------------------------------------------------------

/// Reverse ~a: each k-blade times (-1)^{k(k-1)/2}. For a rotor this is the quaternion conjugate.
template <Basis... A>
SPINMOTOR_GA_PURE constexpr MV<A...> reverse(const MV<A...>& a) noexcept {
  return detail::grade_signs<detail::ReverseSign>(a);
}
template <Basis... A>
SPINMOTOR_GA_PURE constexpr MV<A...> operator~(const MV<A...>& a) noexcept {
  return reverse(a);
}
/// Grade involution: each k-blade times (-1)^k.
template <Basis... A>
SPINMOTOR_GA_PURE constexpr MV<A...> involute(const MV<A...>& a) noexcept {
  return detail::grade_signs<detail::InvoluteSign>(a);
}
/// Clifford conjugate (reverse of the grade involution): each k-blade times (-1)^{k(k+1)/2}.
template <Basis... A>
SPINMOTOR_GA_PURE constexpr MV<A...> conjugate(const MV<A...>& a) noexcept {
  return detail::grade_signs<detail::ConjugateSign>(a);
}

/// Dual a* = a I⁻¹ = -a I with I = o∧e1∧e2∧e3∧inf (I² = -1).
template <Basis... A>
SPINMOTOR_GA_PURE constexpr auto dual(const MV<A...>& a) noexcept {
  return gp(a, Pss{-1.0});
}
/// Undual: the inverse of dual, a I.
template <Basis... A>
SPINMOTOR_GA_PURE constexpr auto undual(const MV<A...>& a) noexcept {
  return gp(a, Pss{1.0});
}

/// Signed squared norm <a ~a>_0 (zero for null vectors, negative for imaginary spheres).
template <Basis... A>
SPINMOTOR_GA_PURE constexpr double norm2(const MV<A...>& a) noexcept {
  return scalar(a, reverse(a));
}
/// sqrt(|<a ~a>_0|).
template <Basis... A>
double norm(const MV<A...>& a) {
  return std::sqrt(std::abs(norm2(a)));
}

/// Inverse of a versor or blade: ~a / (a ~a). For a motor, a ~a = α + β e123∞ is not a scalar when
/// the motor is not normalised, and (α + β e123∞)⁻¹ = (1 - (β/α) e123∞)/α is used.
template <Basis... A>
SPINMOTOR_GA_PURE constexpr MV<A...> inverse(const MV<A...>& a) noexcept {
  if constexpr (std::is_same_v<MV<A...>, Mot>) {
    const auto n = a * reverse(a);
    const double alpha = n.template get<blade::s>(), beta = n.template get<blade::e123ni>();
    return cast<Mot>(reverse(a) * MV<blade::s, blade::e123ni>{1.0 / alpha, -beta / (alpha * alpha)});
  } else {
    return reverse(a) / norm2(a);
  }
}

/// V X ~V, projected onto the type of X (exact for unit versors V acting on X's grade).
template <Basis... V, Basis... X>
constexpr MV<X...> sandwich(const MV<V...>& v, const MV<X...>& x) {
  return cast<MV<X...>>(v * x * reverse(v));
}

// ---- printing (Catch2 and debugging) -----------------------------------------------------------------

template <Basis... A>
std::ostream& operator<<(std::ostream& os, const MV<A...>& a) {
  static constexpr const char* names[5] = {"e1", "e2", "e3", "o", "ni"};
  os << '{';
  for (std::size_t i = 0; i < MV<A...>::size; ++i) {
    const Basis bb = MV<A...>::basis[i];
    os << (i ? ", " : "") << orientation_of(bb) * a.c[i];
    if (mask_of(bb) == 0) continue;
    os << ' ';
    bool first = true;
    for (unsigned v = 0; v < 5; ++v) {
      if (((mask_of(bb) >> v) & 1u) == 0) continue;
      os << (first ? "" : "^") << names[v];
      first = false;
    }
  }
  return os << '}';
}

}  // namespace spinmotor::ga

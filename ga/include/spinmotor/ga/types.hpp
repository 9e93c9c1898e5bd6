#pragma once
// spinmotor/ga/types.hpp — the named multivector types of CGA G(4,1) and their component orders.
//
// Every product of two types returns the type of exactly its possibly non-zero blades; when that blade
// set is one of the sets below, the result *is* the named type (Rot * Rot is a Rot, Mot * Mot a Mot,
// Pnt ∧ Pnt ∧ ... see products.hpp). Component orders (what operator[] and the constructors use):
//
//   Sca  1                                   scalar
//   Vec  e1 e2 e3                            Euclidean vector
//   Biv  e12 e31 e23                         Euclidean bivector B = I3 b, b = (B[2], B[1], B[0])
//   Tri  e123                                Euclidean pseudoscalar I3
//   Pss  I                                   I = o∧e1∧e2∧e3∧inf = e1 e2 e3 e+ e-, I² = -1
//   Pnt  e1 e2 e3 o inf                      null point up(x); also the dual sphere (Sph)
//   Pln  e1 e2 e3 inf                        dual plane n + d inf (points x with n·x = d)
//   Lin  o∧e1∧inf o∧e2∧inf o∧e3∧inf e23∧inf e31∧inf e12∧inf
//                                            direct line up(p)∧d∧inf = Plücker (d; p×d)
//   Dll  e12 e31 e23 e1∞ e2∞ e3∞           dual line, motor generator, motor logarithm
//   Drv  e1∞ e2∞ e3∞                       direction (free vector) t∧inf, translation generator
//   Rot  1 e32 e13 e21                       rotor = unit quaternion w + x i + y j + z k (Quat)
//   Trs  1 e1∞ e2∞ e3∞                     translator 1 - ½ t inf
//   Mot  1 e12 e31 e23 e1∞ e2∞ e3∞ e123∞   motor (rigid body motion)
//   Par  the ten bivectors (sorted masks)    point pair; Bst = 1 + Par (product of two points)
//   Cir  the ten trivectors (sorted masks)   circle
//
// The rotor sub-algebra is the quaternions: with i = e32, j = e13, k = e21 we have i² = j² = k² = ijk
// = -1, and the rotor cos(θ/2) - sin(θ/2) e12 (rotation by θ about z) is the quaternion
// cos(θ/2) + sin(θ/2) k, so R x ~R is q x q̄ (Eigen::Quaterniond's convention). Rot stores (w, x, y, z).
#include "spinmotor/ga/algebra.hpp"

namespace spinmotor::ga {

using Sca = MV<blade::s>;
using Vec = MV<blade::e1, blade::e2, blade::e3>;
using Biv = MV<blade::e12, blade::e31, blade::e23>;
using Tri = MV<blade::e123>;
using Pss = MV<blade::I5>;
using Pnt = MV<blade::e1, blade::e2, blade::e3, blade::o, blade::ni>;
using Sph = Pnt;
using Pln = MV<blade::e1, blade::e2, blade::e3, blade::ni>;
using Lin = MV<blade::oe1ni, blade::oe2ni, blade::oe3ni, blade::e23ni, blade::e31ni, blade::e12ni>;
using Dll = MV<blade::e12, blade::e31, blade::e23, blade::e1ni, blade::e2ni, blade::e3ni>;
using Drv = MV<blade::e1ni, blade::e2ni, blade::e3ni>;
using Rot = QuatLayout;
using Trs = MV<blade::s, blade::e1ni, blade::e2ni, blade::e3ni>;
using Mot =
    MV<blade::s, blade::e12, blade::e31, blade::e23, blade::e1ni, blade::e2ni, blade::e3ni, blade::e123ni>;
using Par = MV<blade::e12, blade::e13, blade::e23, blade::e1o, blade::e2o, blade::e3o, blade::e1ni,
               blade::e2ni, blade::e3ni, blade::oni>;
using Bst = MV<blade::s, blade::e12, blade::e13, blade::e23, blade::e1o, blade::e2o, blade::e3o, blade::e1ni,
               blade::e2ni, blade::e3ni, blade::oni>;
using Cir = MV<blade::e123, blade::e12 | blade::o, blade::e13 | blade::o, blade::e23 | blade::o, blade::e12ni,
               blade::e13ni, blade::e23ni, blade::e1oni, blade::e2oni, blade::e3oni>;

// Register the layouts that differ from the default (sorted masks, positive orientation), so that a
// product whose blade set is theirs returns them.
#define SPINMOTOR_GA_REGISTER(T)     \
  template <>                        \
  struct canonical<blade_set_v<T>> { \
    using type = T;                  \
  }
SPINMOTOR_GA_REGISTER(Biv);
SPINMOTOR_GA_REGISTER(Pss);
SPINMOTOR_GA_REGISTER(Lin);
SPINMOTOR_GA_REGISTER(Dll);
SPINMOTOR_GA_REGISTER(Rot);
SPINMOTOR_GA_REGISTER(Mot);
#undef SPINMOTOR_GA_REGISTER

static_assert(std::is_same_v<canonical_t<blade_set_v<Pnt>>, Pnt> &&
              std::is_same_v<canonical_t<blade_set_v<Trs>>, Trs> &&
              std::is_same_v<canonical_t<blade_set_v<Par>>, Par> &&
              std::is_same_v<canonical_t<blade_set_v<Cir>>, Cir>);

}  // namespace spinmotor::ga

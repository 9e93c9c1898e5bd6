#pragma once
// spinmotor/ga.hpp — the handwritten CGA G(4,1) header set, namespace spinmotor::ga.
//
//   ga/algebra.hpp       blades as masks, MV<basis...>, compile-time blade products      (paper §II.A)
//   ga/types.hpp         named types Sca Vec Biv Tri Pss Pnt Sph Pln Lin Dll Drv Rot Trs Mot ...
//   ga/products.hpp      gp op lc rc scalar, reverse/involute/conjugate, dual, grade, norms
//   ga/quaternion.hpp    Quat = Rot, Eigen::Quaterniond conversions
//   ga/constructors.hpp  up down rotor translator motor plane line sphere                 (§II.B)
//   ga/motor.hpp         normalize exp log sqrt sclerp                                     (§II.B.1-2)
//   ga/blend.hpp         blend(motors, weights, Blend::{Log, PivotLog, DLB})          (§II.B.2)
//   ga/interop.hpp       from_isometry to_isometry transform, dual quaternions
//
// Interop surface (names relied upon by the other modules and the tests):
//   Mot from_isometry(const Eigen::Isometry3d&);   Eigen::Isometry3d to_isometry(const Mot&);
//   Eigen::Vector3d transform(const Mot&, const Eigen::Vector3d&);
//   Dll log(const Mot&);  Mot exp(const Dll&);  Mot sqrt(const Mot&);  Mot sclerp(a, b, t);
//   Mot blend(std::span<const Mot>, std::span<const double> weights, Blend);
//   using Quat = Rot;
#include "spinmotor/ga/algebra.hpp"
#include "spinmotor/ga/blend.hpp"
#include "spinmotor/ga/constructors.hpp"
#include "spinmotor/ga/interop.hpp"
#include "spinmotor/ga/motor.hpp"
#include "spinmotor/ga/products.hpp"
#include "spinmotor/ga/quaternion.hpp"
#include "spinmotor/ga/types.hpp"

namespace spinmotor::ga {
using Quat = Rot;
}  // namespace spinmotor::ga

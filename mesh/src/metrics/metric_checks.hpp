#pragma once
// Internal to the metrics: input checks shared by the metric sources. Not installed.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/face_geometry.hpp"  // kDegenerateFace

namespace spinmotor::detail {

inline void check_points(const Eigen::MatrixXd& V, const char* who, const char* name) {
  if (V.cols() != 3)
    throw Error(std::string(who) + ": " + name + " must have 3 columns (got " + std::to_string(V.cols()) +
                ")");
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (!V.row(i).allFinite())
      throw Error(std::string(who) + ": " + name + " vertex " + std::to_string(i) +
                  " has a non-finite coordinate");
}

/// V_rest and V_def n×3 and finite, F m×3 with indices in [0, n).
inline void check_pair(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F, const Eigen::MatrixXd& V_def,
                       const char* who) {
  check_points(V_rest, who, "rest");
  check_points(V_def, who, "deformed");
  if (V_rest.rows() != V_def.rows())
    throw Error(std::string(who) + ": rest has " + std::to_string(V_rest.rows()) +
                " vertices, deformed has " + std::to_string(V_def.rows()));
  if (F.cols() != 3)
    throw Error(std::string(who) + ": F must have 3 columns (got " + std::to_string(F.cols()) + ")");
  if (F.rows() == 0) throw Error(std::string(who) + ": the mesh has no faces");
  const Eigen::Index n = V_rest.rows();
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (F(f, c) < 0 || F(f, c) >= n)
        throw Error(std::string(who) + ": face " + std::to_string(f) + " has vertex index " +
                    std::to_string(F(f, c)) + " out of range [0, " + std::to_string(n) + ")");
}

/// Twice the area of face f of V and whether it is degenerate.
inline double double_area(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::Index f,
                          bool* degenerate) {
  const Eigen::Vector3d x0 = V.row(F(f, 0)), x1 = V.row(F(f, 1)), x2 = V.row(F(f, 2));
  const Eigen::Vector3d e1 = x1 - x0, e2 = x2 - x0, e3 = x2 - x1;
  const double a2 = e1.cross(e2).norm();
  const double l2 = std::max({e1.squaredNorm(), e2.squaredNorm(), e3.squaredNorm()});
  *degenerate = !(a2 > kDegenerateFace * l2);
  return a2;
}

}  // namespace spinmotor::detail

#include "spinmotor/mesh/face_geometry.hpp"

#include <cmath>

#include "operator_assembly.hpp"

namespace spinmotor {

using detail::FaceFrame;

Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  detail::check_mesh(V, F, "face_areas");
  Eigen::VectorXd A(F.rows());
  detail::for_each_face(V, F, false, "face_areas",
                        [&](Eigen::Index f, const FaceFrame& fr) { A[f] = 0.5 * fr.dbl_area; });
  return A;
}

Eigen::MatrixXd face_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  detail::check_mesh(V, F, "face_normals");
  Eigen::MatrixXd N(F.rows(), 3);
  detail::for_each_face(V, F, true, "face_normals", [&](Eigen::Index f, const FaceFrame& fr) {
    N.row(f) = (fr.cross / fr.dbl_area).transpose();
  });
  return N;
}

Eigen::MatrixXd face_edge_lengths(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  detail::check_mesh(V, F, "face_edge_lengths");
  Eigen::MatrixXd L(F.rows(), 3);
  detail::for_each_face(V, F, false, "face_edge_lengths", [&](Eigen::Index f, const FaceFrame& fr) {
    for (int c = 0; c < 3; ++c) L(f, c) = std::sqrt(fr.l2[c]);
  });
  return L;
}

Eigen::MatrixXd corner_angles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  detail::check_mesh(V, F, "corner_angles");
  Eigen::MatrixXd T(F.rows(), 3);
  detail::for_each_face(V, F, false, "corner_angles", [&](Eigen::Index f, const FaceFrame& fr) {
    // |a×b| is the same for the three corners (twice the area); atan2 is accurate near 0 and π.
    for (int c = 0; c < 3; ++c) T(f, c) = std::atan2(fr.dbl_area, fr.dot[c]);
  });
  return T;
}

Eigen::MatrixXd cotangents(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  detail::check_mesh(V, F, "cotangents");
  Eigen::MatrixXd C(F.rows(), 3);
  detail::for_each_face(V, F, true, "cotangents", [&](Eigen::Index f, const FaceFrame& fr) {
    for (int c = 0; c < 3; ++c) C(f, c) = fr.dot[c] / fr.dbl_area;
  });
  return C;
}

}  // namespace spinmotor

#pragma once
// Lumped (diagonal) mass matrices: the area associated with each vertex.
//
//   Barycentric: each face gives a third of its area to each of its corners.
//   Voronoi:     the "mixed" Voronoi area of Meyer, Desbrun, Schröder & Barr 2003 (Fig. 4): on a
//                non-obtuse face, corner i receives its Voronoi area ⅛(|x_i−x_j|² cot γ_k +
//                |x_i−x_k|² cot γ_j) (eq. 7); on an obtuse face, the obtuse corner receives A/2 and
//                the other two A/4. Unlike the pure Voronoi area it is positive and sums to the area.
// Both sum to the total surface area (to rounding). A vertex referenced by no face gets mass 0.
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace spinmotor {

enum class MassType { Barycentric, Voronoi };

/// Inputs: V (n×3), F (m×3), type. Output: n vertex areas (units of V squared).
/// Voronoi throws Error naming the first degenerate face (face_geometry.hpp); Barycentric never does.
Eigen::VectorXd vertex_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                             MassType type = MassType::Voronoi);

/// Barycentric vertex areas from given face areas: vertex i gets a third of the area of every face
/// around it (faces and corners in order, so the sums are reproducible). Inputs: F (m×3) with indices
/// in [0, n), face_area (m). Output: n areas.
Eigen::VectorXd barycentric_vertex_areas(const Eigen::MatrixXi& F, const Eigen::VectorXd& face_area,
                                         Eigen::Index n);

/// Inputs: V (n×3), F (m×3), type. Output: n×n diagonal sparse M = diag(vertex_areas(V, F, type)),
/// every diagonal entry stored (also zeros).
Eigen::SparseMatrix<double> mass_matrix(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                        MassType type = MassType::Voronoi);

}  // namespace spinmotor

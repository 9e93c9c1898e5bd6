#pragma once
// The curvature change ρ of a spin transformation (Crane et al. 2011, §4.1, §7.1): the change of mean
// curvature half-density, piecewise constant on faces (§5.3). Units: 1/length (ρ·|df| is scale-free,
// so ρ = 5 on a unit sphere corresponds to ρ = 0.05 on a sphere of radius 100).
// Ways to paint it, each returning m values (one per face):
#include <Eigen/Core>
#include <filesystem>
#include <functional>

#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/spin/grayscale_image.hpp"

namespace spinmotor {

/// Inputs: F (m×3), rho_vertices (n values). Output: ρ_f = mean of the values at the face's corners.
/// Throws Error on a size mismatch, an index out of range or a non-finite value (naming the vertex).
Eigen::VectorXd face_rho_from_vertices(const Eigen::MatrixXi& F, const Eigen::VectorXd& rho_vertices);

/// Inputs: V (n×3), F (m×3), g (a scalar function of position). Output: ρ_f = g(barycentre of f).
/// Throws Error naming the face if g returns a non-finite value.
Eigen::VectorXd face_rho_from_function(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const std::function<double(const Eigen::Vector3d&)>& g);

/// Inputs: a mesh with texture coordinates (UV, FUV), a grayscale image, scale. Output: SpinXForm's
/// ρ_f = (2 · (mean of the image at the face's three corner UVs) / 255 − 1) · scale, sampled with
/// GrayscaleImage::sample_uv (so mid grey means no change; black −scale, white +scale). Throws Error
/// if the mesh has no texture coordinates, an FUV index is out of range or a texture coordinate is
/// not finite.
Eigen::VectorXd face_rho_from_image(const Mesh& mesh, const GrayscaleImage& image, double scale = 5.0);

/// Reads `count` real numbers separated by white space (lines starting with '#' are comments) from a
/// text file, e.g. ρ per face or per vertex. Throws Error naming the file and line of a bad token, or
/// the count found when it differs (`what` names the expected items, e.g. "faces").
Eigen::VectorXd read_scalar_values(const std::filesystem::path& path, Eigen::Index count, const char* what);

}  // namespace spinmotor

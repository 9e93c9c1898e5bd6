#include "spinmotor/spin/curvature_change.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "spinmotor/core/error.hpp"

namespace spinmotor {

Eigen::VectorXd face_rho_from_vertices(const Eigen::MatrixXi& F, const Eigen::VectorXd& rho_vertices) {
  const Eigen::Index n = rho_vertices.size();
  for (Eigen::Index i = 0; i < n; ++i)
    if (!std::isfinite(rho_vertices[i])) {
      std::ostringstream s;
      s << "curvature change of vertex " << i << " is not finite (" << rho_vertices[i] << ")";
      throw Error(s.str());
    }
  Eigen::VectorXd rho(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    double sum = 0;
    for (int c = 0; c < 3; ++c) {
      const int i = F(f, c);
      if (i < 0 || i >= n) {
        std::ostringstream s;
        s << "face " << f << " refers to vertex " << i << " but " << n << " vertex values were given";
        throw Error(s.str());
      }
      sum += rho_vertices[i];
    }
    rho[f] = sum / 3.0;
  }
  return rho;
}

Eigen::VectorXd face_rho_from_function(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const std::function<double(const Eigen::Vector3d&)>& g) {
  Eigen::VectorXd rho(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      if (F(f, k) < 0 || F(f, k) >= V.rows()) {
        std::ostringstream s;
        s << "face " << f << " has vertex index " << F(f, k) << " outside [0, " << V.rows() << ")";
        throw Error(s.str());
      }
      c += V.row(F(f, k)).transpose() / 3.0;
    }
    rho[f] = g(c);
    if (!std::isfinite(rho[f])) {
      std::ostringstream s;
      s << "curvature change function is not finite at the barycentre of face " << f << " (" << c.transpose()
        << ")";
      throw Error(s.str());
    }
  }
  return rho;
}

Eigen::VectorXd face_rho_from_image(const Mesh& mesh, const GrayscaleImage& image, double scale) {
  if (!mesh.has_uv())
    throw Error("a curvature image needs texture coordinates, but the mesh has none (OBJ 'vt' with f v/vt)");
  if (image.width <= 0 || image.height <= 0) throw Error("the curvature image is empty");
  Eigen::VectorXd rho(mesh.F.rows());
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    double mean = 0;
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.FUV(f, c);
      if (t < 0 || t >= mesh.UV.rows()) {
        std::ostringstream s;
        s << "face " << f << " has texture coordinate index " << t << " outside [0, " << mesh.UV.rows()
          << ")";
        throw Error(s.str());
      }
      try {
        mean += image.sample_uv(mesh.UV(t, 0), mesh.UV(t, 1)) / 255.0 / 3.0;
      } catch (const Error& e) {  // a sampling coordinate that is not finite: name the face and its UV
        std::ostringstream s;
        s << "face " << f << " has texture coordinate " << t << " = (" << mesh.UV(t, 0) << ", "
          << mesh.UV(t, 1) << "): " << e.what();
        throw Error(s.str(), e.kind());
      }
    }
    rho[f] = (2.0 * mean - 1.0) * scale;  // [0, 1] → [−scale, scale]
  }
  return rho;
}

Eigen::VectorXd read_scalar_values(const std::filesystem::path& path, Eigen::Index count, const char* what) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open '" + path.string() + "'");
  Eigen::VectorXd v(count);
  Eigen::Index k = 0;
  std::string line;
  for (long lineno = 1; std::getline(in, line); ++lineno) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream ls(line);
    std::string tok;
    while (ls >> tok) {
      double x = 0;
      std::size_t used = 0;
      try {
        x = std::stod(tok, &used);
      } catch (...) {
        used = 0;
      }
      if (used != tok.size() || !std::isfinite(x)) {
        std::ostringstream s;
        s << path.string() << ":" << lineno << ": '" << tok << "' is not a finite number";
        throw Error(s.str());
      }
      if (k < count) v[k] = x;
      ++k;
    }
  }
  if (k != count) {
    std::ostringstream s;
    s << path.string() << ": " << k << " values for " << count << " " << what;
    throw Error(s.str());
  }
  return v;
}

}  // namespace spinmotor

#pragma once
// OpenGL 3.3 core drawing of a triangle mesh: the one drawing path of `spinmotor render`, the viewer
// window and the viewer's headless screenshots. Needs a current context whose functions are loaded
// (OffscreenContext, or load_gl after creating a window).
//
// Bind once per mesh (set_mesh: connectivity, texture coordinates, rest positions), then per frame
// set_positions(V) (normals recomputed, positions and normals uploaded as float) and draw(). Texture
// coordinates are per corner (docs/design.md): a mesh vertex with several UVs becomes several GPU vertices,
// gathered from V on every upload. Per-face scalars (Q) live in a texture buffer read with
// gl_PrimitiveID, so they need no vertex splitting; flat normals and wireframe distances come from a
// geometry shader (one pass, no barycentric attributes).
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/render/orbit_camera.hpp"

namespace spinmotor::render {

enum class ColorMode {
  Normals,  ///< world-space unit normal n as colour ½(n + 1), unlit
  Checker,  ///< checkerboard through the texture coordinates (rest-position 3D checker if the mesh has none)
  Q,        ///< per-face value (quasi-conformal error) through q_colormap on a log range
  Plain,    ///< one light grey, lit
  Signed,   ///< per-face signed value (a painted ρ): blue < 0 < red, full colour at ±signed_range
};

struct RenderStyle {
  ColorMode color = ColorMode::Normals;
  bool smooth = true;               ///< interpolated vertex normals (else per-face normals)
  bool wireframe = false;           ///< dark edges over the surface
  double q_min = 1.0, q_max = 2.0;  ///< Q range of the colour map (log scale)
  double signed_range = 1.0;        ///< |value| shown at full colour in ColorMode::Signed
  double checker_cells = 16;  ///< checker cells per unit of UV (or per bounding-box diagonal without UV)
  Eigen::Vector3f background{1.0f, 1.0f, 1.0f};
};

class MeshRenderer {
 public:
  MeshRenderer();  ///< compiles the program; Error with the GLSL log on failure
  ~MeshRenderer();
  MeshRenderer(const MeshRenderer&) = delete;
  MeshRenderer& operator=(const MeshRenderer&) = delete;

  /// Binds the connectivity, texture coordinates and rest positions of `mesh` and uploads its
  /// positions. Throws Error on an index out of range or FUV that does not match F.
  void set_mesh(const Mesh& mesh);
  /// Per frame: new positions (n×3, same vertex order). Error on a wrong size.
  void set_positions(const Eigen::MatrixXd& V);
  /// Per-face values for ColorMode::Q and ColorMode::Signed (m; +inf allowed). Error on a wrong size.
  void set_face_values(const Eigen::VectorXd& values);
  bool has_uv() const { return has_uv_; }
  Eigen::Index vertex_count() const { return n_; }
  Eigen::Index face_count() const { return m_; }

  /// Draws into the bound framebuffer (viewport width×height): clears it to the background, then the mesh.
  void draw(const OrbitCamera& camera, int width, int height, const RenderStyle& style);

 private:
  unsigned program_ = 0, vao_ = 0, vbo_pos_ = 0, vbo_nrm_ = 0, vbo_uv_ = 0, vbo_rest_ = 0, ebo_ = 0;
  unsigned face_buffer_ = 0, face_texture_ = 0, colormap_texture_ = 0;
  Eigen::Index n_ = 0, m_ = 0;
  bool has_uv_ = false;
  double diagonal_ = 1;
  Eigen::MatrixXi F_;               ///< mesh faces (for normals)
  std::vector<int> source_vertex_;  ///< GPU vertex → mesh vertex
  std::vector<float> pos_, nrm_;    ///< staging for uploads
};

/// Area-weighted vertex normals (n×3, unit; zero rows for isolated vertices).
Eigen::MatrixXd vertex_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace spinmotor::render

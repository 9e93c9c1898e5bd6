#include "spinmotor/render/mesh_renderer.hpp"

#include <Eigen/Geometry>
#include <string>
#include <unordered_map>

#include "spinmotor/core/error.hpp"
#include "spinmotor/render/gl_api.hpp"
#include "spinmotor/render/image.hpp"

namespace spinmotor::render {
namespace {

const char* kVertex = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_nrm;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec3 a_rest;
uniform mat4 u_mvp;
out vec3 g_pos; out vec3 g_nrm; out vec2 g_uv; out vec3 g_rest;
void main() {
  g_pos = a_pos; g_nrm = a_nrm; g_uv = a_uv; g_rest = a_rest;
  gl_Position = u_mvp * vec4(a_pos, 1.0);
})";

// Flat normal and screen-space distances to the three edges (for the wireframe) per triangle.
const char* kGeometry = R"(#version 330 core
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
uniform vec2 u_viewport;
in vec3 g_pos[]; in vec3 g_nrm[]; in vec2 g_uv[]; in vec3 g_rest[];
out vec3 f_pos; out vec3 f_nrm; out vec2 f_uv; out vec3 f_rest;
flat out vec3 f_flat; noperspective out vec3 f_edge;
void main() {
  vec3 fn = cross(g_pos[1] - g_pos[0], g_pos[2] - g_pos[0]);
  float len = length(fn);
  fn = len > 0.0 ? fn / len : vec3(0.0);
  vec2 p[3];
  for (int i = 0; i < 3; ++i) p[i] = u_viewport * gl_in[i].gl_Position.xy / gl_in[i].gl_Position.w * 0.5;
  float area = abs((p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x));
  vec3 h = vec3(area / max(length(p[2] - p[1]), 1e-6), area / max(length(p[2] - p[0]), 1e-6),
                area / max(length(p[1] - p[0]), 1e-6));
  for (int i = 0; i < 3; ++i) {
    gl_Position = gl_in[i].gl_Position;
    gl_PrimitiveID = gl_PrimitiveIDIn;
    f_pos = g_pos[i]; f_nrm = g_nrm[i]; f_uv = g_uv[i]; f_rest = g_rest[i]; f_flat = fn;
    f_edge = vec3(0.0); f_edge[i] = h[i];
    EmitVertex();
  }
  EndPrimitive();
})";

const char* kFragment = R"(#version 330 core
in vec3 f_pos; in vec3 f_nrm; in vec2 f_uv; in vec3 f_rest;
flat in vec3 f_flat; noperspective in vec3 f_edge;
uniform int u_mode;          // 0 normals, 1 checker, 2 Q, 3 plain, 4 signed
uniform float u_signed;      // |value| shown at full colour in mode 4
uniform int u_smooth, u_wire, u_has_uv;
uniform vec3 u_eye;
uniform vec2 u_qrange;       // log(q_min), log(q_max / q_min)
uniform float u_cells;
uniform samplerBuffer u_face;
uniform sampler2D u_colormap;
out vec4 o_color;
void main() {
  vec3 n = u_smooth != 0 ? normalize(f_nrm) : f_flat;
  vec3 to_eye = normalize(u_eye - f_pos);
  if (dot(n, to_eye) < 0.0 && u_mode != 0) n = -n;  // two-sided lighting
  float light = 0.3 + 0.7 * abs(dot(n, to_eye));
  vec3 c;
  if (u_mode == 0) {
    c = 0.5 * n + 0.5;
  } else if (u_mode == 1) {
    vec3 k = u_has_uv != 0 ? vec3(floor(f_uv * u_cells), 0.0) : floor(f_rest * u_cells);
    float odd = mod(k.x + k.y + k.z, 2.0);
    c = light * mix(vec3(0.95, 0.95, 0.92), vec3(0.85, 0.33, 0.10), odd);
  } else if (u_mode == 2) {
    float q = texelFetch(u_face, gl_PrimitiveID).r;
    float t = (isinf(q) || isnan(q)) ? 1.0 : clamp((log(max(q, 1.0)) - u_qrange.x) / u_qrange.y, 0.0, 1.0);
    c = light * texture(u_colormap, vec2((t * 255.0 + 0.5) / 256.0, 0.5)).rgb;
  } else if (u_mode == 4) {
    float v = texelFetch(u_face, gl_PrimitiveID).r;
    float t = clamp(v / u_signed, -1.0, 1.0);
    vec3 base = vec3(0.93, 0.93, 0.93);
    c = light * (t >= 0.0 ? mix(base, vec3(0.80, 0.10, 0.10), t) : mix(base, vec3(0.12, 0.25, 0.80), -t));
  } else {
    c = light * vec3(0.78, 0.78, 0.80);
  }
  if (u_wire != 0) {
    float d = min(f_edge.x, min(f_edge.y, f_edge.z));
    c = mix(vec3(0.12), c, smoothstep(0.0, 1.0, d));  // about one pixel wide
  }
  o_color = vec4(c, 1.0);
})";

unsigned compile(GLenum type, const char* src) {
  const GLuint s = gl.CreateShader(type);
  gl.ShaderSource(s, 1, &src, nullptr);
  gl.CompileShader(s);
  GLint ok = 0;
  gl.GetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    gl.GetShaderInfoLog(s, sizeof log, nullptr, log);
    gl.DeleteShader(s);
    throw Error(std::string("MeshRenderer: shader compilation failed: ") + log);
  }
  return s;
}

GLint uniform(unsigned program, const char* name) { return gl.GetUniformLocation(program, name); }

}  // namespace

Eigen::MatrixXd vertex_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(V.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::RowVector3d an = (b - a).cross(c - a).transpose();  // twice the area times the normal
    for (int k = 0; k < 3; ++k) N.row(F(f, k)) += an;
  }
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double l = N.row(i).norm();
    if (l > 0) N.row(i) /= l;
  }
  return N;
}

MeshRenderer::MeshRenderer() {
  const unsigned vs = compile(GL_VERTEX_SHADER, kVertex), gs = compile(GL_GEOMETRY_SHADER, kGeometry),
                 fs = compile(GL_FRAGMENT_SHADER, kFragment);
  program_ = gl.CreateProgram();
  for (unsigned s : {vs, gs, fs}) gl.AttachShader(program_, s);
  gl.LinkProgram(program_);
  for (unsigned s : {vs, gs, fs}) gl.DeleteShader(s);
  GLint ok = 0;
  gl.GetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    gl.GetProgramInfoLog(program_, sizeof log, nullptr, log);
    throw Error(std::string("MeshRenderer: program link failed: ") + log);
  }
  gl.GenVertexArrays(1, &vao_);
  unsigned buffers[6];
  gl.GenBuffers(6, buffers);
  vbo_pos_ = buffers[0], vbo_nrm_ = buffers[1], vbo_uv_ = buffers[2], vbo_rest_ = buffers[3],
  ebo_ = buffers[4];
  face_buffer_ = buffers[5];
  unsigned textures[2];
  gl.GenTextures(2, textures);
  face_texture_ = textures[0], colormap_texture_ = textures[1];
  // The colour map as a 256×1 texture: the shader and the colour bar share q_colormap.
  std::vector<std::uint8_t> cmap(256 * 4);
  for (int i = 0; i < 256; ++i) {
    const Eigen::Vector3f c = q_colormap(i / 255.0);
    for (int k = 0; k < 3; ++k) cmap[4 * i + k] = std::uint8_t(std::lround(255 * c[k]));
    cmap[4 * i + 3] = 255;
  }
  gl.BindTexture(GL_TEXTURE_2D, colormap_texture_);
  gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 256, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, cmap.data());
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

MeshRenderer::~MeshRenderer() {
  if (!gl.DeleteProgram) return;
  gl.DeleteProgram(program_);
  gl.DeleteVertexArrays(1, &vao_);
  const unsigned buffers[6] = {vbo_pos_, vbo_nrm_, vbo_uv_, vbo_rest_, ebo_, face_buffer_};
  gl.DeleteBuffers(6, buffers);
  const unsigned textures[2] = {face_texture_, colormap_texture_};
  gl.DeleteTextures(2, textures);
}

void MeshRenderer::set_mesh(const Mesh& mesh) {
  const Eigen::Index n = mesh.V.rows(), m = mesh.F.rows();
  if (mesh.V.cols() != 3 || mesh.F.cols() != 3 || n == 0 || m == 0)
    throw Error("MeshRenderer: expected a non-empty triangle mesh (V n×3, F m×3)");
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c)
      if (mesh.F(f, c) < 0 || mesh.F(f, c) >= n)
        throw Error("MeshRenderer: face " + std::to_string(f) + " has vertex index " +
                    std::to_string(mesh.F(f, c)) + " out of range [0, " + std::to_string(n) + ")");
  has_uv_ = mesh.UV.rows() > 0 && mesh.FUV.rows() == m && mesh.FUV.cols() == 3;
  if (mesh.UV.rows() > 0 && !has_uv_) throw Error("MeshRenderer: FUV does not have one row per face");
  n_ = n, m_ = m, F_ = mesh.F;
  // GPU vertices: one per distinct (vertex, uv) corner pair.
  source_vertex_.clear();
  std::vector<float> uv, rest;
  std::vector<std::uint32_t> index(3 * m);
  if (has_uv_) {
    std::unordered_map<std::int64_t, std::uint32_t> id;
    id.reserve(std::size_t(n) * 2);
    for (Eigen::Index f = 0; f < m; ++f)
      for (int c = 0; c < 3; ++c) {
        const int v = mesh.F(f, c), t = mesh.FUV(f, c);
        if (t < 0 || t >= mesh.UV.rows())
          throw Error("MeshRenderer: face " + std::to_string(f) + " has UV index " + std::to_string(t) +
                      " out of range");
        auto [it, inserted] =
            id.try_emplace(std::int64_t(v) * mesh.UV.rows() + t, std::uint32_t(source_vertex_.size()));
        if (inserted) {
          source_vertex_.push_back(v);
          uv.push_back(float(mesh.UV(t, 0)));
          uv.push_back(float(mesh.UV(t, 1)));
        }
        index[3 * f + c] = it->second;
      }
  } else {
    source_vertex_.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) source_vertex_[i] = int(i);
    uv.assign(2 * n, 0.0f);
    for (Eigen::Index f = 0; f < m; ++f)
      for (int c = 0; c < 3; ++c) index[3 * f + c] = std::uint32_t(mesh.F(f, c));
  }
  // Rest positions scaled so that one unit is one checker cell per bounding-box diagonal.
  const Eigen::RowVector3d lo = mesh.V.colwise().minCoeff(), hi = mesh.V.colwise().maxCoeff();
  diagonal_ = std::max((hi - lo).norm(), 1e-300);
  rest.reserve(3 * source_vertex_.size());
  for (int v : source_vertex_)
    for (int k = 0; k < 3; ++k) rest.push_back(float((mesh.V(v, k) - lo[k]) / diagonal_));

  gl.BindVertexArray(vao_);
  auto attribute = [](unsigned vbo, int location, int size, const std::vector<float>* data,
                      std::size_t count) {
    gl.BindBuffer(GL_ARRAY_BUFFER, vbo);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(count * size * sizeof(float)), data ? data->data() : nullptr,
                  data ? GL_STATIC_DRAW : GL_DYNAMIC_DRAW);
    gl.VertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.EnableVertexAttribArray(location);
  };
  const std::size_t k = source_vertex_.size();
  attribute(vbo_pos_, 0, 3, nullptr, k);
  attribute(vbo_nrm_, 1, 3, nullptr, k);
  attribute(vbo_uv_, 2, 2, &uv, k);
  attribute(vbo_rest_, 3, 3, &rest, k);
  gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_);
  gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(index.size() * 4), index.data(), GL_STATIC_DRAW);
  gl.BindVertexArray(0);
  set_face_values(Eigen::VectorXd::Ones(m));
  set_positions(mesh.V);
}

void MeshRenderer::set_positions(const Eigen::MatrixXd& V) {
  if (V.rows() != n_ || V.cols() != 3)
    throw Error("MeshRenderer: positions are " + std::to_string(V.rows()) + "×" + std::to_string(V.cols()) +
                ", the mesh has " + std::to_string(n_) + " vertices");
  const Eigen::MatrixXd N = vertex_normals(V, F_);
  const std::size_t k = source_vertex_.size();
  pos_.resize(3 * k);
  nrm_.resize(3 * k);
  for (std::size_t i = 0; i < k; ++i)
    for (int c = 0; c < 3; ++c) {
      pos_[3 * i + c] = float(V(source_vertex_[i], c));
      nrm_[3 * i + c] = float(N(source_vertex_[i], c));
    }
  gl.BindBuffer(GL_ARRAY_BUFFER, vbo_pos_);
  gl.BufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(pos_.size() * sizeof(float)), pos_.data());
  gl.BindBuffer(GL_ARRAY_BUFFER, vbo_nrm_);
  gl.BufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(nrm_.size() * sizeof(float)), nrm_.data());
}

void MeshRenderer::set_face_values(const Eigen::VectorXd& values) {
  if (values.size() != m_)
    throw Error("MeshRenderer: " + std::to_string(values.size()) + " face values for " + std::to_string(m_) +
                " faces");
  std::vector<float> v(values.size());
  for (Eigen::Index f = 0; f < values.size(); ++f) v[f] = float(values[f]);  // +inf stays +inf
  gl.BindBuffer(GL_TEXTURE_BUFFER, face_buffer_);
  gl.BufferData(GL_TEXTURE_BUFFER, GLsizeiptr(v.size() * sizeof(float)), v.data(), GL_DYNAMIC_DRAW);
  gl.BindTexture(GL_TEXTURE_BUFFER, face_texture_);
  gl.TexBuffer(GL_TEXTURE_BUFFER, GL_R32F, face_buffer_);
}

void MeshRenderer::draw(const OrbitCamera& camera, int width, int height, const RenderStyle& style) {
  gl.Viewport(0, 0, width, height);
  gl.ClearColor(style.background[0], style.background[1], style.background[2], 1.0f);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (m_ == 0) return;
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LESS);
  gl.Disable(GL_CULL_FACE);
  gl.Disable(GL_BLEND);
  const Eigen::Matrix4f mvp = (camera.projection(double(width) / height) * camera.view()).cast<float>();
  gl.UseProgram(program_);
  gl.UniformMatrix4fv(uniform(program_, "u_mvp"), 1, GL_FALSE, mvp.data());  // column-major, as GL expects
  gl.Uniform2f(uniform(program_, "u_viewport"), float(width), float(height));
  const Eigen::Vector3f eye = camera.eye().cast<float>();
  gl.Uniform3f(uniform(program_, "u_eye"), eye.x(), eye.y(), eye.z());
  const int mode = style.color == ColorMode::Normals   ? 0
                   : style.color == ColorMode::Checker ? 1
                   : style.color == ColorMode::Q       ? 2
                   : style.color == ColorMode::Signed  ? 4
                                                       : 3;
  gl.Uniform1i(uniform(program_, "u_mode"), mode);
  gl.Uniform1i(uniform(program_, "u_smooth"), style.smooth ? 1 : 0);
  gl.Uniform1i(uniform(program_, "u_wire"), style.wireframe ? 1 : 0);
  gl.Uniform1i(uniform(program_, "u_has_uv"), has_uv_ ? 1 : 0);
  const double q_min = std::max(style.q_min, 1.0), q_max = std::max(style.q_max, q_min * (1 + 1e-6));
  gl.Uniform2f(uniform(program_, "u_qrange"), float(std::log(q_min)), float(std::log(q_max / q_min)));
  gl.Uniform1f(uniform(program_, "u_cells"), float(style.checker_cells));
  gl.Uniform1f(uniform(program_, "u_signed"), float(style.signed_range > 0 ? style.signed_range : 1.0));
  gl.ActiveTexture(GL_TEXTURE0);
  gl.BindTexture(GL_TEXTURE_BUFFER, face_texture_);
  gl.Uniform1i(uniform(program_, "u_face"), 0);
  gl.ActiveTexture(GL_TEXTURE1);
  gl.BindTexture(GL_TEXTURE_2D, colormap_texture_);
  gl.Uniform1i(uniform(program_, "u_colormap"), 1);
  gl.ActiveTexture(GL_TEXTURE0);
  gl.BindVertexArray(vao_);
  gl.DrawElements(GL_TRIANGLES, GLsizei(3 * m_), GL_UNSIGNED_INT, nullptr);
  gl.BindVertexArray(0);
  gl.UseProgram(0);
}

}  // namespace spinmotor::render

// Writes the seed corpora of the fuzz targets: `fuzz_make_corpus DIR` (DIR = fuzz/corpus) fills
// DIR/fuzz_<name>/ with small valid inputs, most of them written by the project's own writers, so that
// fuzzing starts from files that reach deep into each reader. A target whose input starts with a
// selector byte (image, weights, scalars) gets it here too. The whole corpus stays well under 200 kB.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/mesh/gltf_rig_writer.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/procedural_rig.hpp"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace fs = std::filesystem;
using spinmotor::Mesh;

namespace {

fs::path root;

fs::path dir(const std::string& target) {
  const fs::path d = root / ("fuzz_" + target);
  fs::create_directories(d);
  return d;
}

void put(const std::string& target, const std::string& name, const std::string& bytes) {
  std::ofstream(dir(target) / name, std::ios::binary) << bytes;
}

std::string get(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A writer's output as bytes (written to a scratch file first), optionally after a selector byte.
template <class Write>
std::string written(const std::string& ext, Write write) {
  const fs::path tmp = spinmotor::fuzz::scratch_dir() / ("seed" + ext);
  write(tmp);
  return get(tmp);
}

void meshes() {
  const Mesh tetra = spinmotor::fuzz::tetrahedron();
  const Mesh ico = spinmotor::icosphere(0);  // 12 vertices, with per-corner UVs (OBJ vt)
  for (const auto& [name, mesh] : {std::pair{"tetrahedron", tetra}, std::pair{"icosahedron", ico}}) {
    put("obj", std::string(name) + ".obj", written(".obj", [&](auto p) { spinmotor::write_obj(p, mesh); }));
    put("off", std::string(name) + ".off", written(".off", [&](auto p) { spinmotor::write_off(p, mesh); }));
    put("ply", std::string(name) + "_binary.ply",
        written(".ply", [&](auto p) { spinmotor::write_ply(p, mesh, true); }));
    put("ply", std::string(name) + "_ascii.ply",
        written(".ply", [&](auto p) { spinmotor::write_ply(p, mesh, false); }));
    put("stl", std::string(name) + "_binary.stl",
        written(".stl", [&](auto p) { spinmotor::write_stl(p, mesh, true); }));
    put("stl", std::string(name) + "_ascii.stl",
        written(".stl", [&](auto p) { spinmotor::write_stl(p, mesh, false); }));
  }
  // What other writers emit: OBJ quads, v//vn, negative indices, statements the reader skips.
  put("obj", "quads_normals_relative.obj",
      "# a cube corner\nmtllib x.mtl\no corner\nv 0 0 0\nv 1 0 0 1\nv 1 1 0 0.5 0.5 0.5\nv 0 1 0\n"
      "vn 0 0 1\nvt 0 0\nvt 1 0\nvt 1 1 0\nvt 0 1\ng side\ns off\nusemtl m\nf 1/1/1 2/2/1 3/3/1 4/4/1\n"
      "f -4/-4 -2/-2 -1/-1\nl 1 2\n");
  put("obj", "faces_before_vertices.obj", "f 1//1 2//1 3//1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\n");
  put("off", "coff_quad_comments.off",
      "COFF\n# colours per vertex\n4 2 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n"
      "0 1 0 1 1 1 255\n4 0 1 2 3 0.5 0.5 0.5\n3 0 2 3\n");
  put("off", "counts_on_header_line.off", "NOFF 3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n");
  put("ply", "ascii_float_extra_properties.ply",
      "ply\nformat ascii 1.0\ncomment extra properties are skipped\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nproperty uchar red\nelement face 1\n"
      "property list uchar int vertex_indices\nproperty float quality\nelement edge 1\nproperty int a\n"
      "end_header\n0 0 0 255\n1 0 0 0\n0 1 0 7\n3 0 1 2 0.5\n4\n");
  {  // big-endian float vertices, a uint16-counted uint32 list (vertex_index)
    std::string b =
        "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list ushort uint vertex_index\nend_header\n";
    auto be = [&](std::uint32_t v, int bytes) {
      for (int k = bytes - 1; k >= 0; --k) b += static_cast<char>((v >> (8 * k)) & 0xff);
    };
    for (const float x : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) {
      std::uint32_t u;
      std::memcpy(&u, &x, 4);
      be(u, 4);
    }
    be(3, 2);
    for (std::uint32_t i : {0u, 1u, 2u}) be(i, 4);
    put("ply", "binary_big_endian_float.ply", b);
  }
}

void gltf() {
  spinmotor::LimbRigOptions o;
  o.rings = 3;
  o.sides = 3;
  o.joints = 2;
  const spinmotor::GltfRig rig = spinmotor::limb_rig(o);
  const Mesh tetra = spinmotor::fuzz::tetrahedron();
  const std::vector<Eigen::MatrixXd> frames = {tetra.V, tetra.V * 1.5};
  for (const std::string ext : {"gltf", "glb"}) {
    put(ext, "limb_rig." + ext, written("." + ext, [&](auto p) { spinmotor::write_gltf_rig(p, rig); }));
    put(ext, "baked_tetrahedron." + ext, written("." + ext, [&](auto p) {
          spinmotor::write_gltf_morph_animation(p, tetra, frames, {0.0, 0.5});
        }));
  }
}

void images() {
  const unsigned char gray[12] = {0, 40, 80, 120, 160, 200, 240, 255, 7, 70, 170, 250};
  const unsigned char rgba[16] = {255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 0, 9, 99, 199, 255};
  auto to_string = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size);
  };
  for (const int rle : {0, 1}) {
    stbi_write_tga_with_rle = rle;
    std::string s(1, '\0');  // selector: even = .tga
    stbi_write_tga_to_func(to_string, &s, 4, 3, 1, gray);
    put("image", rle ? "gray_4x3_rle.tga" : "gray_4x3.tga", s);
    s.assign(1, '\0');
    stbi_write_tga_to_func(to_string, &s, 2, 2, 4, rgba);
    put("image", rle ? "rgba_2x2_rle.tga" : "rgba_2x2.tga", s);
  }
  std::string s(1, '\1');  // selector: odd = .png
  stbi_write_png_to_func(to_string, &s, 4, 3, 1, gray, 4);
  put("image", "gray_4x3.png", s);
  s.assign(1, '\1');
  stbi_write_png_to_func(to_string, &s, 2, 2, 4, rgba, 8);
  put("image", "rgba_2x2.png", s);
  s.assign(1, '\1');
  stbi_write_png_to_func(to_string, &s, 2, 2, 3, rgba, 6);
  put("image", "rgb_2x2.png", s);
}

// Scenes: the shapes of tests/data/scenes and docs/scene.md at fuzz sizes. Files they name live in the
// target's scratch directory (fuzz_scene.cpp): tetra.obj and limb.gltf.
void scenes() {
  const std::string tube =
      R"("mesh": {"generate": "tube", "radius": 0.5, "length": 4, "rings": 5, "sides": 6)";
  const std::string ends =
      R"("handles": [
    {"name": "base", "select": {"box": {"min": [-1, -1, -0.01], "max": [1, 1, 0.01]}}},
    {"name": "tip", "select": {"box": {"min": [-1, -1, 3.99], "max": [1, 1, 4.01]}}}
  ])";
  put("scene", "surface_harmonic_pose.json", "{\n  " + tube + R"(, "capped": true},
  )" + ends + R"(,
  "deformer": {"type": "surface-harmonic", "weights": "mean-value", "blend": "log"},
  "pose": {"tip": {"rotate": {"axis": [1, 0, 0], "degrees": 60, "about": [0, 0, 4]}, "translate": [0, 0.5, 0]}},
  "output": {"mesh": "out/sh_tube.obj", "metrics": "out/sh_tube.json", "colors": "out/sh_tube_q.ply"}
}
)");
  put("scene", "frames_snap.json", "{\n  " + tube + R"(, "capped": false},
  )" + ends + R"(,
  "deformer": {"type": "surface-harmonic", "blend": "dlb"},
  "frames": [{}, {"tip": {"rotate": {"axis": [0, 1, 0], "degrees": 30, "about": [0, 0, 4]}}}],
  "snap": {"enabled": true, "tradeoff": 0.5}
}
)");
  put("scene", "spline_ik.json", "{\n  " + tube + R"(},
  )" + ends + R"(,
  "deformer": {"type": "spline", "basis": "bspline", "degree": 3, "from": "base", "to": "tip"},
  "ik": {"chain": [[0, 0, 0], [0, 0, 2], [0, 0, 4]], "target": [1.5, 0, 3.2], "tolerance": 1e-4,
         "iterations": 100, "orientation": {"axis": [0, 1, 0], "degrees": 20}}
}
)");
  put("scene", "spline_keys_motor_forms.json", "{\n  " + tube + R"(},
  "handles": [
    {"name": "base", "select": {"plane": {"point": [0, 0, 0.01], "normal": [0, 0, -1]}}},
    {"name": "tip", "select": {"plane": {"point": [0, 0, 3.99], "normal": [0, 0, 1]}}}
  ],
  "deformer": {"type": "spline", "basis": "bezier", "from": "base", "to": "tip", "keys": ["k0", "k1", "k2"]},
  "pose": {
    "k1": {"quaternion": [0.9659258262890683, 0.25881904510252074, 0, 0]},
    "k2": {"matrix": [1, 0, 0, 0, 0, 0.8660254037844387, -0.5, 0.2, 0, 0.5, 0.8660254037844387, 0, 0, 0, 0, 1]}
  },
  "output": {"mesh": "out/keys.off"}
}
)");
  put("scene", "file_vertices_pinned_snap.json", R"({
  "mesh": "tetra.obj",
  "handles": [{"name": "a", "select": {"vertices": [0]}}, {"name": "b", "select": {"sphere": {"center": [0, 0, 1], "radius": 0.1}}}],
  "deformer": {"type": "arap"},
  "pose": {"b": {"translate": [0, 0, 0.2]}},
  "snap": {"mode": "pinned", "pins": ["a", "b"], "keep": "volume", "iterations": 5, "pose_weight": 1}
}
)");
  put("scene", "skeleton_skin_weights_pins.json", R"({
  "mesh": {"generate": "capsule", "radius": 0.5, "length": 2, "rings": 4, "sides": 4},
  "skeleton": {"bones": [{"name": "upper", "head": [0, 0, 0], "tail": [0, 0, 1]},
                         {"name": "lower", "parent": "upper", "head": [0, 0, 1], "tail": [0, 0, 2]}]},
  "deformer": {"type": "skin", "weights": "harmonic", "blend": "lbs"},
  "pose": {"lower": {"rotate": {"axis": [1, 0, 0], "degrees": 45, "about": [0, 0, 1]}}},
  "snap": {"pins": "weights", "pin_threshold": 0.99}
}
)");
  put("scene", "rig_frames_fps.json", R"({
  "rig": {"gltf": "limb.gltf", "animation": "bend", "frames": [0, 2], "fps": 2},
  "deformer": {"type": "skin", "blend": "dlb"},
  "pose": {"joint1": {"rotate": {"axis": [0, 0, 1], "degrees": 10}}}
}
)");
  put("scene", "rig_time.json",
      R"({"rig": {"gltf": "limb.gltf", "animation": 1, "time": 0.5}, "deformer": {"type": "skin"}})");
  put("scene", "generators.json", R"({
  "mesh": {"generate": "torus", "R": 2, "r": 0.5, "u": 6, "v": 4},
  "handles": [{"name": "all", "select": {"all": true}}],
  "deformer": {"type": "ffd", "lattice": [2, 2, 2]}
}
)");
  put("scene", "cage_grid.json", R"({
  "mesh": {"generate": "grid", "size": [2, 2], "n": [3, 3]},
  "deformer": {"type": "cage", "cage": "tetra.obj"}
}
)");
}

void small_files() {
  const std::string tetra_weights_text =
      "# root, tip\nbones root tip\n1 0\n0.5 0.5  # blend\n\n0 1\n0.25 0.75\n";
  put("weights", "text.txt", std::string(1, '\0') + tetra_weights_text);
  put("weights", "text_columns_swapped.txt",
      std::string(1, '\0') + "bones tip root\n0 1\n0.5 0.5\n1 0\n1e-3 2\n");
  put("weights", "json.json",
      std::string(1, '\1') +
          R"({"bones": ["root", "tip"], "weights": [[1, 0], [0.5, 0.5], [0, 1], [0.25, 0.75]]})");
  put("weights", "json_columns_swapped.json",
      std::string(1, '\1') +
          R"({"bones": ["tip", "root"], "weights": [[0, 1], [1, 1], [3, 0], [0.1, 0.2]]})");

  put("scalars", "four_values.txt", std::string(1, '\4') + "# rho per face\n0.5 -1\n2e-1\n  3\n");
  put("scalars", "four_pins.txt", std::string(1, '\4') + "0\n3 # pinned\n\n1 2\n");
  put("scalars", "twelve_values.txt", std::string(1, '\14') + "0 1 2 3 4 5\n-0.5 1e3 +7 .25 1E-2 -0\n");

  const char* expressions[] = {"5 * sin(3*x) * cos(2*y) - 0.5*z^2",
                               "-x^2 + 2^3^2",
                               "sqrt(r) + pi*e",
                               "exp(-(x^2 + y^2) / 0.1)",
                               "atan(y / x) + abs(z) - acos(0.5) + asin(-1)",
                               "1e-3 * log(1 + r) / tan(0.3)",
                               "tanh(sinh(cosh(+x)))"};
  int k = 0;
  for (const char* e : expressions) put("expression", "expression_" + std::to_string(k++) + ".txt", e);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR (the corpus folder, fuzz/corpus)\n", argv[0]);
    return 2;
  }
  root = argv[1];
  meshes();
  gltf();
  images();
  scenes();
  small_files();
  return 0;
}

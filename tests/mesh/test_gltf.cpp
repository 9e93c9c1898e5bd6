// glTF 2.0 rigs (mesh/gltf.hpp, deform/gltf_animation.hpp, deform/gltf_skin.hpp, `spinmotor rig`).
//
// Always run: a tiny two-joint bar written by the test itself (JSON + base64 buffer, also as a side
// .bin and as .glb) with closed-form skinning, sampling (LINEAR slerp, STEP, CUBICSPLINE, clamping),
// weight renormalisation and welding, and one broken variant per error the reader must name.
// With ../shared/rigs: the four samples against the independent evaluation of the glTF formula
// x = Σ w_j W_j IBM_j (v + Σ m_k d_k) of support/gltf_reference.hpp.
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cli_support.hpp"
#include "gltf_reference.hpp"
#include "shared_data.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/gltf_animation.hpp"
#include "spinmotor/deform/gltf_skin.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/scene/rig_cleanup.hpp"
#include "spinmotor/scene/rig_pose.hpp"

namespace test_gltf {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using spinmotor::Error;
using spinmotor::GltfRig;

const std::string kRigs = SPINMOTOR_RIGS_DIR;

// ---- base64, written here (independent of tinygltf's) ---------------------------------------------

const char* kB64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string b64encode(const std::vector<uint8_t>& in) {
  std::string out;
  for (size_t i = 0; i < in.size(); i += 3) {
    const uint32_t v =
        (in[i] << 16) | (i + 1 < in.size() ? in[i + 1] << 8 : 0) | (i + 2 < in.size() ? in[i + 2] : 0);
    out += kB64[(v >> 18) & 63];
    out += kB64[(v >> 12) & 63];
    out += i + 1 < in.size() ? kB64[(v >> 6) & 63] : '=';
    out += i + 2 < in.size() ? kB64[v & 63] : '=';
  }
  return out;
}

// ---- a tiny rig written by the test ------------------------------------------------------------------
//
// A bar in the xy plane, x ∈ [0, 2], y ∈ [0, 1]: two quads (four triangles). File vertex 4 repeats the
// position (1, 0, 0) of file vertex 1 with another UV (a seam), so 7 file vertices weld into 6.
// Joints: 0 'base' at the origin, 1 'tip' at (1, 0, 0), child of base (IBM translate(−1, 0, 0)).
// Weights (base, tip): x = 0 -> (1, 0); x = 1 -> (½, ½); x = 2 -> (0, 1); file vertex 3 = (1, 1, 0)
// has (¼, ¼) (sum ½: renormalised to (½, ½)).
// Animations: 0 'bend' LINEAR rotation of tip, 0° -> 90° about z over t ∈ [0, 1];
//             1 'step' STEP translation of base: (0,0,0), (1,0,0), (2,0,0) at t = 0, 1, 2;
//             2 'cubic' CUBICSPLINE translation of base over [0, 2]: v0 = 0, b0 = (0,2,0),
//               a1 = (0,0,4), v1 = (1,0,0).
struct Tiny {
  json j;
  std::vector<uint8_t> bin;

  int view(const void* data, size_t n) {
    while (bin.size() % 4) bin.push_back(0);
    const size_t off = bin.size();
    bin.insert(bin.end(), static_cast<const uint8_t*>(data), static_cast<const uint8_t*>(data) + n);
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", off}, {"byteLength", n}});
    return static_cast<int>(j["bufferViews"].size()) - 1;
  }
  int floats(const std::vector<float>& v, const std::string& type, size_t comps) {
    const int bv = view(v.data(), v.size() * 4);
    j["accessors"].push_back(
        {{"bufferView", bv}, {"componentType", 5126}, {"count", v.size() / comps}, {"type", type}});
    return static_cast<int>(j["accessors"].size()) - 1;
  }
  int ubytes(const std::vector<uint8_t>& v, const std::string& type, size_t comps, bool normalized) {
    const int bv = view(v.data(), v.size());
    j["accessors"].push_back({{"bufferView", bv},
                              {"componentType", 5121},
                              {"count", v.size() / comps},
                              {"type", type},
                              {"normalized", normalized}});
    return static_cast<int>(j["accessors"].size()) - 1;
  }
  int ushorts(const std::vector<uint16_t>& v, const std::string& type, size_t comps) {
    const int bv = view(v.data(), v.size() * 2);
    j["accessors"].push_back(
        {{"bufferView", bv}, {"componentType", 5123}, {"count", v.size() / comps}, {"type", type}});
    return static_cast<int>(j["accessors"].size()) - 1;
  }
  json with_buffer(const std::string& uri) const {
    json out = j;
    out["buffers"] = json::array({{{"byteLength", bin.size()}}});
    if (!uri.empty()) out["buffers"][0]["uri"] = uri;
    return out;
  }
  void write_embedded(const fs::path& p) const {
    std::ofstream(p) << with_buffer("data:application/octet-stream;base64," + b64encode(bin)).dump();
  }
  void write_side_bin(const fs::path& p) const {
    const fs::path b = fs::path(p).replace_extension(".bin");
    std::ofstream(b, std::ios::binary)
        .write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
    std::ofstream(p) << with_buffer(b.filename().string()).dump();
  }
  void write_glb(const fs::path& p) const {
    std::string js = with_buffer("").dump();
    while (js.size() % 4) js += ' ';
    std::vector<uint8_t> b = bin;
    while (b.size() % 4) b.push_back(0);
    auto u32 = [](std::ofstream& o, uint32_t v) { o.write(reinterpret_cast<const char*>(&v), 4); };
    std::ofstream o(p, std::ios::binary);
    o.write("glTF", 4);
    u32(o, 2);
    u32(o, static_cast<uint32_t>(12 + 8 + js.size() + 8 + b.size()));
    u32(o, static_cast<uint32_t>(js.size()));
    o.write("JSON", 4);
    o.write(js.data(), static_cast<std::streamsize>(js.size()));
    u32(o, static_cast<uint32_t>(b.size()));
    o.write("BIN\0", 4);
    o.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
  }
};

struct TinyOptions {
  float nan_at_x = 0;        // position x of file vertex 2 (NaN to break it)
  uint16_t index0 = 0;       // the first index (99: out of range)
  uint16_t joint_of_v6 = 1;  // second joint slot of file vertex 6 (5: out of range)
};

Tiny bar_rig(const TinyOptions& o = {}) {
  Tiny t;
  t.j["asset"] = {{"version", "2.0"}};
  t.j["scene"] = 0;
  t.j["scenes"] = json::array({{{"nodes", {0}}}});
  const float s = static_cast<float>(std::sqrt(0.5));
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, o.nan_at_x, 1, 0, 1, 1, 0, 1, 0, 0, 2, 0, 0, 2, 1, 0};
  const std::vector<float> uv = {0, 0, 0.5f, 0, 0, 1, 0.5f, 1, 0.9f, 0, 1, 0, 1, 1};
  const std::vector<uint16_t> joints = {
      0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, o.joint_of_v6, 0, 0};
  const std::vector<float> weights = {1, 0, 0,    0,    0.5f, 0.5f, 0, 0, 1, 0, 0, 0, 0.25f, 0.25f,
                                      0, 0, 0.5f, 0.5f, 0,    0,    0, 1, 0, 0, 0, 1, 0,     0};
  const std::vector<uint16_t> idx = {o.index0, 1, 3, 0, 3, 2, 4, 5, 6, 4, 6, 3};
  const int a_pos = t.floats(pos, "VEC3", 3), a_uv = t.floats(uv, "VEC2", 2);
  const int a_j = t.ushorts(joints, "VEC4", 4), a_w = t.floats(weights, "VEC4", 4),
            a_i = t.ushorts(idx, "SCALAR", 1);
  std::vector<float> ibm(32, 0.0f);
  for (int m = 0; m < 2; ++m)
    for (int d = 0; d < 4; ++d) ibm[16 * m + 5 * d] = 1.0f;
  ibm[16 + 12] = -1.0f;  // column-major: translation of matrix 1 in entries 12..14
  const int a_ibm = t.floats(ibm, "MAT4", 16);
  t.j["meshes"] = json::array(
      {{{"name", "bar"},
        {"primitives",
         json::array({{{"attributes",
                        {{"POSITION", a_pos}, {"TEXCOORD_0", a_uv}, {"JOINTS_0", a_j}, {"WEIGHTS_0", a_w}}},
                       {"indices", a_i}}})}}});
  t.j["skins"] = json::array({{{"joints", {1, 2}}, {"inverseBindMatrices", a_ibm}}});
  t.j["nodes"] = json::array({{{"name", "root"}, {"children", {1, 3}}},
                              {{"name", "base"}, {"children", {2}}},
                              {{"name", "tip"}, {"translation", {1, 0, 0}}},
                              {{"name", "body"}, {"mesh", 0}, {"skin", 0}}});
  const int t01 = t.floats({0, 1}, "SCALAR", 1), rot = t.floats({0, 0, 0, 1, 0, 0, s, s}, "VEC4", 4);
  const int t012 = t.floats({0, 1, 2}, "SCALAR", 1), stp = t.floats({0, 0, 0, 1, 0, 0, 2, 0, 0}, "VEC3", 3);
  const int t02 = t.floats({0, 2}, "SCALAR", 1);
  const int cub = t.floats({9, 9, 9, 0, 0, 0, 0, 2, 0, 0, 0, 4, 1, 0, 0, 9, 9, 9}, "VEC3", 3);
  auto anim = [&](const char* name, int in, int out, const char* interp, int node, const char* path) {
    return json{{"name", name},
                {"samplers", json::array({{{"input", in}, {"output", out}, {"interpolation", interp}}})},
                {"channels", json::array({{{"sampler", 0}, {"target", {{"node", node}, {"path", path}}}}})}};
  };
  t.j["animations"] = json::array({anim("bend", t01, rot, "LINEAR", 2, "rotation"),
                                   anim("step", t012, stp, "STEP", 1, "translation"),
                                   anim("cubic", t02, cub, "CUBICSPLINE", 1, "translation")});
  return t;
}

struct Scratch {
  fs::path dir;
  Scratch() : dir(fs::temp_directory_path() / ("spinmotor_gltf_test_" + std::to_string(getpid()))) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
};

Eigen::RowVector3d row(double x, double y, double z) { return {x, y, z}; }

/// read_gltf must throw Error whose message contains every `needle`.
void expect_error(const fs::path& p, const std::vector<std::string>& needles) {
  try {
    spinmotor::read_gltf(p);
    FAIL("no error for " << p);
  } catch (const Error& e) {
    const std::string msg = e.what();
    INFO(msg);
    CHECK(e.kind() == Error::Kind::BadInput);
    CHECK(msg.find(p.filename().string()) != std::string::npos);
    for (const auto& n : needles) CHECK(msg.find(n) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("gltf tiny rig: welding, per-corner UVs, renormalised weights, inverse bind matrices") {
  Scratch s;
  const fs::path p = s.dir / "bar.gltf";
  bar_rig().write_embedded(p);
  const GltfRig rig = spinmotor::read_gltf(p);
  CHECK(rig.file_vertices == 7);
  CHECK(rig.mesh.num_vertices() == 6);  // file vertex 4 welded onto 1
  CHECK(rig.mesh.num_faces() == 4);
  CHECK(rig.dropped_faces == 0);
  CHECK(rig.file_to_surface[4] == rig.file_to_surface[1]);
  CHECK(rig.file_to_surface[5] == 4);
  REQUIRE(rig.pieces.size() == 1);
  CHECK(rig.pieces[0].name == "body");
  CHECK(rig.nodes[rig.pieces[0].node].name == "body");
  CHECK(rig.vertex_label(rig.file_to_surface[5]) == "mesh 'body' primitive 0 vertex 5");
  REQUIRE(rig.num_joints() == 2);
  CHECK(rig.joint_names == std::vector<std::string>{"base", "tip"});
  CHECK(rig.joint_parents == std::vector<int>{-1, 0});
  CHECK(rig.inverse_bind[1](0, 3) == -1.0);
  // UVs stay per corner (v flipped to OBJ's convention): the seam keeps both UVs of (1, 0, 0).
  REQUIRE(rig.mesh.has_uv());
  CHECK(rig.mesh.UV.rows() == 7);
  CHECK(rig.mesh.UV.row(rig.mesh.FUV(2, 0))
            .isApprox(Eigen::RowVector2d(0.9, 1.0), 1e-7));  // corner of file vertex 4
  CHECK(rig.mesh.UV.row(rig.mesh.FUV(0, 1))
            .isApprox(Eigen::RowVector2d(0.5, 1.0), 1e-7));  // corner of file vertex 1
  CHECK(rig.mesh.F(2, 0) == rig.mesh.F(0, 1));
  // Weights: file vertex 3 summed to ½ and was renormalised.
  CHECK(rig.renormalised_rows == 1);
  CHECK(rig.min_weight_sum == Approx(0.5));
  CHECK(rig.weld_weight_mismatches == 0);
  CHECK(rig.weights.coeff(rig.file_to_surface[3], 0) == Approx(0.5));
  CHECK(rig.weights.coeff(rig.file_to_surface[3], 1) == Approx(0.5));
  const Eigen::VectorXd sums = rig.weights * Eigen::VectorXd::Ones(2);
  CHECK((sums.array() - 1.0).abs().maxCoeff() < 1e-15);
  CHECK(rig.warnings.size() == 1);
  // Rest pose: the bind pose reproduces the positions exactly (IBMs are exact inverses here).
  CHECK((spinmotor::skin_positions(rig, -1, 0.0) - rig.mesh.V).cwiseAbs().maxCoeff() < 1e-15);
  // The bones at the bind pose: base at the origin, tip at (1, 0, 0); the rest pose is the bind pose.
  const spinmotor::RigSkin skin = spinmotor::rig_skin(rig);
  CHECK(skin.rig.skeleton[1].head.isApprox(Eigen::Vector3d(1, 0, 0)));
  CHECK(skin.bind[0].isApprox(Eigen::Matrix4d::Identity()));
  CHECK(spinmotor::gltf_bind_pose(rig).deviation < 1e-15);

  // The same rig from a side .bin and from a .glb reads identically.
  const fs::path pb = s.dir / "side.gltf", pg = s.dir / "bar.glb";
  bar_rig().write_side_bin(pb);
  bar_rig().write_glb(pg);
  for (const fs::path& q : {pb, pg}) {
    INFO(q);
    const GltfRig r = spinmotor::read_gltf(q);
    CHECK(r.mesh.V == rig.mesh.V);
    CHECK(r.mesh.F == rig.mesh.F);
    CHECK(r.mesh.UV == rig.mesh.UV);
    CHECK(Eigen::MatrixXd(r.weights) == Eigen::MatrixXd(rig.weights));
    CHECK(r.animations.size() == 3);
  }

  // A side file outside the glTF file's folder is refused, by a relative path or a symbolic link.
  fs::create_directories(s.dir / "asset");
  Tiny out = bar_rig();
  std::ofstream(s.dir / "secret.bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(out.bin.data()), static_cast<std::streamsize>(out.bin.size()));
  std::ofstream(s.dir / "asset" / "up.gltf") << out.with_buffer("../secret.bin").dump();
  CHECK_THROWS_WITH(spinmotor::read_gltf(s.dir / "asset" / "up.gltf"),
                    Catch::Contains("up.gltf") && Catch::Contains("outside the glTF file's folder"));
  fs::create_symlink(s.dir / "secret.bin", s.dir / "asset" / "link.bin");
  std::ofstream(s.dir / "asset" / "link.gltf") << out.with_buffer("link.bin").dump();
  CHECK_THROWS_WITH(spinmotor::read_gltf(s.dir / "asset" / "link.gltf"),
                    Catch::Contains("outside the glTF file's folder"));
  // the same buffer in the folder reads
  fs::copy_file(s.dir / "secret.bin", s.dir / "asset" / "inside.bin");
  std::ofstream(s.dir / "asset" / "inside.gltf") << out.with_buffer("inside.bin").dump();
  CHECK(spinmotor::read_gltf(s.dir / "asset" / "inside.gltf").mesh.V == rig.mesh.V);
}

TEST_CASE(
    "gltf variants: two primitives, byte weights, JOINTS_1, sparse accessors, no inverse bind matrices") {
  Scratch s;
  const fs::path p0 = s.dir / "bar.gltf";
  bar_rig().write_embedded(p0);
  const GltfRig ref = spinmotor::read_gltf(p0);
  const Eigen::MatrixXd ref_bend = spinmotor::skin_positions(ref, 0, 0.5);
  auto variant = [&](const char* name, const std::function<void(Tiny&)>& edit) {
    Tiny t = bar_rig();
    edit(t);
    const fs::path p = s.dir / name;
    t.write_embedded(p);
    return spinmotor::read_gltf(p);
  };
  auto prim = [](Tiny& t) -> json& { return t.j["meshes"][0]["primitives"][0]; };

  // Two primitives (one quad each) over the same attributes: 14 file vertices weld into the same 6.
  const GltfRig two = variant("two.gltf", [&](Tiny& t) {
    json second = prim(t);
    second["indices"] = t.ushorts({4, 5, 6, 4, 6, 3}, "SCALAR", 1);
    prim(t)["indices"] = t.ushorts({0, 1, 3, 0, 3, 2}, "SCALAR", 1);
    t.j["meshes"][0]["primitives"].push_back(second);
  });
  CHECK(two.file_vertices == 14);
  CHECK(two.mesh.V == ref.mesh.V);
  CHECK(two.mesh.F == ref.mesh.F);
  CHECK(two.mesh.FUV.bottomRows(2).minCoeff() >= 7);  // the second primitive's corners, UVs per file vertex
  CHECK(two.renormalised_rows == 2);
  CHECK((spinmotor::skin_positions(two, 0, 0.5) - ref_bend).cwiseAbs().maxCoeff() < 1e-15);

  // Normalised unsigned byte weights and byte joints; vertex 0's weight split over WEIGHTS_0 and WEIGHTS_1.
  const GltfRig bytes = variant("bytes.gltf", [&](Tiny& t) {
    const std::vector<uint8_t> j = {0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1,
                                    0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0};
    const std::vector<uint8_t> w = {51, 0, 0,   0,   128, 128, 0, 0,   255, 0, 0, 0,   64, 64,
                                    0,  0, 128, 128, 0,   0,   0, 255, 0,   0, 0, 255, 0,  0};
    std::vector<uint8_t> j1(28, 0), w1(28, 0);
    w1[0] = 204;  // vertex 0: 51/255 + 204/255 = 1 on joint 0
    prim(t)["attributes"]["JOINTS_0"] = t.ubytes(j, "VEC4", 4, false);
    prim(t)["attributes"]["WEIGHTS_0"] = t.ubytes(w, "VEC4", 4, true);
    prim(t)["attributes"]["JOINTS_1"] = t.ubytes(j1, "VEC4", 4, false);
    prim(t)["attributes"]["WEIGHTS_1"] = t.ubytes(w1, "VEC4", 4, true);
  });
  CHECK(Eigen::MatrixXd(bytes.weights).isApprox(Eigen::MatrixXd(ref.weights), 1e-15));
  // 128/255 · 2 is 1 to within the half steps of the 8 stored bytes (4/255): not counted; 64/255 · 2 is.
  CHECK(bytes.renormalised_rows == 1);
  CHECK(bytes.min_weight_sum == Approx(128.0 / 255));

  // A sparse accessor replaces the UV of file vertex 2 (glTF (0, 1) -> (0.25, 0.75)).
  const GltfRig sparse = variant("sparse.gltf", [&](Tiny& t) {
    const std::vector<uint16_t> idx = {2, 0};  // one index (padded to 4 bytes)
    const std::vector<float> val = {0.25f, 0.75f};
    const int iv = t.view(idx.data(), 2), vv = t.view(val.data(), 8);
    t.j["accessors"][1]["sparse"] = {{"count", 1},
                                     {"indices", {{"bufferView", iv}, {"componentType", 5123}}},
                                     {"values", {{"bufferView", vv}}}};
  });
  CHECK(sparse.mesh.UV.row(2).isApprox(Eigen::RowVector2d(0.25, 0.25)));
  CHECK(sparse.mesh.UV.row(1) == ref.mesh.UV.row(1));

  // Without inverseBindMatrices every IBM is the identity (spec): at rest the tip's translation moves
  // the vertices it carries by (1, 0, 0).
  const GltfRig noibm = variant("noibm.gltf", [](Tiny& t) { t.j["skins"][0].erase("inverseBindMatrices"); });
  CHECK(noibm.inverse_bind[1] == Eigen::Matrix4d::Identity());
  CHECK(spinmotor::skin_positions(noibm, -1, 0.0).row(noibm.file_to_surface[5]).isApprox(row(3, 0, 0)));

  // A uniform scale on a joint: the file's rest pose is then not its bind pose. The rest surface is the
  // bind pose (the skin's root joint 'base' places it); every blend reproduces the spec's matrices for
  // a vertex that one joint moves (closed form: (2, 0, 0) → IBM (1, 0, 0) → scale 2 → (3, 0, 0)).
  const GltfRig grown = variant("grown.gltf", [](Tiny& t) { t.j["nodes"][2]["scale"] = {2, 2, 2}; });
  const int g5 = grown.file_to_surface[5];
  CHECK(spinmotor::skin_positions(grown, -1, 0).row(g5).isApprox(row(3, 0, 0)));
  CHECK(spinmotor::rig_skin(grown).rest.V.row(g5).isApprox(row(2, 0, 0)));
  const spinmotor::GltfBindPose bp = spinmotor::gltf_bind_pose(grown);
  CHECK(bp.joint == 1);
  CHECK(bp.deviation > 0.2);
  using B = spinmotor::SkinBlend;
  for (B b : {B::LBS, B::DLB, B::Log, B::PivotLog}) {
    INFO("blend " << static_cast<int>(b));
    spinmotor::RigSkinner k(grown, b);
    Eigen::MatrixXd V;
    k.pose(-1, 0.0, V);
    CHECK(V.row(g5).isApprox(row(3, 0, 0), 1e-12));
    CHECK(V.row(grown.file_to_surface[0]).isApprox(row(0, 0, 0), 1e-12));
  }

  // A non-uniform scale above the mesh node and the joints scales the scene: the spec multiplies the
  // joints' global matrices (the mesh node's own transform is ignored).
  const GltfRig scaled_root = variant("root.gltf", [](Tiny& t) { t.j["nodes"][0]["scale"] = {1, 2, 1}; });
  const Eigen::MatrixXd stretched = ref_bend * Eigen::Vector3d(1, 2, 1).asDiagonal();
  CHECK((spinmotor::skin_positions(scaled_root, 0, 0.5) - stretched).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((spinmotor::rig_skin(scaled_root).rest.V - ref.mesh.V * Eigen::Vector3d(1, 2, 1).asDiagonal())
            .cwiseAbs()
            .maxCoeff() < 1e-15);
  {
    spinmotor::RigSkinner k(scaled_root, B::LBS);
    Eigen::MatrixXd V;
    k.pose(0, 0.5, V);
    CHECK((V - stretched).cwiseAbs().maxCoeff() < 1e-12);
  }
  // A transform on the skinned node changes nothing (§3.7.3: it is ignored).
  const GltfRig moved = variant("moved.gltf", [](Tiny& t) { t.j["nodes"][3]["translation"] = {5, 6, 7}; });
  CHECK((spinmotor::skin_positions(moved, 0, 0.5) - ref_bend).cwiseAbs().maxCoeff() < 1e-15);
  // Strips and fans are triangulated as the spec orders them (§3.7.2.1).
  const GltfRig strip = variant("strip.gltf", [&](Tiny& t) {
    prim(t)["mode"] = 5;
    prim(t)["indices"] = t.ushorts({0, 1, 2, 3}, "SCALAR", 1);
  });
  REQUIRE(strip.mesh.num_faces() == 2);
  CHECK(strip.mesh.F.row(0) == Eigen::RowVector3i(0, 1, 2));
  CHECK(strip.mesh.F.row(1) == Eigen::RowVector3i(1, 3, 2));  // {v_i, v_(i+1+i%2), v_(i+2−i%2)}, i = 1
}

TEST_CASE("gltf sampling: LINEAR slerp, STEP, CUBICSPLINE and clamping in closed form") {
  Scratch s;
  const fs::path p = s.dir / "bar.gltf";
  bar_rig().write_embedded(p);
  const GltfRig rig = spinmotor::read_gltf(p);
  REQUIRE(rig.animations.size() == 3);
  CHECK(rig.animations[0].name == "bend");
  CHECK(rig.animations[0].duration() == 1.0);
  CHECK(rig.animations[1].duration() == 2.0);
  CHECK(rig.animations[2].end == 2.0);

  // LINEAR rotation: 0° -> 90° about z; at t = 0.3 the slerp is 27° (a lerp of the quaternions is not).
  const spinmotor::GltfChannel& bend = rig.animations[0].channels[0];
  const double a = 0.3 * M_PI / 2;
  const Eigen::Vector4d q = spinmotor::sample_channel(bend, 0.3);
  CHECK(q.isApprox(Eigen::Vector4d(0, 0, std::sin(a / 2), std::cos(a / 2)), 1e-7));
  CHECK(spinmotor::sample_channel(bend, -5.0).isApprox(Eigen::Vector4d(0, 0, 0, 1)));  // clamped
  CHECK(spinmotor::sample_channel(bend, 7.0).isApprox(Eigen::Vector4d(0, 0, std::sqrt(0.5), std::sqrt(0.5)),
                                                      1e-7));  // clamped

  // STEP: the value of the last key at or before t.
  const spinmotor::GltfChannel& step = rig.animations[1].channels[0];
  CHECK(spinmotor::sample_channel(step, 0.999).isApprox(Eigen::Vector3d(0, 0, 0)));
  CHECK(spinmotor::sample_channel(step, 1.0) == Eigen::Vector3d(1, 0, 0));
  CHECK(spinmotor::sample_channel(step, 1.5) == Eigen::Vector3d(1, 0, 0));
  CHECK(spinmotor::sample_channel(step, 2.5) == Eigen::Vector3d(2, 0, 0));

  // CUBICSPLINE (spec Appendix C) at t = 0.5, u = ¼, t_d = 2: p = h01 v1 + t_d h10 b0 + t_d h11 a1 with
  // h01 = −2u³ + 3u² = 0.15625, h10 = u³ − 2u² + u = 0.140625, h11 = u³ − u² = −0.046875.
  const spinmotor::GltfChannel& cubic = rig.animations[2].channels[0];
  CHECK(spinmotor::sample_channel(cubic, 0.5).isApprox(Eigen::Vector3d(0.15625, 0.5625, -0.375), 1e-12));
  CHECK(spinmotor::sample_channel(cubic, 2.0) == Eigen::Vector3d(1, 0, 0));

  // The node hierarchy follows: the tip's world matrix at 'step' t = 1.5 is translate(2, 0, 0).
  const auto W = spinmotor::node_world_matrices(rig, 1, 1.5);
  CHECK(W[rig.joint_nodes[1]].topRightCorner<3, 1>().isApprox(Eigen::Vector3d(2, 0, 0)));
  const auto Wc = spinmotor::node_world_matrices(rig, 2, 0.5);
  CHECK(Wc[rig.joint_nodes[1]].topRightCorner<3, 1>().isApprox(Eigen::Vector3d(1.15625, 0.5625, -0.375),
                                                               1e-12));
  CHECK_THROWS_AS(spinmotor::node_world_matrices(rig, 3, 0.0), Error);
  CHECK_THROWS_AS(spinmotor::node_world_matrices(rig, 0, std::nan("")), Error);
}

TEST_CASE("gltf skinning of the tiny rig in closed form, matrices and every SkinDeformer blend") {
  Scratch s;
  const fs::path p = s.dir / "bar.gltf";
  bar_rig().write_embedded(p);
  const GltfRig rig = spinmotor::read_gltf(p);
  const double c = std::sqrt(0.5);
  const int v_x1 = rig.file_to_surface[1], v_x1y1 = rig.file_to_surface[3], v_x2 = rig.file_to_surface[5],
            v_x2y1 = rig.file_to_surface[6];

  // 'bend' at t = 0.5: the tip turns 45° about (1, 0, 0).
  const auto S = spinmotor::joint_matrices(rig, spinmotor::node_world_matrices(rig, 0, 0.5));
  CHECK(S[0].isApprox(Eigen::Matrix4d::Identity()));
  const Eigen::MatrixXd L = spinmotor::skin_positions(rig, 0, 0.5);
  CHECK(L.row(v_x2).isApprox(row(1 + c, c, 0), 1e-7));
  CHECK(L.row(v_x2y1).isApprox(row(1, 2 * c, 0), 1e-7));
  CHECK(L.row(v_x1).isApprox(row(1, 0, 0), 1e-7));
  // (1, 1, 0) with the renormalised (½, ½): the mean of (1, 1, 0) and (1 − c, c, 0).
  CHECK(L.row(v_x1y1).isApprox(row(1 - c / 2, (1 + c) / 2, 0), 1e-7));

  using B = spinmotor::SkinDeformer::Blend;
  for (B b : {B::LBS, B::DLB, B::Log, B::PivotLog}) {
    INFO("blend " << static_cast<int>(b));
    spinmotor::RigSkinner d(rig, b);
    Eigen::MatrixXd V;
    d.pose(-1, 0.0, V);
    CHECK((V - rig.mesh.V).cwiseAbs().maxCoeff() < 1e-12);
    d.pose(0, 0.5, V);
    CHECK(V.row(v_x2).isApprox(row(1 + c, c, 0), 1e-7));
    if (b == B::LBS) {
      CHECK((V - L).cwiseAbs().maxCoeff() < 1e-7);
    } else {
      // Motor blends of the identity and a 45° turn about (1, 0, 0) with weights ½: the 22.5° turn.
      const double h = M_PI / 8;
      CHECK(V.row(v_x1y1).isApprox(row(1 - std::sin(h), std::cos(h), 0), 1e-7));
    }
  }
}

TEST_CASE("gltf reader errors name the file and the element") {
  Scratch s;
  int k = 0;
  auto broken = [&](const std::function<void(Tiny&)>& edit, const TinyOptions& o = {}) {
    Tiny t = bar_rig(o);
    edit(t);
    const fs::path p = s.dir / ("broken" + std::to_string(k++) + ".gltf");
    t.write_embedded(p);
    return p;
  };
  auto prim = [](Tiny& t) -> json& { return t.j["meshes"][0]["primitives"][0]; };
  expect_error(broken([&](Tiny& t) { prim(t)["attributes"].erase("POSITION"); }),
               {"no POSITION", "primitive 0", "'bar'"});
  expect_error(broken([&](Tiny& t) { prim(t)["mode"] = 1; }),
               {"mesh 'bar'", "has no triangles"});  // lines: skipped
  expect_error(broken([&](Tiny& t) { prim(t)["mode"] = 7; }), {"mode 7", "not a glTF primitive mode"});
  TinyOptions bad_index;
  bad_index.index0 = 99;
  expect_error(broken([](Tiny&) {}, bad_index), {"accessor 4", "index 0 = 99", "out of range"});
  TinyOptions bad_joint;
  bad_joint.joint_of_v6 = 5;
  expect_error(broken([](Tiny&) {}, bad_joint), {"accessor 2", "JOINTS_0", "vertex 6", "joint 5"});
  TinyOptions nan;
  nan.nan_at_x = std::nanf("");
  expect_error(broken([](Tiny&) {}, nan), {"accessor 0", "POSITION", "element 2", "not finite"});
  expect_error(broken([&](Tiny& t) {
                 prim(t)["targets"] = json::array({{{"POSITION", 1}}});
               }),
               {"accessor 1", "morph target 0", "type VEC2, expected VEC3"});
  expect_error(broken([&](Tiny& t) {
                 json second = prim(t);
                 second["targets"] = json::array({{{"POSITION", 0}}});
                 t.j["meshes"][0]["primitives"].push_back(second);
               }),
               {"primitive 1", "1 morph targets", "first primitive has 0"});
  expect_error(broken([&](Tiny& t) { t.j["meshes"][0]["weights"] = {0.5}; }),
               {"1 morph weights for 0 targets"});
  {
    spinmotor::GltfReadOptions named;
    named.meshes = {"nope"};
    const fs::path q = broken([](Tiny&) {});
    CHECK_THROWS_WITH(spinmotor::read_gltf(q, named),
                      Catch::Contains("no skinned mesh named 'nope'") && Catch::Contains("'body'"));
    named.meshes = {"bar"};  // the mesh's name reads the same piece
    CHECK(spinmotor::read_gltf(q, named).pieces.at(0).name == "body");
  }
  expect_error(broken([](Tiny& t) { t.j["animations"][1]["samplers"][0]["interpolation"] = "SMOOTH"; }),
               {"step", "interpolation 'SMOOTH'"});
  expect_error(broken([](Tiny& t) { t.j["nodes"][3].erase("skin"); }), {"no skinned mesh"});
  expect_error(broken([](Tiny& t) { t.j["accessors"][5]["count"] = 1; }),
               {"inverseBindMatrices", "1 matrices for 2 joints"});
  expect_error(broken([](Tiny& t) { t.j["accessors"][4]["count"] = 11; }), {"not a multiple of 3"});
  expect_error(broken([](Tiny& t) { t.j["accessors"][0]["count"] = 700; }),
               {"accessor 0", "overrun bufferView"});
  expect_error(broken([](Tiny& t) { t.j["nodes"][2]["children"] = {1}; }), {"two parents"});
  expect_error(broken([](Tiny& t) { t.j["extensionsRequired"] = {"KHR_draco_mesh_compression"}; }),
               {"KHR_draco"});
  // A file that is not JSON, a missing file, a wrong extension.
  const fs::path junk = s.dir / "junk.gltf";
  std::ofstream(junk) << "{ not json";
  expect_error(junk, {});
  expect_error(s.dir / "missing.gltf", {"no such file"});
  const fs::path obj = s.dir / "bar.obj";
  std::ofstream(obj) << "v 0 0 0\n";
  expect_error(obj, {".gltf or .glb"});
}

TEST_CASE("gltf baked output: morph targets and a STEP weights animation read back with tinygltf") {
  Scratch s;
  const fs::path p = s.dir / "bar.gltf";
  bar_rig().write_embedded(p);
  const GltfRig rig = spinmotor::read_gltf(p);
  std::vector<Eigen::MatrixXd> frames;
  std::vector<double> times;
  for (int f = 0; f < 3; ++f) {
    times.push_back(spinmotor::gltf_frame_time(rig.animations[0], f, 3));
    frames.push_back(spinmotor::skin_positions(rig, 0, times.back()));
  }
  CHECK(times == std::vector<double>{0.0, 0.5, 1.0});
  for (const char* name : {"baked.gltf", "baked.glb"}) {
    INFO(name);
    const fs::path out = s.dir / name;
    Eigen::Matrix4d place = Eigen::Matrix4d::Identity();
    place(2, 3) = 5.0;
    spinmotor::write_gltf_morph_animation(out, rig.mesh, frames, times, "bar baked", place);
    tinygltf::TinyGLTF loader;
    tinygltf::Model m;
    std::string err, warn;
    const bool ok = std::string(name).ends_with(".glb")
                        ? loader.LoadBinaryFromFile(&m, &err, &warn, out.string())
                        : loader.LoadASCIIFromFile(&m, &err, &warn, out.string());
    INFO(err);
    REQUIRE(ok);
    auto floats = [&](int acc) {
      const auto& a = m.accessors[acc];
      const auto& bv = m.bufferViews[a.bufferView];
      const int comps = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
      std::vector<float> v(a.count * comps);
      std::memcpy(v.data(), m.buffers[bv.buffer].data.data() + bv.byteOffset + a.byteOffset, v.size() * 4);
      return v;
    };
    REQUIRE(m.meshes.size() == 1);
    const auto& pr = m.meshes[0].primitives[0];
    REQUIRE(pr.targets.size() == 3);
    const std::vector<float> pos = floats(pr.attributes.at("POSITION")),
                             uv = floats(pr.attributes.at("TEXCOORD_0"));
    CHECK(pos.size() == 7 * 3);  // un-welded at the UV seam: 7 glTF vertices again
    // Every glTF vertex: rest position = a surface vertex r; rest + target f = frame f of r (float32).
    for (size_t k = 0; k < pos.size() / 3; ++k) {
      const Eigen::RowVector3d x(pos[3 * k], pos[3 * k + 1], pos[3 * k + 2]);
      Eigen::Index r = 0;
      CHECK((rig.mesh.V.rowwise() - x).rowwise().norm().minCoeff(&r) < 1e-7);
      for (int f = 0; f < 3; ++f) {
        const std::vector<float> d = floats(pr.targets[f].at("POSITION"));
        const Eigen::RowVector3d y = x + Eigen::RowVector3d(d[3 * k], d[3 * k + 1], d[3 * k + 2]);
        CHECK((y - frames[f].row(r)).norm() < 1e-6);
      }
    }
    // UVs back in glTF's convention: the seam vertex (1, 0, 0) appears with u = 0.5 and u = 0.9, v = 0.
    std::multiset<float> us;
    for (size_t k = 0; k < pos.size() / 3; ++k)
      if (pos[3 * k] == 1.0f && pos[3 * k + 1] == 0.0f) {
        us.insert(uv[2 * k]);
        CHECK(uv[2 * k + 1] == 0.0f);
      }
    CHECK(us == std::multiset<float>{0.5f, 0.9f});
    // The animation: STEP on the mesh node's weights, one-hot per key; the mesh node is the child of a
    // root node that carries the placement.
    REQUIRE(m.animations.size() == 1);
    const auto& an = m.animations[0];
    CHECK(an.samplers[0].interpolation == "STEP");
    CHECK(an.channels[0].target_path == "weights");
    CHECK(an.channels[0].target_node == 1);
    REQUIRE(m.nodes.size() == 2);
    CHECK(m.nodes[1].mesh == 0);
    CHECK(m.nodes[0].children == std::vector<int>{1});
    CHECK(m.nodes[0].name == "bar baked");
    REQUIRE(m.nodes[0].matrix.size() == 16);
    CHECK(m.nodes[0].matrix[14] == 5.0);  // column-major translation z
    const tinygltf::Value& names = m.meshes[0].extras.Get("targetNames");
    REQUIRE(names.IsArray());
    CHECK(names.ArrayLen() == 3);
    CHECK(names.Get(2).Get<std::string>() == "frame 0002");
    CHECK(m.meshes[0].weights == std::vector<double>{1, 0, 0});
    CHECK(floats(an.samplers[0].input) == std::vector<float>{0.0f, 0.5f, 1.0f});
    CHECK(floats(an.samplers[0].output) == std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 1});
  }
  CHECK_THROWS_AS(spinmotor::write_gltf_morph_animation(s.dir / "x.gltf", rig.mesh, frames, {0.0, 1.0}),
                  Error);
  CHECK_THROWS_AS(spinmotor::write_gltf_morph_animation(s.dir / "x.gltf", rig.mesh, frames, {0.0, 1.0, 1.0}),
                  Error);
  CHECK(!fs::exists(s.dir / "x.gltf"));
}

TEST_CASE("gltf baked output read back: read_gltf_morph_animation, RigPoser and bake_rig_gltf") {
  Scratch s;
  const fs::path p = s.dir / "bar.gltf";
  bar_rig().write_embedded(p);
  const GltfRig rig = spinmotor::read_gltf(p);
  spinmotor::scene::RigPoseOptions lbs;  // animation 0, LBS (the defaults, said here)
  lbs.animation = 0;
  lbs.blend = spinmotor::SkinBlend::LBS;
  spinmotor::scene::RigPoser poser(rig, lbs);
  const std::vector<double> times = spinmotor::scene::rig_frame_times(rig, 0, 3);
  CHECK(times == std::vector<double>{0.0, 0.5, 1.0});
  for (const char* name : {"bar.glb", "bar-baked.gltf"}) {
    INFO(name);
    const fs::path out = s.dir / name;
    const std::vector<Eigen::MatrixXd> written = spinmotor::scene::bake_rig_gltf(out, poser, times, "bar");
    REQUIRE(written.size() == 3);
    const spinmotor::GltfMorphAnimation back = spinmotor::read_gltf_morph_animation(out);
    // Welding the un-welded glTF vertices returns the rig's surface in its own vertex order, exactly
    // (its positions were float32 already).
    CHECK(back.mesh.V == rig.mesh.V);
    CHECK(back.mesh.F == rig.mesh.F);
    REQUIRE(back.mesh.has_uv());
    for (Eigen::Index f = 0; f < rig.mesh.F.rows(); ++f)
      for (int k = 0; k < 3; ++k)
        CHECK((back.mesh.UV.row(back.mesh.FUV(f, k)) - rig.mesh.UV.row(rig.mesh.FUV(f, k))).norm() < 1e-7);
    CHECK(back.times == times);  // 0, 0.5, 1 are exact in float32
    CHECK(back.name == "body");  // one mesh node per piece, named after it
    REQUIRE(back.pieces.size() == 1);
    CHECK(back.node_matrix == Eigen::Matrix4d::Identity());
    REQUIRE(back.frames.size() == 3);
    for (size_t f = 0; f < 3; ++f) {
      CHECK(written[f] == poser.pose(times[f]));  // the baker poses with the poser
      // the independent reference: the glTF formula with matrices (bend 90° about z at t = 1)
      CHECK((written[f] - spinmotor::skin_positions(rig, 0, times[f])).cwiseAbs().maxCoeff() < 1e-6);
      CHECK((back.frames[f] - written[f]).cwiseAbs().maxCoeff() < 1e-6);  // float32 displacements
    }
    CHECK((back.frames[0] - rig.mesh.V).cwiseAbs().maxCoeff() < 1e-7);  // t = 0 is the rest pose
  }
  // The bind space: a root translation (0, 0, 5) above the joints places the scene; baked in mesh space
  // the positions are the POSITION frame's and the root node carries the bind matrix.
  Tiny lifted = bar_rig();
  lifted.j["nodes"][0]["translation"] = {0, 0, 5};
  lifted.write_embedded(s.dir / "lifted.gltf");
  const GltfRig up = spinmotor::read_gltf(s.dir / "lifted.gltf");
  spinmotor::scene::RigPoseOptions in_mesh;
  in_mesh.space = spinmotor::scene::RigSpace::Mesh;
  spinmotor::scene::RigPoser placed(up, in_mesh);
  const auto baked = spinmotor::scene::bake_rig_gltf(s.dir / "placed.glb", placed, {0.25});
  const spinmotor::GltfMorphAnimation placed_back =
      spinmotor::read_gltf_morph_animation(s.dir / "placed.glb");
  Eigen::Matrix4d lift = Eigen::Matrix4d::Identity();
  lift(2, 3) = 5;
  CHECK(placed_back.node_matrix.isApprox(lift));
  CHECK(placed_back.mesh.V == up.mesh.V);
  CHECK((baked[0] - (spinmotor::skin_positions(up, 0, 0.25).rowwise() - Eigen::RowVector3d(0, 0, 5)))
            .cwiseAbs()
            .maxCoeff() < 1e-12);
  // Errors name the problem and write nothing.
  CHECK_THROWS_WITH(spinmotor::read_gltf_morph_animation(p), Catch::Contains("no mesh with morph targets"));
  CHECK_THROWS_WITH(spinmotor::read_gltf_morph_animation(s.dir / "none.glb"),
                    Catch::Contains("no such file"));
  CHECK_THROWS_WITH(spinmotor::read_gltf(s.dir / "bar.glb"), Catch::Contains("no skinned mesh"));
  spinmotor::scene::RigPoseOptions third;
  third.animation = 3;
  CHECK_THROWS_WITH(spinmotor::scene::RigPoser(rig, third), Catch::Contains("out of range"));
  CHECK_THROWS_WITH(spinmotor::scene::bake_rig_gltf(s.dir / "bad.glb", poser, {0.5, 0.5}),
                    Catch::Contains("not after the previous"));
  CHECK(!fs::exists(s.dir / "bad.glb"));
}

TEST_CASE("spinmotor rig info and pose on the tiny rig, bad input exits 2 and writes nothing") {
  spinmotor_test::TempDir tmp;
  const fs::path p = tmp.path / "bar.gltf";
  bar_rig().write_embedded(p);
  auto r = spinmotor_test::run_cli(tmp.path, "rig info " + tmp.file("bar.gltf") + " --json");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const json j = json::parse(r.out);
  CHECK(j["surface"]["vertices"] == 6);
  CHECK(j["surface"]["file_vertices"] == 7);
  CHECK(j["surface"]["faces"] == 4);
  REQUIRE(j["pieces"].size() == 1);
  CHECK(j["pieces"][0]["name"] == "body");
  CHECK(j["joints"].size() == 2);
  CHECK(j["joints"][1]["parent"] == 0);
  CHECK(j["weights"]["renormalised_rows"] == 1);
  CHECK(j["animations"].size() == 3);
  CHECK(j["animations"][2]["duration"] == 2.0);
  CHECK(j["bind_pose_deviation"] == 0.0);

  r = spinmotor_test::run_cli(tmp.path, "rig pose " + tmp.file("bar.gltf") +
                                            " --frames 3 --blend dlb --out " + tmp.file("out/f.obj"));
  INFO(r.err);
  REQUIRE(r.code == 0);
  for (const char* f : {"f.0000.obj", "f.0001.obj", "f.0002.obj"}) CHECK(fs::exists(tmp.path / "out" / f));
  CHECK(std::distance(fs::directory_iterator(tmp.path / "out"), fs::directory_iterator{}) ==
        3);  // no staging left
  const spinmotor::Mesh last = spinmotor::read_mesh(tmp.path / "out" / "f.0002.obj");
  CHECK(last.V.row(4).isApprox(row(1, 1, 0), 1e-9));  // 'bend' at t = 1: (2, 0, 0) turned 90° about (1, 0, 0)
  CHECK(last.has_uv());

  r = spinmotor_test::run_cli(
      tmp.path, "rig pose " + tmp.file("bar.gltf") + " --time 0.5 --out " + tmp.file("one.ply"));
  CHECK(r.code == 0);
  CHECK(spinmotor::read_mesh(tmp.path / "one.ply").V.rows() == 6);

  // --space scene (the default) is the file's scene (here the root's translation (0, 0, 5) above the
  // joints); --space mesh the POSITION frame; --rest-out writes the bind pose in the same space.
  Tiny lifted = bar_rig();
  lifted.j["nodes"][0]["translation"] = {0, 0, 5};
  lifted.write_embedded(tmp.path / "lifted.gltf");
  r = spinmotor_test::run_cli(tmp.path, "rig pose " + tmp.file("lifted.gltf") +
                                            " --time 1 --space scene --out " + tmp.file("lifted.obj") +
                                            " --rest-out " + tmp.file("lifted-rest.obj"));
  REQUIRE(r.code == 0);
  CHECK(spinmotor::read_mesh(tmp.path / "lifted.obj").V.row(4).isApprox(row(1, 1, 5), 1e-9));
  CHECK(spinmotor::read_mesh(tmp.path / "lifted-rest.obj").V.row(4).isApprox(row(2, 0, 5), 1e-9));
  r = spinmotor_test::run_cli(tmp.path, "rig pose " + tmp.file("lifted.gltf") +
                                            " --time 1 --space mesh --out " + tmp.file("lifted-mesh.obj"));
  REQUIRE(r.code == 0);
  CHECK(spinmotor::read_mesh(tmp.path / "lifted-mesh.obj").V.row(4).isApprox(row(1, 1, 0), 1e-9));
  // --json: every frame's figures (Q before and after, the volume ratio) for `metrics REST POSED` users.
  r = spinmotor_test::run_cli(
      tmp.path, "rig pose " + tmp.file("bar.gltf") + " --frames 2 --json --out " + tmp.file("j/f.obj"));
  REQUIRE(r.code == 0);
  const json pj = json::parse(r.out);
  REQUIRE(pj["frames"].size() == 2);
  CHECK(pj["frames"][1]["skinned"]["q_mean"].get<double>() > 1.0);
  CHECK(pj["frames"][1]["time"] == 1.0);

  // Bad input: nothing written.
  std::ofstream(tmp.path / "junk.gltf") << "{";
  for (const std::string args : {"--frames 0", "--frames 2 --time 1", "--frames 2 --blend foo",
                                 "--frames 2 --animation 7", "--frames 2 --cleanup sideways"}) {
    INFO(args);
    r = spinmotor_test::run_cli(
        tmp.path, "rig pose " + tmp.file("bar.gltf") + " " + args + " --out " + tmp.file("bad/f.obj"));
    CHECK(r.code == 2);
    CHECK(!fs::exists(tmp.path / "bad"));
  }
  // A scaling joint (the tip grows 1 → 2 over [0, 1]) is posed as the spec says, by every blend; a frame
  // that fails mid-sequence (the tip mirrored at t = 0.5: no rigid motion for a motor blend) leaves nothing.
  Tiny grow = bar_rig();
  {
    const int out = grow.floats({1, 1, 1, 2, 2, 2}, "VEC3", 3),
              flip = grow.floats({1, 1, 1, -1, 1, 1}, "VEC3", 3);
    for (const auto& [name, values] : {std::pair<const char*, int>{"grow", out}, {"flip", flip}})
      grow.j["animations"].push_back(
          {{"name", name},
           {"samplers", json::array({{{"input", 6}, {"output", values}, {"interpolation", "STEP"}}})},
           {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 2}, {"path", "scale"}}}}})}});
  }
  grow.write_embedded(tmp.path / "grow.gltf");
  r = spinmotor_test::run_cli(tmp.path, "rig pose " + tmp.file("grow.gltf") +
                                            " --animation grow --time 1 --blend dlb --out " +
                                            tmp.file("grown.obj"));
  REQUIRE(r.code == 0);
  CHECK(spinmotor::read_mesh(tmp.path / "grown.obj").V.row(4).isApprox(row(3, 0, 0), 1e-9));  // IBM, ×2, +1
  r = spinmotor_test::run_cli(tmp.path, "rig pose " + tmp.file("grow.gltf") +
                                            " --animation flip --frames 3 --blend dlb --out " +
                                            tmp.file("bad/f.obj"));
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Catch::Contains("'tip'") && Catch::Contains("t = 1") && Catch::Contains("mirrors"));
  CHECK(!fs::exists(tmp.path / "bad"));
  r = spinmotor_test::run_cli(
      tmp.path, "rig pose " + tmp.file("junk.gltf") + " --frames 2 --out " + tmp.file("bad/f.obj"));
  CHECK(r.code == 2);
  CHECK(r.err.find("junk.gltf") != std::string::npos);
  r = spinmotor_test::run_cli(
      tmp.path, "rig pose " + tmp.file("bar.gltf") + " --frames 2 --out " + tmp.file("bad/f.xyz"));
  CHECK(r.code == 2);
  CHECK(!fs::exists(tmp.path / "bad"));
  r = spinmotor_test::run_cli(tmp.path, "rig info " + tmp.file("missing.gltf"));
  CHECK(r.code == 2);
  for (const char* help : {"rig --help", "rig info --help", "rig pose --help"}) {
    r = spinmotor_test::run_cli(tmp.path, help);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("Examples") && Catch::Contains("spinmotor rig pose"));
  }
}

// ---- the shared rigs against the independent evaluation -------------------------------------------

namespace {

struct Expected {
  const char* file;
  int file_vertices, welded, faces, joints, renormalised, animations;
  double min_sum;
  bool uv, closed;
};

double diagonal(const Eigen::MatrixXd& V) { return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm(); }

/// max over file vertices of |ours(file_to_surface[i]) − ref[i]|.
double worst(const GltfRig& rig, const Eigen::MatrixXd& ours, const std::vector<Eigen::Vector3d>& ref) {
  REQUIRE(static_cast<Eigen::Index>(ref.size()) == rig.file_vertices);
  double m = 0;
  for (Eigen::Index i = 0; i < rig.file_vertices; ++i)
    m = std::max(m, (ours.row(rig.file_to_surface[i]).transpose() - ref[i]).norm());
  return m;
}

/// The rigid motions of the pose transforms (the shared rigs' joints do not scale) as motors.
std::vector<spinmotor::ga::Mot> rigid_motors(const std::vector<spinmotor::SkinDeformer::Affine>& T) {
  std::vector<spinmotor::ga::Mot> out;
  for (const auto& A : T) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(A.leftCols<3>(), Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
    M.linear() = svd.matrixU() * svd.matrixV().transpose();
    M.translation() = A.col(3);
    out.push_back(spinmotor::ga::normalize(spinmotor::ga::from_isometry(M)));
  }
  return out;
}

}  // namespace

TEST_CASE("gltf shared rigs: counts, welds and the glTF formula against the independent evaluation to 1e-9") {
  SPINMOTOR_REQUIRE_RIGS();
  // Numbers from the files (README of ../shared/rigs), recomputed from the JSON below.
  for (const Expected& e : {Expected{"RiggedSimple.gltf", 96, 96, 188, 2, 0, 1, 1.0, false, true},
                            Expected{"RiggedFigure.gltf", 370, 130, 256, 19, 31, 1, 0.2001, false, true},
                            Expected{"CesiumMan.gltf", 3273, 2338, 4672, 19, 210, 1, 0.1847, true, true},
                            Expected{"Fox.glb", 1728, 290, 576, 24, 0, 3, 1.0, true, true}}) {
    INFO(e.file);
    const fs::path p = fs::path(kRigs) / e.file;
    const GltfRig rig = spinmotor::read_gltf(p);
    const spinmotor::test::GltfReference ref(p);
    CHECK(rig.file_vertices == e.file_vertices);
    CHECK(rig.mesh.num_vertices() == e.welded);
    CHECK(rig.mesh.num_faces() == e.faces);
    CHECK(rig.num_joints() == e.joints);
    CHECK(rig.renormalised_rows == e.renormalised);
    CHECK(rig.min_weight_sum == Approx(e.min_sum).margin(1e-4));
    CHECK(rig.mesh.has_uv() == e.uv);
    CHECK(rig.weld_weight_mismatches == 0);
    CHECK(rig.dropped_faces == 0);
    CHECK(static_cast<int>(rig.animations.size()) == e.animations);
    REQUIRE(rig.pieces.size() == 1);
    // Independently from the JSON: distinct positions = welded vertices.
    const json& attr = ref.j["meshes"][0]["primitives"][0]["attributes"];
    const auto P = ref.accessor(attr["POSITION"]);
    CHECK(static_cast<int>(P.size()) == rig.file_vertices);
    CHECK(static_cast<Eigen::Index>(std::set<std::vector<double>>(P.begin(), P.end()).size()) ==
          rig.mesh.num_vertices());
    // The samples weld into closed manifolds (every edge in two faces, Euler characteristic 2).
    std::map<std::pair<int, int>, int> edges;
    for (Eigen::Index f = 0; f < rig.mesh.F.rows(); ++f)
      for (int q = 0; q < 3; ++q) {
        const int a = rig.mesh.F(f, q), b = rig.mesh.F(f, (q + 1) % 3);
        ++edges[{std::min(a, b), std::max(a, b)}];
      }
    bool two = true;
    for (const auto& [edge, count] : edges) two = two && count == 2;
    CHECK(two == e.closed);
    if (e.closed)
      CHECK(rig.mesh.num_vertices() - static_cast<Eigen::Index>(edges.size()) + rig.mesh.num_faces() == 2);

    // The rest pose, then three times of every animation: the spec's formula (skin_positions) and the
    // skinner's LBS (every influence, matrices) to 1e-9 of the diagonal of the independent evaluation.
    const spinmotor::RigSkin skin = spinmotor::rig_skin(rig);
    const double diag = diagonal(skin.rest.V);
    CHECK(worst(rig, spinmotor::skin_positions(rig, -1, 0.0), ref.skin(-1, 0.0)) < 1e-9 * diag);
    CHECK(worst(rig, skin.rest.V, ref.skin(-1, 0.0)) < 1e-5 * diag);  // rest pose = bind pose (float32)
    spinmotor::RigSkinner lbs(rig, spinmotor::SkinBlend::LBS);
    double worst_formula = 0, worst_skinner = 0;
    for (int a = 0; a < static_cast<int>(rig.animations.size()); ++a)
      for (double frac : {0.2, 0.55, 0.9}) {
        const double t = rig.animations[a].start + frac * rig.animations[a].duration();
        const auto r = ref.skin(a, t);
        const Eigen::MatrixXd ours = spinmotor::skin_positions(rig, a, t);
        Eigen::MatrixXd viaskin;
        lbs.pose(a, t, viaskin);
        worst_formula = std::max(worst_formula, worst(rig, ours, r));
        worst_skinner = std::max(worst_skinner, worst(rig, viaskin, r));
        // The pose moves the mesh (the test is not vacuous): by more than 1% of the diagonal somewhere.
        CHECK((ours - skin.rest.V).rowwise().norm().maxCoeff() > 0.01 * diag);
      }
    CHECK(worst_formula < 1e-9 * diag);
    CHECK(worst_skinner < 1e-9 * diag);
    WARN(e.file << ": diag " << diag << ", formula vs independent " << worst_formula / diag
                << " diag, skinner LBS vs independent " << worst_skinner / diag << " diag");
  }
}

TEST_CASE("gltf shared rigs: DLB, Log and PivotLog approach LBS to second order for small motions") {
  SPINMOTOR_REQUIRE_RIGS();
  using B = spinmotor::SkinDeformer::Blend;
  for (const char* file : {"RiggedFigure.gltf", "CesiumMan.gltf", "Fox.glb"}) {
    const GltfRig rig = spinmotor::read_gltf(fs::path(kRigs) / file);
    const spinmotor::RigSkin skin = spinmotor::rig_skin(rig);
    const double diag = diagonal(skin.rest.V);
    const double t = rig.animations[0].start + 0.55 * rig.animations[0].duration();
    const auto K = rigid_motors(spinmotor::rig_joint_transforms(rig, skin, 0, t));
    // Motions K_j^ε = exp(ε log K_j): ε → 0 is the rest pose.
    auto scaled = [&](double eps) {
      std::vector<spinmotor::ga::Mot> out;
      for (const auto& k : K) out.push_back(spinmotor::ga::exp(eps * spinmotor::ga::log(k)));
      return out;
    };
    spinmotor::SkinDeformer lbs = spinmotor::SkinDeformer::bind(skin.rest, skin.rig, {.blend = B::LBS});
    for (B b : {B::DLB, B::Log, B::PivotLog}) {
      INFO(file << " blend " << static_cast<int>(b));
      spinmotor::SkinDeformer d = spinmotor::SkinDeformer::bind(skin.rest, skin.rig, {.blend = b});
      double dist[3];
      const double eps[3] = {1.0, 0.1, 0.05};
      for (int k = 0; k < 3; ++k) {
        Eigen::MatrixXd a, c;
        lbs.pose(scaled(eps[k]), a);
        d.pose(scaled(eps[k]), c);
        dist[k] = (a - c).rowwise().norm().maxCoeff() / diag;
      }
      WARN(file << " blend " << static_cast<int>(b) << ": max |blend − LBS| / diag = " << dist[0]
                << " (full pose), " << dist[1] << " (ε = 0.1), " << dist[2] << " (ε = 0.05)");
      CHECK(dist[1] < 5e-4);
      CHECK(dist[2] / dist[1] > 0.2);  // second order: halving ε quarters the distance
      CHECK(dist[2] / dist[1] < 0.3);
    }
  }
}

TEST_CASE("spinmotor rig on CesiumMan: info numbers, a baked glb and the CLI cleanup is the library's") {
  SPINMOTOR_REQUIRE_RIGS();
  spinmotor_test::TempDir tmp;
  const std::string file = "'" + kRigs + "/CesiumMan.gltf'";
  auto r = spinmotor_test::run_cli(tmp.path, "rig info " + file + " --json");
  REQUIRE(r.code == 0);
  const json j = json::parse(r.out);
  CHECK(j["surface"]["vertices"] == 2338);
  CHECK(j["surface"]["file_vertices"] == 3273);
  CHECK(j["joints"].size() == 19);
  CHECK(j["weights"]["renormalised_rows"] == 210);
  CHECK(j["weights"]["max_influences"] == 4);
  CHECK(j["animations"][0]["duration"] == 2.0);
  CHECK(j["bind_pose_deviation"].get<double>() < 1e-5);  // README: bind pose = rest pose to 1.0e-6
  for (const char* space : {"scene", "mesh"}) {
    INFO(space);
    r = spinmotor_test::run_cli(tmp.path, "rig pose " + file + " --frames 5 --blend pivot-log --space " +
                                              space + " --out " + tmp.file("baked.glb"));
    INFO(r.err);
    REQUIRE(r.code == 0);
    tinygltf::TinyGLTF loader;
    tinygltf::Model m;
    std::string err, warn;
    REQUIRE(loader.LoadBinaryFromFile(&m, &err, &warn, (tmp.path / "baked.glb").string()));
    CHECK(m.meshes[0].primitives[0].targets.size() == 5);
    CHECK(m.accessors[m.meshes[0].primitives[0].attributes.at("POSITION")].count ==
          3273);  // re-split at UV seams
    CHECK(m.nodes[0].matrix.empty() ==
          (std::string(space) == "scene"));  // mesh: the bind matrix (Z-up -> Y-up)
    CHECK(m.animations[0].samplers[0].interpolation == "STEP");
  }
  // --cleanup pinned is the library's RigCleanup with its defaults (scene/rig_cleanup.hpp), bit for bit
  // through the shortest round-trip OBJ digits; --pose-weight reaches it.
  const GltfRig rig = spinmotor::read_gltf(fs::path(kRigs) / "CesiumMan.gltf");
  const spinmotor::RigSkin skin = spinmotor::rig_skin(rig);
  for (const double gamma : {10.0, 0.0}) {
    INFO("pose weight " << gamma);
    r = spinmotor_test::run_cli(tmp.path, "rig pose " + file + " --time 1 --cleanup pinned --pose-weight " +
                                              std::to_string(gamma) + " --out " + tmp.file("clean.obj"));
    INFO(r.err);
    REQUIRE(r.code == 0);
    spinmotor::scene::RigCleanupOptions o;
    o.cleanup.pose_weight = gamma;
    spinmotor::scene::RigCleanup rc =
        spinmotor::scene::RigCleanup::bind(skin.rest, skin.rig.weights, skin.rig.skeleton, o);
    Eigen::MatrixXd E, V;
    spinmotor::RigSkinner(rig, spinmotor::SkinBlend::LBS).pose(0, 1.0, E);
    rc(E, V);
    const Eigen::MatrixXd cli = spinmotor::read_mesh(tmp.path / "clean.obj").V;
    CHECK((cli - V).cwiseAbs().maxCoeff() <= 1e-12 * diagonal(V));
  }
}

}  // namespace test_gltf

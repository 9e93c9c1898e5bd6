#pragma once
// An independent evaluation of the glTF 2.0 skinning formula, written here from the specification and
// nothing of the project's (nlohmann-json for the JSON, Eigen for the matrices): the reference the
// readers, samplers and skinners are compared with.
//
// Reads .gltf (one buffer as a base64 data: URI) and .glb (the JSON and BIN chunks, §4.4). Evaluates, for
// every node of the default scene that has `mesh` and `skin` (in node order; the order read_gltf reads
// them), every vertex of every primitive (primitives concatenated: the file vertex numbering of
// GltfRig::file_to_surface):
//   x = Σ_sets Σ_q (w_q / Σ w) · W(joints[j_q]) · IBM(j_q) · (p + Σ_k m_k d_k)          (§3.7.3.3, §3.7.2.2)
// with W a node's global matrix (parent · local, local = `matrix` or T·R·S, §3.5.3) at time t of an
// animation (LINEAR with the shortest-arc slerp for rotations, STEP; Appendix C), morph weights m from the
// node's `weights`, else the mesh's, else 0, replaced by a `weights` channel; the skinned node's own
// transform is not used. Accessors: float, unsigned byte / short (normalised or not), byteStride, no
// sparse storage (REQUIREd).
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace spinmotor::test {

class GltfReference {
 public:
  using json = nlohmann::json;

  explicit GltfReference(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    REQUIRE(in);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (p.extension() == ".glb") {
      REQUIRE(bytes.size() >= 20);
      REQUIRE(std::memcmp(bytes.data(), "glTF", 4) == 0);
      const uint32_t json_len = u32(bytes, 12);
      j = json::parse(std::string(bytes.begin() + 20, bytes.begin() + 20 + json_len));
      const size_t bin = 20 + json_len;
      if (bin + 8 <= bytes.size())
        buf.assign(bytes.begin() + bin + 8, bytes.begin() + bin + 8 + u32(bytes, bin));
    } else {
      j = json::parse(std::string(bytes.begin(), bytes.end()));
      const std::string uri = j["buffers"][0]["uri"];
      buf = b64decode(uri.substr(uri.find(',') + 1));
    }
    REQUIRE(buf.size() >= j["buffers"][0]["byteLength"].get<size_t>());
    parent.assign(j["nodes"].size(), -1);
    for (size_t i = 0; i < j["nodes"].size(); ++i)
      for (int c : j["nodes"][i].value("children", std::vector<int>{})) parent[c] = static_cast<int>(i);
    std::vector<char> in_scene(j["nodes"].size(), j.contains("scenes") ? 0 : 1);
    if (j.contains("scenes"))
      for (int r : j["scenes"][j.value("scene", 0)]["nodes"]) in_scene[r] = 1;
    for (size_t i = 0; i < j["nodes"].size(); ++i)
      for (int q = static_cast<int>(i); q >= 0 && !in_scene[i]; q = parent[q])
        if (in_scene[q]) in_scene[i] = 1;
    for (size_t i = 0; i < j["nodes"].size(); ++i)
      if (in_scene[i] && j["nodes"][i].contains("mesh") && j["nodes"][i].contains("skin"))
        skinned.push_back(static_cast<int>(i));
  }

  /// Accessor `index` as count rows of its components (doubles; normalised integers mapped to [0, 1]).
  std::vector<std::vector<double>> accessor(int index) const {
    const json& a = j["accessors"][index];
    REQUIRE(!a.contains("sparse"));
    const json& bv = j["bufferViews"][a["bufferView"].get<int>()];
    const std::map<std::string, int> nc = {
        {"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}, {"MAT4", 16}};
    const int c = nc.at(a["type"]), ct = a["componentType"];
    const bool norm = a.value("normalized", false);
    const int size = ct == 5126 || ct == 5125 ? 4 : ct == 5123 ? 2 : 1;
    const size_t stride = bv.value("byteStride", size_t(size * c));
    const size_t off = bv.value("byteOffset", size_t(0)) + a.value("byteOffset", size_t(0));
    std::vector<std::vector<double>> out(a["count"].get<size_t>(), std::vector<double>(c));
    for (size_t k = 0; k < out.size(); ++k)
      for (int q = 0; q < c; ++q) {
        const uint8_t* ptr = buf.data() + off + k * stride + q * size;
        if (ct == 5126) {
          float f;
          std::memcpy(&f, ptr, 4);
          out[k][q] = f;
        } else if (ct == 5125) {
          uint32_t u;
          std::memcpy(&u, ptr, 4);
          out[k][q] = u;
        } else if (ct == 5123) {
          uint16_t u;
          std::memcpy(&u, ptr, 2);
          out[k][q] = norm ? u / 65535.0 : u;
        } else {
          REQUIRE(ct == 5121);
          out[k][q] = norm ? *ptr / 255.0 : *ptr;
        }
      }
    return out;
  }

  /// Every node's global matrix and every skinned node's morph weights at time t of animation `anim`
  /// (−1: the nodes' own values).
  struct State {
    std::vector<Eigen::Matrix4d> world;
    std::map<int, std::vector<double>> weights;  // node -> morph weights
  };
  State state(int anim, double t) const {
    const size_t N = j["nodes"].size();
    std::vector<Eigen::Vector3d> T(N, Eigen::Vector3d::Zero()), S(N, Eigen::Vector3d::Ones());
    std::vector<Eigen::Quaterniond> R(N, Eigen::Quaterniond::Identity());
    State st;
    for (size_t i = 0; i < N; ++i) {
      const json& n = j["nodes"][i];
      if (n.contains("translation")) T[i] = vec3(n["translation"]);
      if (n.contains("scale")) S[i] = vec3(n["scale"]);
      if (n.contains("rotation"))
        R[i] = Eigen::Quaterniond(n["rotation"][3], n["rotation"][0], n["rotation"][1], n["rotation"][2])
                   .normalized();
    }
    for (int node : skinned) {
      const json& mesh = j["meshes"][j["nodes"][node]["mesh"].get<int>()];
      const size_t targets = mesh["primitives"][0].value("targets", json::array()).size();
      std::vector<double> w = j["nodes"][node].value("weights", mesh.value("weights", std::vector<double>{}));
      w.resize(targets, 0.0);
      st.weights[node] = w;
    }
    if (anim >= 0) animate(anim, t, T, R, S, st);
    std::vector<Eigen::Matrix4d> local(N);
    for (size_t i = 0; i < N; ++i) {
      const json& n = j["nodes"][i];
      if (n.contains("matrix")) {
        for (int e = 0; e < 16; ++e) local[i](e % 4, e / 4) = n["matrix"][e];
      } else {
        Eigen::Affine3d a = Eigen::Translation3d(T[i]) * R[i] * Eigen::Scaling(S[i]);
        local[i] = a.matrix();
      }
    }
    st.world.resize(N);
    for (size_t i = 0; i < N; ++i) {
      Eigen::Matrix4d w = local[i];
      for (int q = parent[i]; q >= 0; q = parent[q]) w = local[q] * w;
      st.world[i] = w;
    }
    return st;
  }

  /// The specification's positions of every file vertex (see the header comment), in order.
  std::vector<Eigen::Vector3d> skin(int anim, double t) const {
    const State st = state(anim, t);
    std::vector<Eigen::Vector3d> out;
    for (int node : skinned) {
      const json& skin = j["skins"][j["nodes"][node]["skin"].get<int>()];
      std::vector<Eigen::Matrix4d> M;
      const auto ibm = skin.contains("inverseBindMatrices") ? accessor(skin["inverseBindMatrices"])
                                                            : std::vector<std::vector<double>>();
      for (size_t k = 0; k < skin["joints"].size(); ++k) {
        Eigen::Matrix4d b = Eigen::Matrix4d::Identity();
        if (!ibm.empty())
          for (int e = 0; e < 16; ++e) b(e % 4, e / 4) = ibm[k][e];
        M.push_back(st.world[skin["joints"][k].get<int>()] * b);
      }
      const std::vector<double>& mw = st.weights.at(node);
      for (const json& prim : j["meshes"][j["nodes"][node]["mesh"].get<int>()]["primitives"]) {
        const json& attr = prim["attributes"];
        const auto P = accessor(attr["POSITION"]);
        std::vector<std::vector<std::vector<double>>> D;
        for (const json& tg : prim.value("targets", json::array()))
          D.push_back(tg.contains("POSITION") ? accessor(tg["POSITION"])
                                              : std::vector<std::vector<double>>(P.size(), {0, 0, 0}));
        std::vector<std::vector<std::vector<double>>> Js, Ws;
        for (int set = 0; attr.contains("JOINTS_" + std::to_string(set)); ++set) {
          Js.push_back(accessor(attr["JOINTS_" + std::to_string(set)]));
          Ws.push_back(accessor(attr["WEIGHTS_" + std::to_string(set)]));
        }
        for (size_t i = 0; i < P.size(); ++i) {
          Eigen::Vector4d p(P[i][0], P[i][1], P[i][2], 1.0);
          for (size_t k = 0; k < D.size(); ++k)
            p.head<3>() += mw[k] * Eigen::Vector3d(D[k][i][0], D[k][i][1], D[k][i][2]);
          double sum = 0;
          Eigen::Vector4d acc = Eigen::Vector4d::Zero();
          for (size_t s = 0; s < Js.size(); ++s)
            for (int q = 0; q < 4; ++q) {
              sum += Ws[s][i][q];
              if (Ws[s][i][q] != 0) acc += Ws[s][i][q] * (M[static_cast<size_t>(Js[s][i][q])] * p);
            }
          out.push_back(acc.head<3>() / sum);
        }
      }
    }
    return out;
  }

  json j;
  std::vector<uint8_t> buf;
  std::vector<int> parent;
  std::vector<int> skinned;  ///< the skinned nodes of the scene, in order

 private:
  static uint32_t u32(const std::vector<uint8_t>& b, size_t at) {
    uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
  }
  static Eigen::Vector3d vec3(const json& a) {
    return {a[0].get<double>(), a[1].get<double>(), a[2].get<double>()};
  }
  static std::vector<uint8_t> b64decode(const std::string& s) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::vector<uint8_t> out;
    uint32_t acc = 0;
    int bits = 0;
    for (char c : s) {
      const char* p = std::strchr(k, c);
      if (c == '=' || !p || !c) continue;
      acc = (acc << 6) | static_cast<uint32_t>(p - k);
      bits += 6;
      if (bits >= 8) {
        bits -= 8;
        out.push_back(static_cast<uint8_t>((acc >> bits) & 0xff));
      }
    }
    return out;
  }
  void animate(int anim, double t, std::vector<Eigen::Vector3d>& T, std::vector<Eigen::Quaterniond>& R,
               std::vector<Eigen::Vector3d>& S, State& st) const {
    const json& a = j["animations"][anim];
    for (const json& ch : a["channels"]) {
      if (!ch["target"].contains("node")) continue;
      const json& smp = a["samplers"][ch["sampler"].get<int>()];
      const std::string interp = smp.value("interpolation", std::string("LINEAR"));
      REQUIRE((interp == "LINEAR" || interp == "STEP"));
      const auto in = accessor(smp["input"]), out = accessor(smp["output"]);
      size_t k = 0;
      while (k + 1 < in.size() && in[k + 1][0] <= t) ++k;
      double u = 0;
      size_t k1 = k;
      if (t > in[0][0] && k + 1 < in.size() && interp == "LINEAR") {
        k1 = k + 1;
        u = (t - in[k][0]) / (in[k1][0] - in[k][0]);
      }
      const int node = ch["target"]["node"];
      const std::string path = ch["target"]["path"];
      if (path == "weights") {
        if (!st.weights.count(node)) continue;
        std::vector<double>& w = st.weights[node];
        for (size_t q = 0; q < w.size(); ++q)
          w[q] = (1 - u) * out[k * w.size() + q][0] + u * out[k1 * w.size() + q][0];
      } else if (path == "rotation") {
        const Eigen::Quaterniond q0(out[k][3], out[k][0], out[k][1], out[k][2]),
            q1(out[k1][3], out[k1][0], out[k1][1], out[k1][2]);
        R[node] = q0.normalized().slerp(u, q1.normalized()).normalized();  // Eigen: shortest arc
      } else {
        const Eigen::Vector3d v = (1 - u) * Eigen::Vector3d(out[k][0], out[k][1], out[k][2]) +
                                  u * Eigen::Vector3d(out[k1][0], out[k1][1], out[k1][2]);
        (path == "translation" ? T : S)[node] = v;
      }
    }
  }
};

}  // namespace spinmotor::test

// fuzz_scene: a scene file (docs/scene.md) through load_scene (scene/scene.hpp): JSON parse, the schema
// check (scene/json_schema.hpp), the mesh source (file, generator or glTF rig), handles and their
// selections, poses and motors, `frames`, `rig` (animation, time, frames), `ik`, `snap`, `output`.
//
// Not covered: binding the deformer (deformer_registry.hpp: each type's own keys past the schema and
// its precomputation, a solve on the whole mesh) and running or writing frames (run.hpp); loading does
// neither. fuzz_weights binds the skin deformer for its weight files.
//
// Bounded, so that every input runs in milliseconds and touches only files of its own:
//   - the schema leaves generator sizes unbounded (rings, sides, ...): documents whose generated mesh
//     would exceed kMaxVertices are skipped (icosphere level ≤ 10 is the schema's own limit);
//   - mesh and rig paths must be plain file names, resolved in the scratch directory, which holds
//     tetra.obj (a tetrahedron) and limb.gltf (a small procedural rig with two animations) to refer to.
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "fuzz_support.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/gltf_rig_writer.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/procedural_rig.hpp"
#include "spinmotor/scene/scene.hpp"

namespace {

using nlohmann::json;
constexpr double kMaxVertices = 20000;

// The files a scene may name, written once per process.
void write_fixtures() {
  const std::filesystem::path& dir = spinmotor::fuzz::scratch_dir();
  spinmotor::write_obj(dir / "tetra.obj", spinmotor::fuzz::tetrahedron());
  spinmotor::LimbRigOptions o;
  o.rings = 6;
  o.sides = 4;
  spinmotor::write_gltf_rig(dir / "limb.gltf", spinmotor::limb_rig(o));
}

double number(const json& obj, const char* key, double fallback) {
  const auto it = obj.find(key);
  return it != obj.end() && it->is_number() ? it->get<double>() : fallback;
}

// Vertices of a generator block, from the sizes in mesh/generators.hpp (defaults as the loader's).
double generated_vertices(const json& m) {
  const json& g = m["generate"];
  if (g == "icosphere") return 10 * std::pow(4.0, std::min(number(m, "level", 4), 10.0)) + 2;
  if (g == "uv-sphere") return number(m, "rings", 64) * number(m, "sectors", 128);
  if (g == "tube") return number(m, "rings", 200) * number(m, "sides", 64);
  if (g == "torus") return number(m, "u", 128) * number(m, "v", 64);
  if (g == "capsule") return number(m, "rings", 64) * number(m, "sides", 64);
  if (g == "grid") {
    const auto n = m.find("n");
    if (n == m.end() || !n->is_array() || n->size() != 2 || !(*n)[0].is_number() || !(*n)[1].is_number())
      return 100 * 100;
    return (*n)[0].get<double>() * (*n)[1].get<double>();
  }
  if (g ==
      "cross-bar") {  // segments bands of about 4k outline vertices, caps of about k² (k = 2 half_span / h)
    const double segments = number(m, "segments", 64),
                 k = std::max(1.0, 2 * number(m, "half_span", 0.5) * segments / number(m, "length", 4));
    return (segments + 1) * 4 * k + 2 * k * k;
  }
  return 0;
}

bool plain_name(const json& path) {
  if (!path.is_string()) return true;  // the schema refuses it
  const std::string s = path.get<std::string>();
  return s.find('/') == std::string::npos && s != "." && s != "..";
}

// True when load_scene may run on the document (see the header comment).
bool bounded(const json& doc) {
  if (!doc.is_object()) return true;
  if (const auto m = doc.find("mesh"); m != doc.end()) {
    if (!plain_name(*m)) return false;
    if (m->is_object() && m->contains("generate") && !(generated_vertices(*m) <= kMaxVertices)) return false;
  }
  if (const auto r = doc.find("rig"); r != doc.end() && r->is_object() && r->contains("gltf"))
    if (!plain_name((*r)["gltf"])) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool fixtures = (write_fixtures(), true);
  (void)fixtures;
  const json doc = json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (!doc.is_discarded() && !bounded(doc)) return 0;
  const std::filesystem::path path = spinmotor::fuzz::write_input(data, size, "scene.json");
  try {
    const spinmotor::scene::Scene scene = spinmotor::scene::load_scene(path);
    spinmotor::fuzz::check(!scene.frames.empty(), "a scene has a frame");
    spinmotor::fuzz::check(scene.mesh.V.rows() > 0 && scene.mesh.F.rows() > 0, "a scene has a mesh");
  } catch (const spinmotor::Error& e) {
    spinmotor::fuzz::refused(e);
  }
  return 0;
}

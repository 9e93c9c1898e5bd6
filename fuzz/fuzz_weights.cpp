// fuzz_weights: skin weight files, both forms, on a fixed rig: the tetrahedron (4 vertices) and a
// skeleton of two bones, "root" and its child "tip". The first byte selects the form, the rest is the
// file:
//   even: the text form, read_skin_weights (deform/skinning.hpp), whose result is checked;
//   odd:  the JSON form {"bones": [...], "weights": [[...] ...]}, which only the scene's skin deformer
//         reads (scene/src/deformer_skin.cpp, when it binds).
// Either way the file then goes the way a scene file's "weights" goes: bind_deformer reads it again
// (by its extension) and binds the skin deformer, which is posed once at rest.
#include <nlohmann/json.hpp>
#include <vector>

#include "fuzz_support.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/scene/deformer_registry.hpp"
#include "spinmotor/scene/scene.hpp"

namespace {

namespace scene = spinmotor::scene;

// The scene whose skin deformer reads `weights` (a file name in the scratch directory).
scene::Scene skin_scene(const char* weights) {
  const std::filesystem::path& dir = spinmotor::fuzz::scratch_dir();
  if (!std::filesystem::exists(dir / "tetra.obj"))
    spinmotor::write_obj(dir / "tetra.obj", spinmotor::fuzz::tetrahedron());
  const nlohmann::json doc = {
      {"mesh", "tetra.obj"},
      {"skeleton",
       {{"bones",
         {{{"name", "root"}, {"head", {0, 0, 0}}, {"tail", {0, 0, 0.5}}},
          {{"name", "tip"}, {"parent", "root"}, {"head", {0, 0, 0.5}}, {"tail", {0, 0, 1}}}}}}},
      {"deformer", {{"type", "skin"}, {"weights", weights}}}};
  return scene::parse_scene(doc, dir, "weights-scene.json");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using spinmotor::fuzz::check;
  static const scene::Scene text_scene = skin_scene("weights.txt"), json_scene = skin_scene("weights.json");
  if (size < 1) return 0;
  const bool text = data[0] % 2 == 0;
  const scene::Scene& s = text ? text_scene : json_scene;
  const std::filesystem::path path =
      spinmotor::fuzz::write_input(data + 1, size - 1, text ? "weights.txt" : "weights.json");
  if (text) {
    std::vector<spinmotor::Bone> bones(2);
    bones[0].name = "root";
    bones[1].name = "tip";
    bones[1].parent = 0;
    try {
      const Eigen::MatrixXd W = spinmotor::read_skin_weights(path, bones, s.mesh.V.rows());
      check(W.rows() == s.mesh.V.rows() && W.cols() == 2, "weights are n x B");
      check(W.allFinite() && W.minCoeff() >= 0.0, "weights are finite and >= 0");
      check((W.rowwise().sum().array() > 0.0).all(), "every vertex has a positive weight");
    } catch (const spinmotor::Error& e) {
      return spinmotor::fuzz::refused(e);
    }
  }
  try {
    const std::unique_ptr<scene::SceneDeformer> d = scene::bind_deformer(s);
    Eigen::MatrixXd V;
    d->pose(s.frames.front(), V);
    check(V.rows() == s.mesh.V.rows() && V.cols() == 3, "the posed mesh is n x 3");
  } catch (const spinmotor::Error& e) {
    spinmotor::fuzz::refused(e);
  }
  return 0;
}

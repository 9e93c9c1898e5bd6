#pragma once
// The deformer panel's starting points: for each deformer type, the scene blocks (docs/scene.md) a user
// gets when switching to it in the viewer, built from what the scene already has (its handles, its
// skeleton) and tuned for interactive use. Window-free; Session::set_deformer binds them.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "spinmotor/scene/scene.hpp"

namespace spinmotor::viewer {

struct DeformerPreset {
  nlohmann::json deformer;  ///< the `deformer` block
  nlohmann::json ik;        ///< the `ik` block, or null
};

/// The choices of the panel, in order: "surface-harmonic", "spline" (4 key motors), "spline-ik" (a
/// FABRIK chain whose target is dragged), "ffd", "cage", "arap", "skin".
const std::vector<std::string>& deformer_choices();

/// The blocks for `choice` on scene `s`:
///   surface-harmonic  mean-value weights, log blend (the scene's own keys kept if it already is one)
///   spline            from/to = the first two handles, B-spline of 4 keys "key0".."key3"
///   spline-ik         from/to = the first two handles, a 5-joint straight chain between their
///                     centroids, target = the `to` centroid (then dragged as control "ik.target")
///   ffd               3×3×3 Bézier lattice of motors around the bounding box
///   cage              the scene's cage file if it has one, else a bounding-box cage (`{"box": ...}`),
///                     mean-value coordinates (no grid solve at bind)
///   arap              spokes-and-rims, 20 iterations, each frame starting from the previous result
///   skin              the scene's skeleton, harmonic weights, DLB
/// Throws Error saying what is missing (spline needs two handles, skin a skeleton) or for an unknown
/// choice.
DeformerPreset deformer_preset(const std::string& choice, const scene::Scene& s);

/// One key of a deformer block the panel edits with a widget.
struct DeformerOption {
  enum class Kind { Choice, Integer, Number, Boolean, Integers3, Handle };
  std::string key;
  Kind kind = Kind::Choice;
  std::vector<std::string> choices;          ///< Choice: the schema's enum; Handle: the handle names
  double minimum = -1e300, maximum = 1e300;  ///< Integer, Number, Integers3 (per item)
};

/// The keys of deformer type `type` (a `deformer.type` value) the panel shows as widgets, read from
/// the scene schema (definitions/deformer_<type>, so a key added there appears here): enums,
/// integers, numbers, booleans, arrays of 3 integers (the FFD lattice), and `from`/`to` as handle
/// choices. Other keys (paths, key lists, fit, box) are edited as JSON text. Error for an unknown type.
std::vector<DeformerOption> deformer_options(const std::string& type,
                                             const std::vector<std::string>& handle_names);

}  // namespace spinmotor::viewer

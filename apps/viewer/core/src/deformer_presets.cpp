#include "spinmotor/viewer/deformer_presets.hpp"

#include <algorithm>

#include "spinmotor/core/error.hpp"

namespace spinmotor::viewer {

namespace {
using nlohmann::json;

json point(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

void need_two_handles(const scene::Scene& s, const std::string& choice) {
  if (s.handles.size() < 2)
    throw Error("viewer: the " + choice +
                " deformer runs from one handle to another: make two handles first (" +
                std::to_string(s.handles.size()) + " now)");
}
}  // namespace

const std::vector<std::string>& deformer_choices() {
  static const std::vector<std::string> c = {
      "surface-harmonic", "spline", "spline-ik", "ffd", "cage", "arap", "skin"};
  return c;
}

DeformerPreset deformer_preset(const std::string& choice, const scene::Scene& s) {
  const bool same = !s.deformer.is_null() && s.deformer_type == choice;
  if (choice == "surface-harmonic")
    return {
        same ? s.deformer : json{{"type", "surface-harmonic"}, {"weights", "mean-value"}, {"blend", "log"}},
        nullptr};
  if (choice == "spline") {
    if (s.deformer_type == "spline" && s.deformer.contains("keys")) return {s.deformer, nullptr};
    need_two_handles(s, choice);
    return {{{"type", "spline"},
             {"from", s.handles[0].name},
             {"to", s.handles[1].name},
             {"basis", "bspline"},
             {"degree", 3},
             {"keys", {"key0", "key1", "key2", "key3"}}},
            nullptr};
  }
  if (choice == "spline-ik") {
    if (s.deformer_type == "spline" && s.doc.contains("ik")) return {s.deformer, s.doc["ik"]};
    need_two_handles(s, choice);
    const Eigen::Vector3d a = handle_centroid(s.mesh.V, s.handles[0]),
                          b = handle_centroid(s.mesh.V, s.handles[1]);
    json chain = json::array();
    for (int i = 0; i < 5; ++i) chain.push_back(point(a + (b - a) * (i / 4.0)));
    return {
        {{"type", "spline"}, {"from", s.handles[0].name}, {"to", s.handles[1].name}, {"basis", "bspline"}},
        {{"chain", chain}, {"target", point(b)}}};
  }
  if (choice == "ffd")
    return {same ? s.deformer
                 : json{{"type", "ffd"}, {"lattice", {3, 3, 3}}, {"basis", "bezier"}, {"mode", "motor"}},
            nullptr};
  if (choice == "cage") {
    if (same) return {s.deformer, nullptr};
    return {{{"type", "cage"}, {"cage", {{"box", {{"margin", 0.05}}}}}, {"coordinates", "mean-value"}},
            nullptr};
  }
  if (choice == "arap")
    return {same ? s.deformer
                 : json{{"type", "arap"},
                        {"energy", "spokes-and-rims"},
                        {"iterations", 20},
                        {"initial", "previous"}},
            nullptr};
  if (choice == "skin") {
    if (!s.doc.contains("skeleton"))
      throw Error(
          "viewer: the skin deformer needs a `skeleton` in the scene (docs/scene.md); this scene has none");
    return {same ? s.deformer : json{{"type", "skin"}, {"weights", "harmonic"}, {"blend", "dlb"}}, nullptr};
  }
  throw Error("viewer: no deformer choice '" + choice + "'");
}

std::vector<DeformerOption> deformer_options(const std::string& type,
                                             const std::vector<std::string>& handle_names) {
  const json& defs = scene::scene_schema()["definitions"];
  std::string def = "deformer_" + type;
  std::replace(def.begin(), def.end(), '-', '_');
  if (!defs.contains(def)) throw Error("viewer: no deformer type '" + type + "' in the scene schema");
  auto resolve = [&](const json& p) -> const json& {
    if (p.contains("$ref")) {
      const std::string ref = p["$ref"].get<std::string>();  // "#/definitions/<name>"
      return defs[ref.substr(ref.rfind('/') + 1)];
    }
    return p;
  };
  std::vector<DeformerOption> out;
  for (const auto& [key, raw] : defs[def]["properties"].items()) {
    if (key == "type") continue;
    const json& p = resolve(raw);
    DeformerOption o;
    o.key = key;
    if (key == "from" || key == "to") {
      o.kind = DeformerOption::Kind::Handle;
      o.choices = handle_names;
    } else if (p.contains("enum")) {
      o.kind = DeformerOption::Kind::Choice;
      o.choices = p["enum"].get<std::vector<std::string>>();
    } else if (p.value("type", "") == "integer" || p.value("type", "") == "number") {
      o.kind = p["type"] == "integer" ? DeformerOption::Kind::Integer : DeformerOption::Kind::Number;
      o.minimum = p.value("minimum", o.minimum);
      o.maximum = p.value("maximum", o.maximum);
    } else if (p.value("type", "") == "boolean") {
      o.kind = DeformerOption::Kind::Boolean;
    } else if (p.value("type", "") == "array" && p.value("minItems", 0) == 3 && p.value("maxItems", 0) == 3 &&
               p.contains("items") && p["items"].value("type", "") == "integer") {
      o.kind = DeformerOption::Kind::Integers3;
      o.minimum = p["items"].value("minimum", o.minimum);
      o.maximum = p["items"].value("maximum", o.maximum);
    } else {
      continue;
    }
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace spinmotor::viewer

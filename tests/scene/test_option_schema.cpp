// The scene schema's enums are the library's option tables (core/option_names.hpp): a name added to
// one and not the other fails here. (The viewer's widgets read their choices from the schema.)
#include <algorithm>
#include <catch2/catch.hpp>

#include "spinmotor/deform/arap.hpp"
#include "spinmotor/deform/cage_deformer.hpp"
#include "spinmotor/deform/delta_mush.hpp"
#include "spinmotor/deform/ffd.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/deform/spline_basis.hpp"
#include "spinmotor/scene/scene.hpp"

namespace test_option_schema {

using namespace spinmotor;

namespace {

std::vector<std::string> sorted(std::vector<std::string> v) {
  std::sort(v.begin(), v.end());
  return v;
}

std::vector<std::string> schema_enum(const std::string& pointer) {
  return sorted(scene::scene_schema()
                    .at(nlohmann::json::json_pointer(pointer))
                    .at("enum")
                    .get<std::vector<std::string>>());
}

template <class E>
std::vector<std::string> table(std::initializer_list<std::string_view> rejected = {}) {
  std::vector<std::string> v;
  for (const std::string& n : option_values<E>())
    if (std::find(rejected.begin(), rejected.end(), n) == rejected.end()) v.push_back(n);
  return sorted(v);
}

}  // namespace

TEST_CASE("the scene schema's enums equal the option tables", "[scene][schema][options]") {
  const std::string d = "/definitions/";
  CHECK(schema_enum(d + "weights") == table<HarmonicWeights>());
  CHECK(schema_enum(d + "deformer_surface_harmonic/properties/blend") == table<ga::Blend>());
  CHECK(schema_enum(d + "deformer_spline/properties/basis") == table<SplineBasis>());
  CHECK(schema_enum(d + "deformer_ffd/properties/basis") == table<FfdDeformer::Basis>());
  CHECK(schema_enum(d + "deformer_ffd/properties/mode") == table<ControlMode>());
  // FFD offers no pivot-log blend (FfdDeformer::bind rejects it).
  CHECK(schema_enum(d + "deformer_ffd/properties/blend") == table<ga::Blend>({"pivot-log"}));
  CHECK(schema_enum(d + "deformer_cage/properties/coordinates") == table<CageDeformer::Coordinates>());
  CHECK(schema_enum(d + "deformer_cage/properties/mode") == table<ControlMode>());
  CHECK(schema_enum(d + "deformer_cage/properties/blend") == table<ga::Blend>());
  CHECK(schema_enum(d + "deformer_arap/properties/energy") == table<ArapEnergy>());
  CHECK(schema_enum(d + "deformer_arap/properties/initial") == table<ArapInitial>());
  CHECK(schema_enum(d + "deformer_skin/properties/blend") == table<SkinBlend>());
  CHECK(schema_enum(d + "deformer_skin/properties/mush") == table<MushKind>());
}

}  // namespace test_option_schema

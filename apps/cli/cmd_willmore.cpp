// `spinmotor willmore MESH [--json]`: the discrete Willmore energy of Ye et al. 2018 (eq. 11, face
// edge-constraint nets: Σ H_i²/A_i) next to the vertex-based cotangent one (mesh/metrics/willmore.hpp).
// Both are ∫H²dA with H the mean of the principal curvatures: 4π for a round sphere.
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/willmore.hpp"
#include "spinmotor/spin/edge_constraint_net.hpp"

namespace {

using namespace spinmotor;

const cli::RegisterCommand register_willmore{
    "willmore", "Discrete Willmore energy (face-based, Ye 2018 eq. 11, and vertex-based cotangent)",
    [](CLI::App& sub) {
      struct Args {
        std::string mesh;
        bool json = false;
      };
      auto a = std::make_shared<Args>();
      sub.add_option("MESH", a->mesh, "Manifold, oriented mesh (OBJ, OFF, PLY, STL)")->required();
      sub.add_flag("--json", a->json, "Print JSON");
      sub.footer(
          "Examples:\n"
          "  spinmotor willmore sphere.obj   # about 12.566 (4 pi)\n"
          "  spinmotor willmore spot.obj --json");
      sub.callback([a] {
        const Mesh mesh = read_mesh(a->mesh);
        const EdgeConstraintNet net = edge_constraint_net(mesh.V, mesh.F);
        const double wv = willmore_energy(mesh.V, mesh.F);
        if (a->json) {
          nlohmann::json j;
          j["vertices"] = mesh.V.rows();
          j["faces"] = mesh.F.rows();
          j["willmore_face"] = net.willmore;
          j["willmore_vertex"] = wv;
          j["over_4pi"] = net.willmore / (4 * M_PI);
          std::cout << j.dump(2) << '\n';
        } else {
          std::printf("Willmore energy (face, Ye eq. 11):   %.10g  (%.6g x 4 pi)\n", net.willmore,
                      net.willmore / (4 * M_PI));
          std::printf("Willmore energy (vertex, cotangent): %.10g\n", wv);
        }
      });
    }};

}  // namespace

// `spinmotor spectrum MESH --operator crane|ye-intrinsic|ye-extrinsic -k K [--json]`: the K eigenvalues
// nearest 0 of the generalized problem A*A λ = γ B*A λ (Crane et al. 2011, eq. 6) with ρ = 0 and the
// constant solutions removed (§6.2), or of problem (26) of Ye et al. 2018 for their face-based intrinsic
// (eq. 19) or extrinsic (eq. 13) operator (constants removed for the extrinsic one).
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/spin/dirac_spectrum.hpp"

namespace {

using namespace spinmotor;

const cli::RegisterCommand register_spectrum{
    "spectrum", "Eigenvalues nearest 0 of a discrete Dirac operator (constants removed)", [](CLI::App& sub) {
      struct Args {
        std::string mesh, op = "crane";
        int k = 20;
        bool json = false, quiet = false;
      };
      auto a = std::make_shared<Args>();
      sub.add_option("MESH", a->mesh, "Closed, connected, oriented manifold mesh")->required();
      sub.add_flag("-q,--quiet", a->quiet, "Print nothing unless --json");
      sub.footer(
          "Examples:\n"
          "  spinmotor spectrum sphere.obj -k 28   # unit sphere: 0 (x4), +1 (x8), -2 (x4), +2 (x12)\n"
          "  spinmotor spectrum sphere.obj --operator ye-intrinsic -k 24   # +-1 (x4), +-2 (x8)\n"
          "  spinmotor spectrum spot.obj --json");
      sub.add_option("--operator", a->op,
                     "crane: the vertex-based extrinsic Dirac operator of Crane et al. 2011; ye-intrinsic / "
                     "ye-extrinsic: the face-based operators of Ye et al. 2018 (problem 26)")
          ->check(CLI::IsMember({"crane", "ye-intrinsic", "ye-extrinsic"}))
          ->capture_default_str();
      sub.add_option("-k", a->k, "Number of eigenvalues (real multiplicities)")->capture_default_str();
      sub.add_flag("--json", a->json, "Print JSON");
      sub.callback([a] {
        const Mesh mesh = read_mesh(a->mesh);
        DiracSpectrumOptions o;
        o.count = a->k;
        const DiracSpectrum s =
            a->op == "crane"
                ? dirac_spectrum(mesh.V, mesh.F, {}, o)
                : face_dirac_spectrum(
                      mesh.V, mesh.F,
                      a->op == "ye-intrinsic" ? FaceDiracKind::Intrinsic : FaceDiracKind::Extrinsic, {}, o);
        if (a->json) {
          nlohmann::json j;
          j["operator"] = a->op;
          j["vertices"] = mesh.V.rows();
          j["faces"] = mesh.F.rows();
          j["constant_kernel"] = s.constant_kernel;
          j["eigenvalues"] =
              std::vector<double>(s.eigenvalues.data(), s.eigenvalues.data() + s.eigenvalues.size());
          j["iterations"] = s.iterations;
          j["operations"] = s.operations;
          std::cout << j.dump(2) << '\n';
        } else if (!a->quiet) {
          std::printf("%d constant solutions removed (eigenvalue 0); %d eigenvalues nearest 0:\n",
                      s.constant_kernel, static_cast<int>(s.eigenvalues.size()));
          for (Eigen::Index i = 0; i < s.eigenvalues.size(); ++i) std::printf("%.10g\n", s.eigenvalues[i]);
        }
      });
    }};

}  // namespace

// `spinmotor render MESH [--rest REST] --color q|checker|normals|plain --out out.png [--size WxH]
// [--camera AZ,EL[,DIST]] [--up x|y|z] [--flat] [--wireframe] [--q-range LO,HI]`: a picture of a mesh
// without a window (render/: EGL surfaceless, EGL pbuffer or OSMesa). Compiled only when the
// renderer library is built (SPINMOTOR_BUILD_VIEWER). The PNG is written atomically: on any error
// (exit 2 bad input, 3 numerical) no file is left.
#include <iostream>
#include <memory>
#include <string>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/render/render_mesh.hpp"

namespace {

using namespace spinmotor;

const cli::RegisterCommand register_render{
    "render", "Render a mesh to PNG without a window (Q / checker / normal colours)", [](CLI::App& sub) {
      struct Args {
        std::string mesh, rest, out, color = "normals", size = "800x600", camera, up = "y", q_range = "1,2";
        bool flat = false, wireframe = false, no_bar = false, quiet = false;
        double cells = 16;
      };
      auto a = std::make_shared<Args>();
      sub.add_option("MESH", a->mesh, "Mesh to draw (OBJ, OFF, PLY, STL)")->required();
      sub.add_option("--rest", a->rest,
                     "Rest mesh (same vertices and faces): Q of MESH against it (--color q)");
      sub.add_option("--color", a->color,
                     "q (quasi-conformal error vs --rest), checker (texture coordinates), "
                     "normals, plain")
          ->check(CLI::IsMember({"q", "checker", "normals", "plain"}))
          ->capture_default_str();
      sub.add_option("--out", a->out, "Output PNG")->required();
      sub.add_option("--size", a->size, "Image size WxH")->capture_default_str();
      sub.add_option("--camera", a->camera,
                     "AZ,EL[,DIST]: azimuth and elevation in degrees about the up axis, distance from the "
                     "bounding-box centre (default 30,20 and a distance that frames the bounding box)");
      sub.add_option("--up", a->up, "Up axis")->check(CLI::IsMember({"x", "y", "z"}))->capture_default_str();
      sub.add_flag("--flat", a->flat, "Flat shading (one normal per face)");
      sub.add_flag("--wireframe", a->wireframe, "Draw the edges");
      sub.add_option("--q-range", a->q_range, "LO,HI: Q range of the colour map (log scale)")
          ->capture_default_str();
      sub.add_option("--checker-cells", a->cells, "Checker cells per unit of texture coordinate")
          ->check(CLI::PositiveNumber)
          ->capture_default_str();
      sub.add_flag("--no-color-bar", a->no_bar, "No colour bar with --color q");
      sub.add_flag("-q,--quiet", a->quiet, "Print nothing on success");
      sub.footer(
          "Examples:\n  spinmotor render posed.obj --rest rest.obj --color q --out q.png --size 1024x768\n"
          "  spinmotor render spot.obj --color checker --camera 120,15 --out spot.png");
      sub.callback([a] {
        render::RenderOptions o;
        render::parse_size(a->size, o);
        if (!a->camera.empty()) render::parse_camera(a->camera, o);
        o.up = a->up == "x"   ? Eigen::Vector3d::UnitX()
               : a->up == "y" ? Eigen::Vector3d::UnitY()
                              : Eigen::Vector3d::UnitZ();
        render::parse_q_range(a->q_range, o);
        o.style.color = a->color == "q"         ? render::ColorMode::Q
                        : a->color == "checker" ? render::ColorMode::Checker
                        : a->color == "normals" ? render::ColorMode::Normals
                                                : render::ColorMode::Plain;
        o.style.smooth = !a->flat;
        o.style.wireframe = a->wireframe;
        o.style.checker_cells = a->cells;
        o.color_bar = !a->no_bar;
        if (o.style.color == render::ColorMode::Q && a->rest.empty())
          throw Error("render: --color q needs --rest REST (Q compares MESH with its rest shape)");
        const Mesh mesh = read_mesh(a->mesh);
        Mesh rest;
        if (!a->rest.empty()) rest = read_mesh(a->rest);
        render::RenderTimings t;
        const render::Image im = render::render_mesh(mesh, a->rest.empty() ? nullptr : &rest, o, &t);
        render::write_png(a->out, im);
        if (!a->quiet)
          std::cout << "wrote " << a->out << " (" << o.width << "x" << o.height << ", " << mesh.V.rows()
                    << " vertices, " << mesh.F.rows() << " faces) with " << t.backend << ": context "
                    << t.context_ms << " ms, upload " << t.upload_ms << " ms, draw " << t.draw_ms << " ms\n";
      });
    }};

}  // namespace

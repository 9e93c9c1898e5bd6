#include "spinmotor/viewer/bone_overlay.hpp"

#include <algorithm>
#include <cmath>

namespace spinmotor::viewer {

int draw_bones(render::Image& im, const std::vector<PosedBone>& bones, const render::OrbitCamera& cam,
               int width, std::array<std::uint8_t, 3> colour) {
  int written = 0;
  auto put = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= im.width || y >= im.height) return;
    const std::size_t i = 4 * (std::size_t(y) * im.width + x);
    im.rgba[i] = colour[0], im.rgba[i + 1] = colour[1], im.rgba[i + 2] = colour[2], im.rgba[i + 3] = 255;
    ++written;
  };
  auto disc = [&](double cx, double cy, double r) {
    for (int y = int(std::floor(cy - r)); y <= int(std::ceil(cy + r)); ++y)
      for (int x = int(std::floor(cx - r)); x <= int(std::ceil(cx + r)); ++x)
        if (std::hypot(x + 0.5 - cx, y + 0.5 - cy) <= r) put(x, y);
  };
  const Eigen::Vector3d forward = (cam.target - cam.eye()).normalized();
  auto in_front = [&](const Eigen::Vector3d& p) { return (p - cam.eye()).dot(forward) > 1e-9; };
  for (const PosedBone& b : bones) {
    if (!in_front(b.head) || !in_front(b.tail)) continue;
    const Eigen::Vector3d a = cam.project(b.head, im.width, im.height),
                          c = cam.project(b.tail, im.width, im.height);
    const double len = std::hypot(c.x() - a.x(), c.y() - a.y());
    const int steps = std::max(1, int(std::ceil(len)));
    for (int k = 0; k <= steps; ++k) {
      const double t = double(k) / steps;
      disc(a.x() + t * (c.x() - a.x()), a.y() + t * (c.y() - a.y()), 0.5 * width);
    }
    disc(a.x(), a.y(), 2.0 * width);
  }
  return written;
}

}  // namespace spinmotor::viewer

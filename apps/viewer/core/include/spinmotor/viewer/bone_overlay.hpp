#pragma once
// The skeleton drawn over a rendered picture (the headless screenshot's --skeleton; the window draws the
// same segments with ImGui): one line per bone from its posed head to its posed tail and a dot at each
// head, projected through the camera that rendered the picture. Window-free, unit-tested.
#include <array>
#include <cstdint>
#include <vector>

#include "spinmotor/render/image.hpp"
#include "spinmotor/render/orbit_camera.hpp"
#include "spinmotor/viewer/session.hpp"

namespace spinmotor::viewer {

/// The bone colour of the overlay (pure orange: no shading of the mesh produces it).
inline constexpr std::array<std::uint8_t, 3> kBoneColour{255, 140, 0};

/// Draws `bones` into `image` (its width × height are the camera's pixels): lines `width` pixels wide,
/// dots of radius 2·width at the heads; bones with an end behind the eye are skipped. Returns the number
/// of pixel writes (0: no bone visible).
int draw_bones(render::Image& image, const std::vector<PosedBone>& bones, const render::OrbitCamera& camera,
               int width = 2, std::array<std::uint8_t, 3> colour = kBoneColour);

}  // namespace spinmotor::viewer

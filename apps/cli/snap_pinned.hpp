#pragma once
// `spinmotor snap ... --mode pinned --pin FILE`: the pose-keeping conformal cleanup
// (spin/pinned_cleanup.hpp), called from cmd_snap.cpp once the meshes are read and checked.
#include <string>

#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

namespace spinmotor::cli {

struct SnapPinnedArgs {
  std::string rest_path, pin_file, out, keep = "auto";
  double pose_weight = PinnedCleanupOptions{}.pose_weight;  ///< γ, uniform attraction a_i = 1
  bool json = false, quiet = false;
};

/// Reads the pins (read_pin_file), binds, cleans `edited` up and writes OUT (EDITED's texture
/// coordinates, or REST's). Throws spinmotor::Error (exit 2) for a missing, unreadable or empty pin
/// file, an index out of range, a component without a pin; nothing is written then.
void snap_pinned(const Mesh& rest, const Mesh& edited, const SnapPinnedArgs& args);

}  // namespace spinmotor::cli

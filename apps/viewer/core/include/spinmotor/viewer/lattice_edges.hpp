#pragma once
// The lines the viewer draws between FFD control points: pairs of controls named "ffd[a,b,c]"
// (cli/scene/deformer_ffd.cpp) that are lattice neighbours. Window-free, unit-tested.
#include <string>
#include <utility>
#include <vector>

namespace spinmotor::viewer {

/// Pairs (i, j), i < j, of indices into `controls` whose names are "ffd[a,b,c]" lattice points
/// differing by one in exactly one of a, b, c. Other names are ignored.
std::vector<std::pair<int, int>> ffd_lattice_edges(const std::vector<std::string>& controls);

}  // namespace spinmotor::viewer

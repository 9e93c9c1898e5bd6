#include "spinmotor/viewer/lattice_edges.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>

namespace spinmotor::viewer {

std::vector<std::pair<int, int>> ffd_lattice_edges(const std::vector<std::string>& controls) {
  std::map<std::array<int, 3>, int> index;
  for (int i = 0; i < int(controls.size()); ++i) {
    std::array<int, 3> abc{};
    int used = 0;
    if (std::sscanf(controls[i].c_str(), "ffd[%d,%d,%d]%n", &abc[0], &abc[1], &abc[2], &used) == 3 &&
        used == int(controls[i].size()))
      index[abc] = i;
  }
  std::vector<std::pair<int, int>> edges;
  for (const auto& [abc, i] : index)
    for (int axis = 0; axis < 3; ++axis) {
      std::array<int, 3> next = abc;
      ++next[axis];
      if (const auto it = index.find(next); it != index.end())
        edges.emplace_back(std::min(i, it->second), std::max(i, it->second));
    }
  return edges;
}

}  // namespace spinmotor::viewer

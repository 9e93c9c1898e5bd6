#pragma once
// What test_delta_mush.cpp and test_delta_mush_alloc.cpp share: a chain of six bones along z with
// rest motors, random weights and random posed frames.
#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/ga.hpp"

namespace test_delta_mush_fixtures {

using namespace spinmotor;

/// Rotation by `degrees` about `axis` (through the origin), then translation by `t`.
inline ga::Mot rigid(const Eigen::Vector3d& axis, double degrees, const Eigen::Vector3d& t) {
  return ga::motor(ga::rotor(axis.normalized(), degrees * M_PI / 180.0), ga::translator(t));
}

/// Six unit bones stacked along z, each with a rest motor of its own.
inline std::vector<Bone> six_bones() {
  std::vector<Bone> b;
  for (int j = 0; j < 6; ++j)
    b.push_back({std::string("b").append(std::to_string(j)),
                 j - 1,
                 {0, 0, 1.0 * j},
                 {0, 0, 1.0 * j + 1},
                 rigid({1.0, static_cast<double>(j), 0.0}, 10 * j, {0, 0, 0.1 * j})});
  return b;
}

/// Random weights on B bones, one zero per row.
inline Eigen::MatrixXd random_weights(Eigen::Index n, int B, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::MatrixXd W(n, B);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int j = 0; j < B; ++j) W(i, j) = u(rng);
    W(i, i % B) = 0.0;
  }
  return W;
}

/// Each bone's rest motor after a random rigid motion of up to `degrees`.
inline std::vector<ga::Mot> random_frames(const std::vector<Bone>& bones, std::mt19937& rng,
                                          double degrees = 60) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<ga::Mot> f;
  for (const Bone& b : bones)
    f.push_back(rigid({u(rng), u(rng), u(rng) + 2.0}, degrees * u(rng), {u(rng), u(rng), u(rng)}) * b.rest);
  return f;
}

}  // namespace test_delta_mush_fixtures

// Skinning of a rigged mesh (deform/skinning.hpp): identity and rigid poses, agreement of the fast
// blends with ga::blend, 4-influence truncation, the twisted-tube volume study (LBS collapses, DLB and
// Log do not), harmonic bone weights, the weight file reader and its errors, skeleton checks.
#include <unistd.h>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace test_skinning {

using namespace spinmotor;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::Vector3d;

namespace {

const ga::Mot kId(1, 0, 0, 0, 0, 0, 0, 0);

ga::Mot rigid(const Vector3d& axis, double degrees, const Vector3d& t) {
  return ga::motor(ga::rotor(axis, degrees * M_PI / 180.0), ga::translator(t));
}

/// Two bones along the z axis of a capped tube of length 10: lower [0, 5], upper [5, 10].
std::vector<Bone> arm() {
  Bone lower{"lower", -1, {0, 0, 0}, {0, 0, 5}};
  Bone upper{"upper", 0, {0, 0, 5}, {0, 0, 10}};
  return {lower, upper};
}

double volume(const MatrixXd& V, const Eigen::MatrixXi& F) {
  double v = 0.0;
  for (Index f = 0; f < F.rows(); ++f) {
    const Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    v += a.dot(b.cross(c));
  }
  return v / 6.0;
}

/// Random weights on 6 bones, 5 non-zero per vertex.
MatrixXd random_weights(Index n, int B, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  MatrixXd W = MatrixXd::Zero(n, B);
  for (Index i = 0; i < n; ++i) {
    for (int j = 0; j < B; ++j) W(i, j) = u(rng);
    W(i, i % B) = 0.0;
  }
  return W;
}

std::vector<Bone> six_bones() {
  std::vector<Bone> b;
  for (int j = 0; j < 6; ++j) {
    std::string name = "b";  // not "b" + to_string(j): GCC 12's -Wrestrict false positive (bug 105329)
    name += std::to_string(j);
    b.push_back({name,
                 j - 1,
                 {0, 0, 1.0 * j},
                 {0, 0, 1.0 * j + 1},
                 rigid({1.0, static_cast<double>(j), 0.0}, 10 * j, {0, 0, 0.1 * j})});
  }
  return b;
}

/// One random rigid frame per bone (axis and translation components in [-1, 1], angle up to
/// max_degrees), composed with the bone's rest frame.
std::vector<ga::Mot> random_frames(const std::vector<Bone>& bones, double max_degrees, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<ga::Mot> frames;
  for (const Bone& b : bones)
    frames.push_back(rigid({u(rng), u(rng), u(rng)}, max_degrees * u(rng), {u(rng), u(rng), u(rng)}) *
                     b.rest);
  return frames;
}

const SkinDeformer::Blend kBlends[] = {SkinDeformer::Blend::LBS, SkinDeformer::Blend::DLB,
                                       SkinDeformer::Blend::Log, SkinDeformer::Blend::PivotLog};

}  // namespace

TEST_CASE("skin: the rest frames give the rest mesh, one rigid motion moves it rigidly", "[skin]") {
  const Mesh m = torus(2.0, 0.6, 40, 20);
  std::mt19937 rng(3);
  const auto bones = six_bones();
  const MatrixXd W = random_weights(m.V.rows(), 6, rng);
  const ga::Mot R = rigid({0.2, 1, -0.4}, 150, {1, 2, -3});
  const Eigen::Isometry3d iso = ga::to_isometry(R);
  const MatrixXd expected = (m.V * iso.linear().transpose()).rowwise() + iso.translation().transpose();
  for (auto blend : kBlends) {
    SkinDeformer d = SkinDeformer::bind(m, bones, W, {blend});
    std::vector<ga::Mot> frames;
    for (const Bone& b : bones) frames.push_back(b.rest);
    MatrixXd V;
    d.pose(frames, V);
    CHECK((V - m.V).cwiseAbs().maxCoeff() < 1e-12);
    for (std::size_t j = 0; j < bones.size(); ++j) frames[j] = R * bones[j].rest;  // K_j = R for every bone
    d.pose(frames, V);
    CHECK((V - expected).cwiseAbs().maxCoeff() < 1e-12);
  }
}

TEST_CASE("skin: at most 4 influences, renormalized, fast blends equal ga::blend", "[skin]") {
  const Mesh m = torus(2.0, 0.6, 30, 16);
  std::mt19937 rng(8);
  const auto bones = six_bones();
  const MatrixXd W = random_weights(m.V.rows(), 6, rng);
  const std::vector<ga::Mot> frames = random_frames(bones, 120, rng);
  for (auto blend : kBlends) {
    SkinDeformer d = SkinDeformer::bind(m, bones, W, {blend});
    const Eigen::SparseMatrix<double> K = d.weights();
    for (Index i = 0; i < m.V.rows(); i += 7) {
      // the kept weights are the 4 largest of the row, scaled to sum 1
      Eigen::VectorXd w = W.row(i).transpose();
      std::vector<double> sorted(w.data(), w.data() + w.size());
      std::sort(sorted.rbegin(), sorted.rend());
      const double s4 = sorted[0] + sorted[1] + sorted[2] + sorted[3];
      for (int j = 0; j < 6; ++j) {
        const double expect = w[j] >= sorted[3] ? w[j] / s4 : 0.0;
        CHECK(std::abs(K.coeff(i, j) - expect) < 1e-15);
      }
    }
    MatrixXd V;
    d.pose(frames, V);
    if (blend == SkinDeformer::Blend::LBS) continue;
    double err = 0.0;
    for (Index i = 0; i < m.V.rows(); i += 5)
      err = std::max(
          err,
          (V.row(i).transpose() - ga::transform(d.vertex_motor(i, frames), m.V.row(i).transpose())).norm());
    CHECK(err < 1e-12);
  }
}

TEST_CASE("skin: LBS and DLB equal their per-vertex definitions at every vertex, across blocks and threads",
          "[skin]") {
  // 10,100 vertices: above the parallel threshold (parallel::kMotorBlend), 79 blocks of 128 vertices
  // (SkinDeformer's LBS/DLB panels), the last one partial; 6 bones, 4 kept influences each with a
  // different pivot bone from vertex to vertex, so blocks mix bones and signs.
  const Mesh m = torus(2.0, 0.6, 101, 100);
  REQUIRE(m.V.rows() % 128 != 0);
  std::mt19937 rng(11);
  const auto bones = six_bones();
  const MatrixXd W = random_weights(m.V.rows(), 6, rng);
  const std::vector<ga::Mot> frames = random_frames(bones, 170, rng);
  {
    SkinDeformer d = SkinDeformer::bind(m, bones, W, {SkinDeformer::Blend::LBS});
    const MatrixXd K = MatrixXd(d.weights());
    std::vector<Eigen::Isometry3d> T;
    for (std::size_t j = 0; j < bones.size(); ++j)
      T.push_back(ga::to_isometry(ga::normalize(frames[j] * ga::reverse(bones[j].rest))));
    MatrixXd V;
    d.pose(frames, V);
    double err = 0.0;
    for (Index i = 0; i < m.V.rows(); ++i) {
      Vector3d v = Vector3d::Zero();
      for (int j = 0; j < 6; ++j) v += K(i, j) * (T[j] * Vector3d(m.V.row(i)));
      err = std::max(err, (V.row(i).transpose() - v).norm());
    }
    CHECK(err < 1e-12);
  }
  // DLB twice: with the random weights every block mixes pivot bones (a sign per vertex); with one
  // dominant bone per run of 300 consecutive vertices most blocks share their pivot (one sign per bone).
  MatrixXd W_runs = 0.2 * W;
  for (Index i = 0; i < m.V.rows(); ++i) W_runs(i, (i / 300) % 6) = 1.0;
  for (const MatrixXd* weights : std::initializer_list<const MatrixXd*>{&W, &W_runs}) {
    SkinDeformer d = SkinDeformer::bind(m, bones, *weights, {SkinDeformer::Blend::DLB});
    MatrixXd V;
    d.pose(frames, V);
    double err = 0.0;
    for (Index i = 0; i < m.V.rows(); ++i)
      err = std::max(
          err,
          (V.row(i).transpose() - ga::transform(d.vertex_motor(i, frames), m.V.row(i).transpose())).norm());
    CHECK(err < 1e-12);
  }
}

TEST_CASE("skin: a tube twisted 180 degrees keeps its volume with DLB and Log, not with LBS", "[skin]") {
  const Mesh m = tube(1.0, 10.0, 101, 48, true);
  const auto bones = arm();
  const MatrixXd W = bone_harmonic_weights(m, bones);
  // harmonic bone weights: a partition of unity in [0, 1], 1 far from the joint
  CHECK((W.rowwise().sum().array() - 1.0).abs().maxCoeff() < 1e-10);
  CHECK(W.minCoeff() > -1e-12);
  CHECK(W(0, 0) == 1.0);  // ring 0 (z = 0) is in the lower bone's region
  const double v0 = volume(m.V, m.F);
  std::vector<ga::Mot> frames = {kId, rigid({0, 0, 1}, 180, {0, 0, 0})};
  double ratio[4];
  for (int b = 0; b < 4; ++b) {
    SkinDeformer d = SkinDeformer::bind(m, bones, W, {kBlends[b]});
    MatrixXd V;
    d.pose(frames, V);
    ratio[b] = volume(V, m.F) / v0;
  }
  WARN("volume ratio after a 180° twist: LBS " << ratio[0] << ", DLB " << ratio[1] << ", Log " << ratio[2]
                                               << ", PivotLog " << ratio[3]);
  CHECK(ratio[0] < 0.95);  // the candy wrapper
  CHECK(ratio[1] > ratio[0]);
  CHECK(ratio[2] > ratio[0]);
  CHECK(ratio[1] > 0.99);
  CHECK(ratio[2] > 0.99);
  CHECK(ratio[1] < 1.01);
  CHECK(ratio[2] < 1.01);
}

TEST_CASE("skin: pose inheritance and skeleton errors", "[skin]") {
  auto bones = arm();
  bones.push_back({"hand", 1, {0, 0, 10}, {0, 0, 11}});
  const ga::Mot R = rigid({1, 0, 0}, 30, {0, 0, 0});
  auto motions = inherit_bone_motions(bones, std::vector<ga::Mot>{kId, R, kId}, {false, true, false});
  CHECK(motions[0] == kId);
  CHECK(motions[1] == R);
  CHECK(motions[2] == R);
  bones[0].parent = 2;
  CHECK_THROWS_WITH(check_skeleton(bones), Catch::Contains("cycle"));
  bones[0].parent = -1;
  bones[2].name = "upper";
  CHECK_THROWS_WITH(check_skeleton(bones), Catch::Contains("same name"));
  bones[2].name = "hand";
  bones[2].tail = bones[2].head;
  CHECK_THROWS_WITH(check_skeleton(bones), Catch::Contains("'hand'"));
}

TEST_CASE("skin: weight file reader", "[skin]") {
  const auto bones = arm();
  const auto dir = std::filesystem::temp_directory_path() / ("spinmotor_skin_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    const auto p = dir / name;
    std::ofstream(p) << text;
    return p;
  };
  const auto good = write("good.txt", "# two bones\nbones upper lower\n0.25 0.75\n\n1 0  # tip\n0 2\n");
  const MatrixXd W = read_skin_weights(good, bones, 3);
  CHECK(W(0, 0) == 0.75);  // columns in skeleton order
  CHECK(W(0, 1) == 0.25);
  CHECK(W(1, 1) == 1.0);
  CHECK(W(2, 0) == 2.0);
  CHECK_THROWS_WITH(read_skin_weights(good, bones, 4), Catch::Contains("good.txt: 3 vertex lines"));
  CHECK_THROWS_WITH(read_skin_weights(write("a.txt", "bones upper elbow\n"), bones, 1),
                    Catch::Contains("a.txt:1:") && Catch::Contains("'elbow'"));
  CHECK_THROWS_WITH(read_skin_weights(write("b.txt", "bones upper lower\n1 0\n0.5\n"), bones, 2),
                    Catch::Contains("b.txt:3:"));
  CHECK_THROWS_WITH(read_skin_weights(write("c.txt", "bones upper lower\n1 x\n"), bones, 1),
                    Catch::Contains("c.txt:2: 'x' is not a number"));
  CHECK_THROWS_WITH(read_skin_weights(write("d.txt", "bones upper lower\n1 -1\n"), bones, 1),
                    Catch::Contains("d.txt:2:"));
  CHECK_THROWS_WITH(read_skin_weights(write("e.txt", "bones upper lower\n0 0\n"), bones, 1),
                    Catch::Contains("e.txt:2: vertex 0 has no positive"));
  CHECK_THROWS_WITH(read_skin_weights(write("f.txt", "1 0\n"), bones, 1), Catch::Contains("f.txt:1:"));
  CHECK_THROWS_WITH(read_skin_weights(write("g.txt", "bones upper\n"), bones, 1), Catch::Contains("'lower'"));
  CHECK_THROWS_WITH(read_skin_weights(dir / "missing.txt", bones, 1), Catch::Contains("missing.txt"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("skin: bind errors name the vertex or bone", "[skin]") {
  const Mesh m = tube(1.0, 10.0, 11, 8, false);
  const auto bones = arm();
  MatrixXd W = MatrixXd::Constant(m.V.rows(), 2, 0.5);
  W(7, 1) = -0.5;
  CHECK_THROWS_WITH(SkinDeformer::bind(m, bones, W, {}),
                    Catch::Contains("vertex 7") && Catch::Contains("'upper'"));
  W(7, 1) = 0.0;
  W(7, 0) = 0.0;
  CHECK_THROWS_WITH(SkinDeformer::bind(m, bones, W, {}), Catch::Contains("vertex 7"));
  // finite weights whose sum overflows are still normalised (not divided by inf into zeros)
  W(7, 0) = W(7, 1) = 1e308;
  CHECK(
      MatrixXd(SkinDeformer::bind(m, bones, W, {}).weights()).row(7).isApprox(Eigen::RowVector2d(0.5, 0.5)));
  W(7, 0) = 1.0;
  W(7, 1) = 0.0;
  SkinDeformer d = SkinDeformer::bind(m, bones, W, {});
  MatrixXd V;
  CHECK_THROWS_WITH(d.pose(std::vector<ga::Mot>{kId}, V), Catch::Contains("1 bone frames"));
  ga::Mot bad = kId;
  bad[0] = 3.0;
  CHECK_THROWS_WITH(d.pose(std::vector<ga::Mot>{kId, bad}, V), Catch::Contains("'upper'"));
}

}  // namespace test_skinning

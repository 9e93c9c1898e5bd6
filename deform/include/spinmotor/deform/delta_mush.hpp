#pragma once
// DeltaMushDeformer: Delta Mush (Mancewicz, Derksen, Rijpkema & Wilson, "Delta Mush: smoothing
// deformations while preserving detail", DigiPro 2014) on top of skinning, the clean-up technical
// artists use (Maya's deltaMush, Blender's Corrective Smooth). A baseline for spinmotor's conformal
// clean-up. Follows the bind/pose contract of deformer.hpp; the controls are the bones, exactly as for
// SkinDeformer (same skeleton, weights and frames).
//
// The method as the paper describes it (implemented from memory of the published text, which is not in
// shared/papers: no section or equation numbers are quoted because they could not be checked):
//   smoothing S   k iterations of uniform Laplacian smoothing, all vertices at once (Jacobi):
//                   x_i ← x_i + λ (1/|N(i)| Σ_{j∈N(i)} x_j − x_i)
//   frame F_i(x)  on a mesh x, at vertex i: n = the area-weighted vertex normal (Σ over the faces
//                 (i, a, b) of (x_a − x_i) × (x_b − x_i), normalized), t = the edge to the first
//                 one-ring neighbour (lowest index) projected onto the plane ⟂ n, normalized (if that
//                 projection vanishes, the next neighbour's), b = n × t.
//   bind          d_i = F_i(S(u))ᵀ (u_i − S(u)_i): the detail the smoothing removes, in the frame of the
//                 smoothed rest mesh (coordinates along t, b, n).
//   pose          v = skin(frames) (SkinDeformer, blend as chosen: LBS by default), then
//                   v'_i = S(v)_i + F_i(S(v)) d_i.
// With 0 iterations S is the identity, d = 0 and the result is the skinning, bit for bit.
//
// pose(): one SkinDeformer pose, k smoothing sweeps over the one-rings, one sweep for the normals (over
// each vertex's incident faces, so no atomics) and the frames; parallel over vertices (OpenMP, from
// parallel::kMotorBlend vertices on); no allocation after the first call (tested).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <span>
#include <vector>

#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

/// The smoothing a skin can be cleaned up with (the scene's skin `mush` key): none (plain skinning),
/// Delta Mush (this header) or Direct Delta Mush (direct_delta_mush.hpp).
enum class MushKind { None, Delta, Direct };
inline constexpr OptionNames<MushKind, 3> kMushKindNames{
    "mush",
    {{{MushKind::None, "none"}, {MushKind::Delta, "delta-mush"}, {MushKind::Direct, "direct-delta-mush"}}}};
constexpr const auto& option_names(MushKind) { return kMushKindNames; }

class DeltaMushDeformer {
 public:
  struct Options {
    int iterations = 10;  ///< smoothing sweeps k ≥ 0
    double step = 0.5;    ///< λ ∈ (0, 1]: the fraction of the way to the one-ring average per sweep
    SkinDeformer::Blend blend = SkinDeformer::Blend::LBS;  ///< the skinning under the mush
  };

  DeltaMushDeformer() = default;

  /// Inputs: rest mesh (finite, manifold, consistently oriented, every vertex in a face, ≥ 1 face),
  /// skeleton and weights as SkinDeformer::bind. Throws Error naming the bad vertex, edge, face or
  /// bone, the bad option, or a vertex of the smoothed rest mesh without a normal or tangent.
  static DeltaMushDeformer bind(const Mesh& rest, std::span<const Bone> bones, const Eigen::MatrixXd& weights,
                                const Options& options);
  static DeltaMushDeformer bind(const Mesh& rest, std::span<const Bone> bones,
                                const Eigen::SparseMatrix<double>& weights, const Options& options);
  /// The deformer shape (deformer.hpp): rig.skeleton and rig.weights (n×B).
  static DeltaMushDeformer bind(const Mesh& rest, const Rig& rig, const Options& options) {
    return bind(rest, rig.skeleton, rig.weights, options);
  }

  /// B posed world frames F_j (unit motors), in bone order. Output: V_out (n×3). Throws Error for a
  /// wrong frame count or a bad frame (naming the bone), and a numerical Error naming the vertex whose
  /// smoothed posed one-ring has collapsed (no normal or no tangent).
  void pose(std::span<const ga::Mot> frames, Eigen::MatrixXd& V_out);

  Eigen::Index vertices() const { return skin_.vertices(); }
  /// One control per bone (its name, anchored at its rest head), as SkinDeformer.
  const std::vector<Control>& controls() const { return skin_.controls(); }
  /// The deltas d_i (n×3: components along t, b, n of the smoothed rest frame).
  const Eigen::MatrixXd& deltas() const { return delta_; }
  /// The skinning under the mush (its weights() are the kept weights).
  const SkinDeformer& skin() const { return skin_; }
  const Options& options() const { return options_; }

 private:
  using RowMatrix3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  static DeltaMushDeformer finish(const Mesh& rest, SkinDeformer skin, const Options& options);
  /// S(x) of `x` (n×3, any storage) into a_ (b_ is the second buffer).
  void smooth(const Eigen::MatrixXd& x);
  /// Frames of the mesh in a_ into the rows of tan_, bit_, nrm_ (unit vectors). Returns −1, or the first
  /// vertex without a normal or tangent.
  int frames();

  Options options_;
  SkinDeformer skin_;
  std::vector<int> ring_offset_, ring_;  // one-rings (CSR, ascending)
  std::vector<int> fan_offset_;          // incident faces of vertex i: fan_[fan_offset_[i] .. +1)
  std::vector<std::array<int, 2>> fan_;  // (a, b) with (i, a, b) a face in its orientation
  Eigen::MatrixXd delta_;                // n×3
  // per-pose scratch
  Eigen::MatrixXd skinned_;
  RowMatrix3 a_, b_, tan_, bit_, nrm_;
};

}  // namespace spinmotor

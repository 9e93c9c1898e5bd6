#pragma once
// The pose-keeping cleanup of a skinned character, bound once: the one door through which the CLI, scene
// files, the viewer, Python and the Blender add-on clean up a rig. It takes the rest surface, the skin
// weights and the bones, chooses pins and the pose attraction from the weights (deform/rig_pins.hpp) and
// runs the cleanup (spin/pinned_cleanup.hpp) on every connected piece of the surface that needs one.
//
//   pins        the vertices one bone moves rigidly (dominant weight ≥ pin_threshold) that lie farther
//               than the margin from every blended vertex (pin_margin, or per bone a quarter of its
//               widest joint band: default_pin_margins);
//   attraction  a_i = smoothstep of the dominant weight between attraction_low and pin_threshold
//               (pin_attraction_from_weights), with strength pose_weight (γ): 1 on the rigid parts, 0 in
//               the middle of each joint, so the joints are free to become conformal while the soft parts
//               of the body stay near the skinned pose.
//
// Pieces. A production character is many connected pieces (a body, eyes, teeth, armour plates, loose
// triangles), some open, some non-manifold. Each connected component of the surface is handled on its own
// (its own factorisation and its own kept measure: the volume when it is closed and consistently oriented,
// every edge used as often in each direction, else its area) and gets a status:
//   cleaned     it has pins, or (γ > 0) vertices with a positive attraction that anchor it;
//   rigid       one bone moves all of it rigidly (every vertex's dominant weight ≥ pin_threshold on the
//               same bone): skinning is already exact, nothing to clean;
//   pinned      every vertex is a pin;
//   unanchored  no pin and no attraction to hold it (γ = 0, or its vertices all sit mid-joint): kept as
//               skinned.
// Nothing aborts on such a piece. Degenerate rest triangles (zero area) are left out of a piece's
// energy, and a vertex no other triangle holds is kept as skinned.
//
// Why γ = 10 by default: on CesiumMan (2,338 welded vertices, 62 pins at 0.999) the cleanup without
// attraction is conformal (Q_mean 1.010) but drifts 3.9% of the diagonal from the pose, a stride that
// closes, because soft weights leave most of the body unpinned; γ = 10 keeps it within 0.6% at Q_mean
// 1.022 and the rest volume (docs/performance.md).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/rig_pins.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

namespace spinmotor::scene {

/// The rig's γ of the pose attraction (header comment). PinnedCleanup on its own, pinned by handles,
/// defaults to 0; a rig's soft parts need the attraction.
inline constexpr double kRigPoseWeight = 10;

/// The cleanup's options with the rig's γ.
inline PinnedCleanupOptions rig_pinned_cleanup_options() {
  PinnedCleanupOptions o;
  o.pose_weight = kRigPoseWeight;
  return o;
}

/// The rig defaults: one home for every option of the rig cleanup and its default.
struct RigCleanupOptions {
  double pin_threshold = kRigidWeight;  ///< pins: dominant weight ≥ this (rig_pins.hpp), in [0.5, 1]
  double pin_margin = -1;  ///< pins: distance to the blended vertices; < 0: per bone (default_pin_margins)
  double attraction_low = kAttractionLow;  ///< dominant weight at and below which a vertex is not attracted
  /// The cleanup's options: iterations, tolerance, warm start, keep, and γ of the pose attraction
  /// (cleanup.pose_weight, kRigPoseWeight by default; 0: the pins only).
  PinnedCleanupOptions cleanup = rig_pinned_cleanup_options();
};

enum class RigPieceStatus { Cleaned, Rigid, Pinned, Unanchored };
inline constexpr OptionNames<RigPieceStatus, 4> kRigPieceStatusNames{
    "status",
    {{{RigPieceStatus::Cleaned, "cleaned"},
      {RigPieceStatus::Rigid, "rigid"},
      {RigPieceStatus::Pinned, "pinned"},
      {RigPieceStatus::Unanchored, "unanchored"}}}};
constexpr const auto& option_names(RigPieceStatus) { return kRigPieceStatusNames; }

/// One connected piece of the surface.
struct RigCleanupPiece {
  std::vector<int> vertices;  ///< its vertices, increasing
  RigPieceStatus status = RigPieceStatus::Cleaned;
  Eigen::Index pins = 0;                 ///< of its vertices
  Eigen::Index faces = 0;                ///< its triangles (degenerate ones included)
  Eigen::Index degenerate = 0;           ///< rest triangles left out of the energy
  CleanupKeep keep = CleanupKeep::None;  ///< the measure kept (cleaned pieces)
};

/// One frame's figures: every cleaned piece's own result, and the whole surface's.
struct RigCleanupResult {
  std::vector<PinnedCleanupResult> pieces;  ///< per piece (default-constructed for pieces not cleaned)
  int iterations = 0;                       ///< the most any piece took
  bool converged = true;                    ///< every cleaned piece met its stopping rule
  /// Σ volumes / Σ rest volumes over the cleaned pieces that keep their volume (1 when none does), after
  /// the cleanup and of the edit.
  double volume_ratio = 1, edit_volume_ratio = 1;
  double pin_error = 0;  ///< the largest over the pieces (PinnedCleanupResult::pin_error)
  double total_ms = 0;
};

class RigCleanup {
 public:
  /// Names a vertex in the caller's numbering for messages (e.g. GltfRig::vertex_label); default "vertex i".
  using VertexLabel = std::function<std::string(Eigen::Index)>;

  RigCleanup();
  ~RigCleanup();
  RigCleanup(RigCleanup&&) noexcept;
  RigCleanup& operator=(RigCleanup&&) noexcept;

  /// Inputs: rest (n vertices, m triangles; any topology), W (n×B skin weights ≥ 0, rows need not sum to
  /// 1), bones (B, for the default margins), options, label. Throws Error naming the problem (bad weights
  /// or options, a bone count that does not match W, and the cleanup's own bind errors, which name the
  /// vertex through `label`).
  [[nodiscard]] static RigCleanup bind(const Mesh& rest, const Eigen::SparseMatrix<double>& W,
                                       std::span<const Bone> bones, const RigCleanupOptions& options = {},
                                       const VertexLabel& label = {});
  [[nodiscard]] static RigCleanup bind(const Mesh& rest, const Eigen::MatrixXd& W,
                                       std::span<const Bone> bones, const RigCleanupOptions& options = {},
                                       const VertexLabel& label = {});

  /// One frame: V_edit (n×3, the skinned pose) → V_out (n×3): cleaned pieces solved, the others copied.
  RigCleanupResult operator()(const Eigen::MatrixXd& V_edit, Eigen::MatrixXd& V_out);
  /// Forget the previous frame (warm start).
  void reset() noexcept;

  const Eigen::VectorXi& pins() const;        ///< increasing vertex indices (over every piece)
  const Eigen::VectorXd& attraction() const;  ///< a_i ∈ [0, 1] per vertex
  const Eigen::VectorXd& margins() const;     ///< per bone, as used for the pins
  const std::vector<RigCleanupPiece>& pieces() const;
  const RigCleanupOptions& options() const;
  Eigen::Index vertices() const;
  /// Vertices of cleaned pieces (what the cleanup may move).
  Eigen::Index cleaned_vertices() const;
  double bind_ms() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinmotor::scene

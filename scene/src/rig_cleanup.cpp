// The rig cleanup, piece by piece (rig_cleanup.hpp).
#include "spinmotor/scene/rig_cleanup.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/deform/rig_pins.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/topology.hpp"

namespace spinmotor::scene {

/// A cleaned piece's own problem: its sub-mesh (local numbering), the cleanup and per-frame buffers. (Not
/// in the anonymous namespace: RigCleanup::Impl, which has external linkage, holds a vector of them.)
struct RigPieceSolver {
  int piece = -1;
  std::vector<int> vertices;  // local -> global
  PinnedCleanup cleanup;
  Eigen::MatrixXd edit, out;
};

namespace {

using Solver = RigPieceSolver;

void check_options(const RigCleanupOptions& o) {
  if (!(o.pin_threshold >= 0.5 && o.pin_threshold <= 1.0))
    throw Error("rig cleanup: pin threshold " + std::to_string(o.pin_threshold) + " outside [0.5, 1]");
  if (!std::isfinite(o.pin_margin)) throw Error("rig cleanup: pin margin is not finite");
  if (!(o.cleanup.pose_weight >= 0) || !std::isfinite(o.cleanup.pose_weight))
    throw Error("rig cleanup: pose weight must be a finite number ≥ 0");
  if (!(o.attraction_low >= 0 && o.attraction_low < o.pin_threshold))
    throw Error("rig cleanup: attraction_low must lie in [0, pin threshold)");
}

bool degenerate(const Mesh& rest, Eigen::Index f) {
  const Eigen::Vector3d a = rest.V.row(rest.F(f, 0)), b = rest.V.row(rest.F(f, 1)),
                        c = rest.V.row(rest.F(f, 2));
  const double l2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return !((b - a).cross(c - a).norm() > kDegenerateFace * l2);
}

/// Closed and consistently oriented: every edge used equally often in each direction (the enclosed
/// volume is then defined and independent of the origin).
bool balanced(const Eigen::MatrixXi& F) {
  std::map<std::pair<int, int>, int> count;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      count[{std::min(a, b), std::max(a, b)}] += a < b ? 1 : -1;
    }
  return std::all_of(count.begin(), count.end(), [](const auto& e) { return e.second == 0; });
}

/// Dominant bone of each vertex (normalised weight ≥ threshold), −1 where blended.
std::vector<int> rigid_bone(const Eigen::MatrixXd& W, double threshold) {
  std::vector<int> out(static_cast<size_t>(W.rows()), -1);
  for (Eigen::Index i = 0; i < W.rows(); ++i) {
    Eigen::Index j = 0;
    const double top = W.row(i).maxCoeff(&j), sum = W.row(i).sum();
    if (sum > 0 && top / sum >= threshold) out[i] = static_cast<int>(j);
  }
  return out;
}

}  // namespace

struct RigCleanup::Impl {
  RigCleanupOptions options;
  Eigen::Index n = 0;
  Eigen::VectorXi pins;
  Eigen::VectorXd attraction, margins;
  std::vector<RigCleanupPiece> pieces;
  std::vector<Solver> solvers;
  Eigen::Index cleaned = 0;
  double bind_ms = 0;

  void classify(const Mesh& rest, const Eigen::MatrixXd& W, const VertexLabel& label);
  void bind_piece(const Mesh& rest, const std::vector<Eigen::Index>& faces, int p, const VertexLabel& label);
};

void RigCleanup::Impl::classify(const Mesh& rest, const Eigen::MatrixXd& W, const VertexLabel& label) {
  // Pieces: connected components of the non-degenerate rest triangles.
  std::vector<Eigen::Index> kept;
  std::vector<Eigen::Index> dropped_of(static_cast<size_t>(n), 0);
  for (Eigen::Index f = 0; f < rest.F.rows(); ++f) {
    if (degenerate(rest, f)) {
      ++dropped_of[rest.F(f, 0)];
      continue;
    }
    kept.push_back(f);
  }
  Eigen::MatrixXi F(static_cast<Eigen::Index>(kept.size()), 3);
  for (size_t k = 0; k < kept.size(); ++k) F.row(static_cast<Eigen::Index>(k)) = rest.F.row(kept[k]);
  int count = 0;
  const Eigen::VectorXi comp = vertex_components(F, n, &count);
  pieces.assign(static_cast<size_t>(count), {});
  for (Eigen::Index i = 0; i < n; ++i) pieces[comp[i]].vertices.push_back(static_cast<int>(i));
  std::vector<std::vector<Eigen::Index>> faces(static_cast<size_t>(count));
  for (Eigen::Index k = 0; k < F.rows(); ++k) faces[comp[F(k, 0)]].push_back(kept[k]);
  for (Eigen::Index f = 0; f < rest.F.rows(); ++f) ++pieces[comp[rest.F(f, 0)]].faces;
  for (Eigen::Index i = 0; i < n; ++i) pieces[comp[i]].degenerate += dropped_of[i];
  std::vector<char> pinned(static_cast<size_t>(n), 0);
  for (const int i : pins) pinned[i] = 1;
  const std::vector<int> bone = rigid_bone(W, options.pin_threshold);
  for (int p = 0; p < count; ++p) {
    RigCleanupPiece& piece = pieces[p];
    double attracted = 0;
    for (const int i : piece.vertices) piece.pins += pinned[i], attracted += attraction[i];
    const int b0 = bone[piece.vertices.front()];
    const bool rigid = b0 >= 0 && std::all_of(piece.vertices.begin(), piece.vertices.end(),
                                              [&](int i) { return bone[i] == b0; });
    if (faces[p].empty() || piece.pins == static_cast<Eigen::Index>(piece.vertices.size()))
      piece.status = RigPieceStatus::Pinned;
    else if (rigid)
      piece.status = RigPieceStatus::Rigid;
    else if (piece.pins == 0 && !(options.cleanup.pose_weight > 0 && attracted > 0))
      piece.status = RigPieceStatus::Unanchored;
    else
      bind_piece(rest, faces[p], p, label);
  }
}

void RigCleanup::Impl::bind_piece(const Mesh& rest, const std::vector<Eigen::Index>& faces, int p,
                                  const VertexLabel& label) {
  RigCleanupPiece& piece = pieces[p];
  Solver s;
  s.piece = p;
  s.vertices = piece.vertices;
  std::vector<int> local(static_cast<size_t>(n), -1);
  for (size_t k = 0; k < s.vertices.size(); ++k) local[s.vertices[k]] = static_cast<int>(k);
  Mesh sub;
  sub.V.resize(static_cast<Eigen::Index>(s.vertices.size()), 3);
  for (size_t k = 0; k < s.vertices.size(); ++k)
    sub.V.row(static_cast<Eigen::Index>(k)) = rest.V.row(s.vertices[k]);
  sub.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t k = 0; k < faces.size(); ++k)
    for (int c = 0; c < 3; ++c) sub.F(static_cast<Eigen::Index>(k), c) = local[rest.F(faces[k], c)];
  std::vector<int> sub_pins;
  Eigen::VectorXd sub_attraction(static_cast<Eigen::Index>(s.vertices.size()));
  for (size_t k = 0; k < s.vertices.size(); ++k)
    sub_attraction[static_cast<Eigen::Index>(k)] = attraction[s.vertices[k]];
  for (const int i : pins)
    if (local[i] >= 0) sub_pins.push_back(local[i]);
  const bool closed = boundary_vertices(sub.F, sub.V.rows()).size() == 0 && balanced(sub.F);
  PinnedCleanupOptions o = options.cleanup;
  if (o.keep == CleanupKeep::Auto || (o.keep == CleanupKeep::Volume && !closed))
    o.keep = closed ? CleanupKeep::Volume : CleanupKeep::Area;
  try {
    s.cleanup = PinnedCleanup::bind(sub, sub_pins, o,
                                    std::span<const double>(sub_attraction.data(), sub_attraction.size()));
  } catch (const Error& e) {
    const std::string where =
        label ? label(s.vertices.front()) : "vertex " + std::to_string(s.vertices.front());
    throw Error("rig cleanup: the piece of " + where + " (" + std::to_string(s.vertices.size()) +
                    " vertices): " + e.what(),
                e.kind());
  }
  piece.keep = s.cleanup.keep();
  cleaned += static_cast<Eigen::Index>(s.vertices.size());
  solvers.push_back(std::move(s));
}

RigCleanup::RigCleanup() : impl_(std::make_unique<Impl>()) {}
RigCleanup::~RigCleanup() = default;
RigCleanup::RigCleanup(RigCleanup&&) noexcept = default;
RigCleanup& RigCleanup::operator=(RigCleanup&&) noexcept = default;

RigCleanup RigCleanup::bind(const Mesh& rest, const Eigen::MatrixXd& W, std::span<const Bone> bones,
                            const RigCleanupOptions& options, const VertexLabel& label) {
  check_options(options);
  if (static_cast<Eigen::Index>(bones.size()) != W.cols()) {
    std::ostringstream s;
    s << "rig cleanup: " << bones.size() << " bones for " << W.cols() << " weight columns";
    throw Error(s.str());
  }
  if (W.rows() != rest.V.rows() || rest.V.cols() != 3 || rest.F.cols() != 3)
    throw Error("rig cleanup: " + std::to_string(W.rows()) + " weight rows for " +
                std::to_string(rest.V.rows()) + " vertices (the rest mesh needs n×3 V and m×3 F)");
  const auto t0 = std::chrono::steady_clock::now();
  RigCleanup out;
  Impl& m = *out.impl_;
  m.options = options;
  m.n = rest.V.rows();
  const double threshold = options.pin_threshold;
  m.margins = options.pin_margin >= 0 ? Eigen::VectorXd::Constant(W.cols(), options.pin_margin)
                                      : default_pin_margins(rest.V, W, bones, threshold);
  m.pins = pins_from_weights(rest.V, W, threshold, m.margins);
  m.attraction = options.cleanup.pose_weight > 0
                     ? pin_attraction_from_weights(W, threshold, options.attraction_low)
                     : Eigen::VectorXd::Zero(W.rows());
  m.classify(rest, W, label);
  m.bind_ms = ms_since(t0);
  return out;
}

RigCleanup RigCleanup::bind(const Mesh& rest, const Eigen::SparseMatrix<double>& W,
                            std::span<const Bone> bones, const RigCleanupOptions& options,
                            const VertexLabel& label) {
  return bind(rest, Eigen::MatrixXd(W), bones, options, label);
}

RigCleanupResult RigCleanup::operator()(const Eigen::MatrixXd& V_edit, Eigen::MatrixXd& V_out) {
  const auto t0 = std::chrono::steady_clock::now();
  Impl& m = *impl_;
  if (V_edit.rows() != m.n || V_edit.cols() != 3)
    throw Error("rig cleanup: the edit has " + std::to_string(V_edit.rows()) + "×" +
                std::to_string(V_edit.cols()) + " positions for " + std::to_string(m.n) + " vertices");
  V_out = V_edit;
  RigCleanupResult r;
  r.pieces.resize(m.pieces.size());
  double measure = 0, rest = 0, edit = 0;
  for (Solver& s : m.solvers) {
    const Eigen::Index k = static_cast<Eigen::Index>(s.vertices.size());
    s.edit.resize(k, 3);
    for (Eigen::Index i = 0; i < k; ++i) s.edit.row(i) = V_edit.row(s.vertices[i]);
    PinnedCleanupResult pr = s.cleanup.cleanup(s.edit, s.out);
    for (Eigen::Index i = 0; i < k; ++i) V_out.row(s.vertices[i]) = s.out.row(i);
    r.iterations = std::max(r.iterations, pr.iterations);
    r.converged = r.converged && pr.converged;
    if (pr.kept == CleanupKeep::Volume)
      measure += pr.measure, rest += pr.rest_measure, edit += pr.edit_measure;
    r.pin_error = std::max(r.pin_error, pr.pin_error);
    r.pieces[s.piece] = std::move(pr);
  }
  r.volume_ratio = rest != 0 ? measure / rest : 1.0;
  r.edit_volume_ratio = rest != 0 ? edit / rest : 1.0;
  r.total_ms = ms_since(t0);
  return r;
}

void RigCleanup::reset() noexcept {
  for (Solver& s : impl_->solvers) s.cleanup.reset();
}

const Eigen::VectorXi& RigCleanup::pins() const { return impl_->pins; }
const Eigen::VectorXd& RigCleanup::attraction() const { return impl_->attraction; }
const Eigen::VectorXd& RigCleanup::margins() const { return impl_->margins; }
const std::vector<RigCleanupPiece>& RigCleanup::pieces() const { return impl_->pieces; }
const RigCleanupOptions& RigCleanup::options() const { return impl_->options; }
Eigen::Index RigCleanup::vertices() const { return impl_->n; }
Eigen::Index RigCleanup::cleaned_vertices() const { return impl_->cleaned; }
double RigCleanup::bind_ms() const { return impl_->bind_ms; }

}  // namespace spinmotor::scene

// Procedural rigged characters (procedural_rig.hpp).
#include "spinmotor/mesh/procedural_rig.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace spinmotor {

namespace {

using Vec3 = Eigen::Vector3d;

constexpr double kPi = std::numbers::pi;

/// Rotation keys 0 → angle → 0 about `axis` at 0, d/2, d (x y z w rows).
GltfChannel rotation_channel(int node, const Vec3& axis, double degrees, double duration) {
  GltfChannel c;
  c.node = node;
  c.path = GltfPath::Rotation;
  c.interpolation = GltfInterpolation::Linear;
  c.times.resize(3);
  c.times << 0.0, duration / 2, duration;
  c.values.resize(3, 4);
  for (int k = 0; k < 3; ++k) {
    const double a = (k == 1 ? degrees : 0.0) * kPi / 180.0;
    const Eigen::Quaterniond q(Eigen::AngleAxisd(a, axis));
    c.values.row(k) << q.x(), q.y(), q.z(), q.w();
  }
  return c;
}

/// A rig with one piece on one skin covering the whole mesh; file numbering = surface numbering.
void single_piece(GltfRig& rig, const std::string& name, int node) {
  const Eigen::Index n = rig.mesh.V.rows();
  rig.file_vertices = n;
  rig.file_to_surface = Eigen::VectorXi::LinSpaced(n, 0, static_cast<int>(n - 1));
  rig.surface_to_file = rig.file_to_surface;
  GltfPiece p;
  p.name = name;
  p.node = node;
  p.mesh = 0;
  p.skin = 0;
  p.vertices = n, p.faces = rig.mesh.F.rows(), p.file_vertices = n;
  p.primitive_start = {0};
  p.default_weights.resize(0);
  rig.pieces = {p};
  GltfSkin s;
  s.name = "skin";
  s.file_index = 0;
  for (int j = 0; j < rig.num_joints(); ++j) s.joints.push_back(j);
  rig.skins = {s};
  rig.joint_skins.assign(rig.joint_nodes.size(), 0);
}

}  // namespace

GltfRig limb_rig(const LimbRigOptions& o) {
  auto bad = [](const std::string& what) { return Error("limb_rig: " + what); };
  if (!(o.radius > 0) || !std::isfinite(o.radius)) throw bad("radius must be positive");
  if (!(o.length > 0) || !std::isfinite(o.length)) throw bad("length must be positive");
  if (o.joints < 2) throw bad("joints must be at least 2");
  if (!(o.blend > 0 && o.blend <= 1)) throw bad("blend must lie in (0, 1]");
  if (!(std::abs(o.bend_degrees) < 180) || !(std::abs(o.twist_degrees) < 180))
    throw bad("bend_degrees and twist_degrees must lie in (−180, 180)");
  if (!(o.duration > 0) || !std::isfinite(o.duration)) throw bad("duration must be positive");

  GltfRig rig;
  rig.mesh = capsule(o.radius, o.length, o.rings, o.sides);
  const Eigen::Index n = rig.mesh.V.rows();
  const int J = o.joints;
  const double s = o.length / J, h = o.blend * s / 2;
  // Nodes 0..J−1: the joint chain; node J: the mesh node (a root).
  rig.nodes.resize(J + 1);
  for (int k = 0; k < J; ++k) {
    GltfNode& g = rig.nodes[k];
    g.name = "joint" + std::to_string(k);
    g.parent = k - 1;
    if (k > 0) g.translation = Vec3(0, 0, s);
    rig.joint_nodes.push_back(k);
    rig.joint_names.push_back(g.name);
    rig.joint_parents.push_back(k - 1);
    Eigen::Matrix4d ibm = Eigen::Matrix4d::Identity();
    ibm(2, 3) = -k * s;
    rig.inverse_bind.push_back(ibm);
  }
  rig.nodes[J].name = "limb";
  single_piece(rig, "limb", J);

  std::vector<Eigen::Triplet<double>> w;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double z = rig.mesh.V(i, 2);
    const int seg = std::clamp(static_cast<int>(std::floor(z / s)), 0, J - 1);
    int joint = -1;  // the inner joint whose band holds z, if any (bands do not overlap for blend ≤ 1)
    for (int k = 1; k < J; ++k)
      if (std::abs(z - k * s) < h) joint = k;
    if (joint < 0) {
      w.emplace_back(static_cast<int>(i), seg, 1.0);
      continue;
    }
    const double u = std::clamp((z - joint * s + h) / (2 * h), 0.0, 1.0), a = u * u * (3 - 2 * u);
    if (a > 0) w.emplace_back(static_cast<int>(i), joint, a);
    if (a < 1) w.emplace_back(static_cast<int>(i), joint - 1, 1 - a);
  }
  rig.weights.resize(n, J);
  rig.weights.setFromTriplets(w.begin(), w.end());

  GltfAnimation bend{"bend", 0.0, o.duration, {}}, twist{"twist", 0.0, o.duration, {}};
  for (int k = 1; k < J; ++k)
    bend.channels.push_back(rotation_channel(k, Vec3::UnitX(), o.bend_degrees, o.duration));
  twist.channels.push_back(rotation_channel(J - 1, Vec3::UnitZ(), o.twist_degrees, o.duration));
  rig.animations = {bend, twist};
  return rig;
}

// ---- the standing character ---------------------------------------------------------------------------

namespace {

struct JointSpec {
  const char* name;
  int parent;
  Vec3 p;  // rest position in scene space
};

// The skeleton, parents first (indices into this table; also the joint and node order).
enum Joint {
  Hips,
  Spine,
  Chest,
  Neck,
  Head,
  ShoulderL,
  ElbowL,
  WristL,
  ShoulderR,
  ElbowR,
  WristR,
  ThighL,
  KneeL,
  AnkleL,
  ThighR,
  KneeR,
  AnkleR,
  kJoints
};
const JointSpec kSkeleton[kJoints] = {{"hips", -1, {0, 0.95, 0}},
                                      {"spine", Hips, {0, 1.1, 0}},
                                      {"chest", Spine, {0, 1.3, 0}},
                                      {"neck", Chest, {0, 1.55, 0}},
                                      {"head", Neck, {0, 1.66, 0}},
                                      {"shoulderL", Chest, {0.22, 1.5, 0}},
                                      {"elbowL", ShoulderL, {0.52, 1.5, 0}},
                                      {"wristL", ElbowL, {0.82, 1.5, 0}},
                                      {"shoulderR", Chest, {-0.22, 1.5, 0}},
                                      {"elbowR", ShoulderR, {-0.52, 1.5, 0}},
                                      {"wristR", ElbowR, {-0.82, 1.5, 0}},
                                      {"thighL", Hips, {0.1, 0.92, 0}},
                                      {"kneeL", ThighL, {0.1, 0.49, 0}},
                                      {"ankleL", KneeL, {0.1, 0.06, 0}},
                                      {"thighR", Hips, {-0.1, 0.92, 0}},
                                      {"kneeR", ThighR, {-0.1, 0.49, 0}},
                                      {"ankleR", KneeR, {-0.1, 0.06, 0}}};

/// A piece under construction, in scene space.
struct PieceSpec {
  std::string name;
  Mesh mesh;
  std::vector<Eigen::Triplet<double>> weights;  // (local vertex, joint, w)
  std::vector<Eigen::MatrixXd> targets;
  std::vector<std::string> target_names;
};

/// capsule() turned so that its axis runs from a to b.
Mesh placed_capsule(double radius, const Vec3& a, const Vec3& b, int rings, int sides) {
  Mesh m = capsule(radius, (b - a).norm(), rings, sides);
  const Eigen::Matrix3d R =
      Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), (b - a).normalized()).toRotationMatrix();
  m.V = ((m.V * R.transpose()).rowwise() + a.transpose()).eval();
  return m;
}

/// Smoothstep limb weights: `upper` before the band of half-width h around the middle joint, `lower` after.
void limb_weights(PieceSpec& p, const Vec3& a, const Vec3& mid, int upper, int lower, double h) {
  const Vec3 d = (mid - a).normalized();
  const double sm = (mid - a).norm();
  for (Eigen::Index i = 0; i < p.mesh.V.rows(); ++i) {
    const double s = (p.mesh.V.row(i).transpose() - a).dot(d);
    const double u = std::clamp((s - sm + h) / (2 * h), 0.0, 1.0), w = u * u * (3 - 2 * u);
    if (w < 1) p.weights.emplace_back(static_cast<int>(i), upper, 1 - w);
    if (w > 0) p.weights.emplace_back(static_cast<int>(i), lower, w);
  }
}

/// The torso's Gaussian weights over hips, spine, chest, neck and the shoulders (up to six influences).
void torso_weights(PieceSpec& p) {
  const int joints[] = {Hips, Spine, Chest, Neck, ShoulderL, ShoulderR};
  const double sigma = 0.16;
  for (Eigen::Index i = 0; i < p.mesh.V.rows(); ++i) {
    const Vec3 x = p.mesh.V.row(i).transpose();
    double w[6], sum = 0, kept = 0;
    for (int k = 0; k < 6; ++k) {
      const Vec3& c = kSkeleton[joints[k]].p;
      const double d = k < 4 ? x.y() - c.y() : (x - c).norm() * 1.5;
      sum += (w[k] = std::exp(-(d * d) / (sigma * sigma)));
    }
    for (int k = 0; k < 6; ++k) kept += (w[k] = w[k] > 1e-4 * sum ? w[k] : 0.0);
    for (int k = 0; k < 6; ++k)
      if (w[k] > 0) p.weights.emplace_back(static_cast<int>(i), joints[k], w[k] / kept);
  }
}

std::vector<PieceSpec> character_pieces(const CharacterRigOptions& o) {
  const int r = o.resolution;
  std::vector<PieceSpec> out;
  PieceSpec torso{"Torso", placed_capsule(0.16, {0, 0.95, 0}, {0, 1.55, 0}, 24 * r, 28 * r), {}, {}, {}};
  torso_weights(torso);
  out.push_back(std::move(torso));
  PieceSpec head{"Head", uv_sphere(12 * r, 24 * r, 0.12), {}, {}, {}};
  const Vec3 hc(0, 1.72, 0);
  // uv_sphere's poles lie on ±z: turn them onto ±y, then place the head.
  const Eigen::Matrix3d up = Eigen::AngleAxisd(-kPi / 2, Vec3::UnitX()).toRotationMatrix();
  head.mesh.V = ((head.mesh.V * up.transpose()).rowwise() + hc.transpose()).eval();
  for (Eigen::Index i = 0; i < head.mesh.V.rows(); ++i)
    head.weights.emplace_back(static_cast<int>(i), Head, 1.0);
  if (o.morph_targets) {
    Eigen::MatrixXd bulge = Eigen::MatrixXd::Zero(head.mesh.V.rows(), 3), squint = bulge;
    for (Eigen::Index i = 0; i < head.mesh.V.rows(); ++i) {
      const Vec3 rel = head.mesh.V.row(i).transpose() - hc;
      if (rel.y() > 0) bulge.row(i) = 0.03 * (rel.y() / 0.12) * rel.normalized().transpose();
      if (rel.z() > 0) squint(i, 2) = -0.5 * rel.z();
    }
    head.targets = {bulge, squint};
    head.target_names = {"bulge", "squint"};
  }
  out.push_back(std::move(head));
  const double band = 0.06;
  for (int side = 0; side < 2; ++side) {
    const int sh = side == 0 ? ShoulderL : ShoulderR, el = sh + 1, wr = sh + 2;
    PieceSpec arm{side == 0 ? "ArmL" : "ArmR",
                  placed_capsule(0.05, kSkeleton[sh].p, kSkeleton[wr].p, 36 * r, 12 * r),
                  {},
                  {},
                  {}};
    limb_weights(arm, kSkeleton[sh].p, kSkeleton[el].p, sh, el, band);
    out.push_back(std::move(arm));
  }
  for (int side = 0; side < 2; ++side) {
    const int th = side == 0 ? ThighL : ThighR, kn = th + 1, an = th + 2;
    PieceSpec leg{side == 0 ? "LegL" : "LegR",
                  placed_capsule(0.07, kSkeleton[th].p, kSkeleton[an].p, 40 * r, 14 * r),
                  {},
                  {},
                  {}};
    limb_weights(leg, kSkeleton[th].p, kSkeleton[kn].p, th, kn, band);
    out.push_back(std::move(leg));
  }
  PieceSpec cap{"Cap", grid(Eigen::Vector2d(0.1, 0.1), Eigen::Vector2i(4 * r + 1, 4 * r + 1)), {}, {}, {}};
  cap.mesh.V = ((cap.mesh.V * up.transpose()).rowwise() + Vec3(0, 1.845, 0).transpose()).eval();
  for (Eigen::Index i = 0; i < cap.mesh.V.rows(); ++i)
    cap.weights.emplace_back(static_cast<int>(i), Head, 1.0);
  out.push_back(std::move(cap));
  return out;
}

/// Quaternion keys of `angle(t)` (radians) about a scene axis, as a local rotation of a joint whose
/// parent frame is turned by R (local = Rᵀ q R).
GltfChannel walk_rotation(int node, const Vec3& axis, const Eigen::Matrix3d& R,
                          const std::function<double(double)>& angle) {
  GltfChannel c;
  c.node = node;
  c.path = GltfPath::Rotation;
  c.times = Eigen::VectorXd::LinSpaced(9, 0.0, 1.0);
  c.values.resize(9, 4);
  for (int k = 0; k < 9; ++k) {
    const Eigen::Quaterniond q(Eigen::AngleAxisd(angle(c.times[k]), R.transpose() * axis));
    c.values.row(k) << q.x(), q.y(), q.z(), q.w();
  }
  return c;
}

/// The joints (Scene layout: roots at the top; else under an "Armature" node of rotation R, scale s)
/// and their inverse bind matrices.
void character_skeleton(const CharacterRigOptions& o, const Eigen::Matrix3d& R, double s, GltfRig& rig) {
  const bool armature = o.layout != CharacterLayout::Scene;
  // A: the armature's global matrix (identity in the Scene layout); joints' local frames are A's.
  Eigen::Matrix4d A = Eigen::Matrix4d::Identity();
  A.topLeftCorner<3, 3>() = s * R;
  for (int j = 0; j < kJoints; ++j) {
    const JointSpec& js = kSkeleton[j];
    GltfNode g;
    g.name = js.name;
    const Vec3 rel = js.parent < 0 ? js.p : Vec3(js.p - kSkeleton[js.parent].p);
    g.translation = R.transpose() * rel / s;
    g.parent = js.parent < 0 ? (armature ? kJoints : -1) : js.parent;
    rig.nodes.push_back(g);
    rig.joint_nodes.push_back(j);
    rig.joint_names.push_back(js.name);
    rig.joint_parents.push_back(js.parent);
    rig.joint_skins.push_back(0);
    Eigen::Matrix4d W = A;  // the joint's global matrix at rest: A · translate(A⁻¹ p)
    W.topRightCorner<3, 1>() = js.p;
    Eigen::Matrix4d J = Eigen::Matrix4d::Identity();
    J.topRightCorner<3, 1>() = R.transpose() * js.p / s;
    rig.inverse_bind.push_back(o.layout == CharacterLayout::Armature ? J.inverse() : W.inverse());
  }
  if (armature) {
    GltfNode a;
    a.name = "Armature";
    a.rotation = Eigen::Quaterniond(R);
    a.scale = Vec3::Constant(s);
    rig.nodes.push_back(a);
  }
}

/// The pieces (one node each, skinned by the one skin), welded surface = file vertices.
void character_surface(const CharacterRigOptions& o, const Eigen::Matrix3d& R, double s, GltfRig& rig) {
  const bool armature = o.layout != CharacterLayout::Scene;
  const std::vector<PieceSpec> specs = character_pieces(o);
  // POSITION: scene coordinates, or the armature's (A⁻¹ x) in the Armature layout.
  const Eigen::Matrix3d to_file = o.layout == CharacterLayout::Armature ? Eigen::Matrix3d(R.transpose() / s)
                                                                        : Eigen::Matrix3d::Identity();
  std::vector<Eigen::Triplet<double>> weights;
  GltfSkin skin;
  skin.name = "Skeleton";
  skin.file_index = 0;
  skin.skeleton = Hips;
  for (int j = 0; j < kJoints; ++j) skin.joints.push_back(j);
  rig.skins = {skin};
  Eigen::Index nv = 0, nf = 0, nuv = 0;
  for (const PieceSpec& p : specs) nv += p.mesh.V.rows(), nf += p.mesh.F.rows(), nuv += p.mesh.UV.rows();
  rig.mesh.V.resize(nv, 3), rig.mesh.F.resize(nf, 3), rig.mesh.UV.resize(nuv, 2), rig.mesh.FUV.resize(nf, 3);
  Eigen::Index v0 = 0, f0 = 0, t0 = 0;
  for (const PieceSpec& p : specs) {
    GltfNode node;
    node.name = p.name;
    node.parent = armature ? kJoints : -1;
    if (o.mesh_node_offset) {
      node.translation = Vec3(0.5, 0, 0) / s;
      node.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vec3::UnitY()));
    }
    GltfPiece piece;
    piece.name = p.name;
    piece.node = static_cast<int>(rig.nodes.size());
    rig.nodes.push_back(node);
    piece.mesh = static_cast<int>(rig.pieces.size());
    piece.skin = 0;
    piece.first_vertex = piece.first_file_vertex = v0, piece.vertices = piece.file_vertices = p.mesh.V.rows();
    piece.first_face = f0, piece.faces = p.mesh.F.rows();
    piece.primitive_start = {v0};
    for (const Eigen::MatrixXd& t : p.targets) piece.targets.push_back(t * to_file.transpose());
    piece.target_names = p.target_names;
    piece.default_weights = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(p.targets.size()));
    rig.mesh.V.middleRows(v0, piece.vertices) = p.mesh.V * to_file.transpose();
    rig.mesh.F.middleRows(f0, piece.faces) = p.mesh.F.array() + static_cast<int>(v0);
    rig.mesh.UV.middleRows(t0, p.mesh.UV.rows()) = p.mesh.UV;
    rig.mesh.FUV.middleRows(f0, piece.faces) = p.mesh.FUV.array() + static_cast<int>(t0);
    for (const auto& w : p.weights) weights.emplace_back(static_cast<int>(v0) + w.row(), w.col(), w.value());
    v0 += piece.vertices, f0 += piece.faces, t0 += p.mesh.UV.rows();
    rig.pieces.push_back(std::move(piece));
  }
  rig.file_vertices = nv;
  rig.file_to_surface = Eigen::VectorXi::LinSpaced(nv, 0, static_cast<int>(nv - 1));
  rig.surface_to_file = rig.file_to_surface;
  rig.weights.resize(nv, kJoints);
  rig.weights.setFromTriplets(weights.begin(), weights.end());
}

/// "walk" (legs, arms, head, the hips' bob, morph weights) and, optionally, "squash" (scaling joints).
void character_animations(const CharacterRigOptions& o, const Eigen::Matrix3d& R, double s, GltfRig& rig) {
  const double a = o.walk_degrees * kPi / 180.0;
  auto phase = [](double t) { return 2 * kPi * t; };
  GltfAnimation walk{"walk", 0.0, 1.0, {}};
  walk.channels.push_back(
      walk_rotation(ThighL, Vec3::UnitX(), R, [&](double t) { return -a * std::sin(phase(t)); }));
  walk.channels.push_back(
      walk_rotation(ThighR, Vec3::UnitX(), R, [&](double t) { return a * std::sin(phase(t)); }));
  walk.channels.push_back(
      walk_rotation(KneeL, Vec3::UnitX(), R, [&](double t) { return a * (1 - std::cos(phase(t))) / 2; }));
  walk.channels.push_back(
      walk_rotation(KneeR, Vec3::UnitX(), R, [&](double t) { return a * (1 + std::cos(phase(t))) / 2; }));
  walk.channels.push_back(
      walk_rotation(ShoulderL, Vec3::UnitY(), R, [&](double t) { return 0.6 * a * std::sin(phase(t)); }));
  walk.channels.push_back(
      walk_rotation(ShoulderR, Vec3::UnitY(), R, [&](double t) { return 0.6 * a * std::sin(phase(t)); }));
  walk.channels.push_back(
      walk_rotation(ElbowL, Vec3::UnitY(), R, [&](double t) { return a * (1 + std::sin(phase(t))) / 2; }));
  walk.channels.push_back(
      walk_rotation(ElbowR, Vec3::UnitY(), R, [&](double t) { return -a * (1 - std::sin(phase(t))) / 2; }));
  walk.channels.push_back(
      walk_rotation(Head, Vec3::UnitX(), R, [&](double t) { return 0.3 * a * std::sin(2 * phase(t)); }));
  {
    GltfChannel bob;
    bob.node = Hips;
    bob.path = GltfPath::Translation;
    bob.times = Eigen::VectorXd::LinSpaced(9, 0.0, 1.0);
    bob.values.resize(9, 3);
    for (int k = 0; k < 9; ++k)
      bob.values.row(k) =
          (R.transpose() * Vec3(0, 0.95 + 0.02 * std::cos(2 * phase(bob.times[k])), 0) / s).transpose();
    walk.channels.push_back(bob);
  }
  if (o.morph_targets) {
    GltfChannel w;
    w.node = rig.pieces[1].node;
    w.path = GltfPath::Weights;
    w.times = Eigen::VectorXd::LinSpaced(9, 0.0, 1.0);
    w.values.resize(9, 2);
    for (int k = 0; k < 9; ++k) {
      const double t = w.times[k];
      w.values.row(k) << (1 - std::cos(phase(t))) / 2, 0.5 * t;
    }
    walk.channels.push_back(w);
  }
  rig.animations.push_back(walk);
  if (o.scale_animation) {
    GltfAnimation squash{"squash", 0.0, 1.0, {}};
    GltfChannel chest;
    chest.node = Chest;
    chest.path = GltfPath::Scale;
    chest.times.resize(3);
    chest.times << 0, 0.5, 1;
    chest.values.resize(3, 3);
    chest.values << 1, 1, 1, 1.2, 1.2, 1.2, 1, 1, 1;
    GltfChannel elbow = chest;
    elbow.node = ElbowL;
    elbow.values << 1, 1.5, 1, 1, 1, 1, 1, 1, 1;
    squash.channels = {chest, elbow};
    rig.animations.push_back(squash);
  }
}

}  // namespace

GltfRig character_rig(const CharacterRigOptions& o) {
  if (o.resolution < 1) throw Error("character_rig: resolution must be at least 1");
  if (!(o.armature_scale > 0) || !std::isfinite(o.armature_scale))
    throw Error("character_rig: armature_scale must be positive");
  if (!(std::abs(o.walk_degrees) < 90)) throw Error("character_rig: walk_degrees must lie in (−90, 90)");
  const bool armature = o.layout != CharacterLayout::Scene;
  const double s = armature ? o.armature_scale : 1.0;
  const Eigen::Matrix3d R =
      armature ? Eigen::AngleAxisd(-kPi / 2, Vec3::UnitX()).toRotationMatrix() : Eigen::Matrix3d::Identity();
  GltfRig rig;
  character_skeleton(o, R, s, rig);
  character_surface(o, R, s, rig);
  character_animations(o, R, s, rig);
  return rig;
}

}  // namespace spinmotor

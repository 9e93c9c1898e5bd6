#include "spinmotor/scene/rig_cleanup.hpp"

#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/rig_pins.hpp"

namespace spinmotor::scene {

RigCleanup RigCleanup::bind(const Mesh& rest, const Eigen::MatrixXd& W, std::span<const Bone> bones,
                            const RigCleanupOptions& options) {
  if (static_cast<Eigen::Index>(bones.size()) != W.cols()) {
    std::ostringstream s;
    s << "rig cleanup: " << bones.size() << " bones for " << W.cols() << " weight columns";
    throw Error(s.str());
  }
  const double threshold = options.pin_threshold;
  Eigen::VectorXd margins = options.pin_margin >= 0 ? Eigen::VectorXd::Constant(W.cols(), options.pin_margin)
                                                    : default_pin_margins(rest.V, W, bones, threshold);
  Eigen::VectorXi pins = pins_from_weights(rest.V, W, threshold, margins);
  if (pins.size() == 0) {
    std::ostringstream s;
    s << "rig cleanup: no vertex has a dominant weight ≥ " << threshold
      << " far enough from every blended vertex (largest margin " << margins.maxCoeff()
      << "): lower the pin threshold or the margin";
    throw Error(s.str());
  }
  Eigen::VectorXd attraction = options.pose_weight > 0
                                   ? pin_attraction_from_weights(W, threshold, options.attraction_low)
                                   : Eigen::VectorXd::Ones(W.rows());
  PinnedCleanupOptions o = options.cleanup;
  o.pose_weight = options.pose_weight;
  PinnedCleanup pc = PinnedCleanup::bind(rest, pins, o, attraction);
  return {std::move(pins), std::move(attraction), std::move(margins), std::move(pc)};
}

RigCleanup RigCleanup::bind(const Mesh& rest, const Eigen::SparseMatrix<double>& W,
                            std::span<const Bone> bones, const RigCleanupOptions& options) {
  return bind(rest, Eigen::MatrixXd(W), bones, options);
}

}  // namespace spinmotor::scene

#pragma once
// AnyDeformer: a bound deformer of any type (deformer.hpp's concept), behind one value type.
//
//   AnyDeformer d = SurfaceHarmonicDeformer::bind(rest, rig, options);  // or any other Deformer
//   d.controls();          // names + rest anchors, in pose order
//   d.pose(motors, V);     // one virtual call per frame; the work is the deformer's own
//   if (auto* arap = d.get<ArapDeformer>()) arap->report();  // the concrete type, when a caller needs it
//
// Move-only (a bound deformer owns its factorizations). An empty AnyDeformer (default-constructed or
// moved from) throws Error from controls(), vertices() and pose().
#include <Eigen/Core>
#include <memory>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/deformer.hpp"

namespace spinmotor {

class AnyDeformer {
 public:
  AnyDeformer() = default;
  // The "not AnyDeformer" test comes first: checking Deformer<AnyDeformer> would ask whether AnyDeformer
  // is move-constructible, which considers this constructor again (clang rejects the recursion).
  template <class D>
  requires(!std::is_same_v<std::remove_cvref_t<D>, AnyDeformer> && Deformer<D>)
      AnyDeformer(D deformer)  // NOLINT(google-explicit-constructor): a bound deformer *is* an AnyDeformer
      : self_(std::make_unique<Model<D>>(std::move(deformer))) {}

  [[nodiscard]] const std::vector<Control>& controls() const { return self().controls(); }
  [[nodiscard]] Eigen::Index vertices() const { return self().vertices(); }
  void pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out) { self().pose(motors, V_out); }

  /// The deformer as its concrete type, or nullptr if it is another one.
  template <Deformer D>
  [[nodiscard]] D* get() noexcept {
    auto* m = dynamic_cast<Model<D>*>(self_.get());
    return m ? &m->d : nullptr;
  }
  template <Deformer D>
  [[nodiscard]] const D* get() const noexcept {
    const auto* m = dynamic_cast<const Model<D>*>(self_.get());
    return m ? &m->d : nullptr;
  }

  [[nodiscard]] explicit operator bool() const noexcept { return self_ != nullptr; }

 private:
  struct Concept {
    virtual ~Concept() = default;
    virtual const std::vector<Control>& controls() const = 0;
    virtual Eigen::Index vertices() const = 0;
    virtual void pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out) = 0;
  };
  template <class D>
  struct Model final : Concept {
    explicit Model(D deformer) : d(std::move(deformer)) {}
    const std::vector<Control>& controls() const override { return d.controls(); }
    Eigen::Index vertices() const override { return d.vertices(); }
    void pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out) override { d.pose(motors, V_out); }
    D d;
  };

  Concept& self() const {
    if (!self_) throw Error("AnyDeformer: no deformer is bound");
    return *self_;
  }

  std::unique_ptr<Concept> self_;
};

}  // namespace spinmotor

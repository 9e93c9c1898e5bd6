#pragma once
// Ordering: the one choice of fill-reducing permutation for every sparse factorization of the project,
// with its name table (core/option_names.hpp) for the CLI, scene files and Python.
//
// Each solver accepts the subset it implements and throws Error (BadInput) "<who>: ordering 'x' is
// not supported here (one of: a, b, c)" for the others (require_ordering):
//   CholeskySolver (cholesky_solver.hpp)   auto (default), natural, amd, metis, nesdis
//   LUSolver (lu_solver.hpp)               colamd (default), natural, mmd-ata, mmd-at-plus-a
//   DiracAssembly / SpinTransform (spin/)  natural, amd, metis (of the vertex graph: kVertexOrderings)
//   ArapDeformer (deform/arap.hpp)         auto (default), amd, nested-dissection
// What each value means:
//   auto               the solver's own choice (documented by each solver)
//   natural            no permutation
//   amd                approximate minimum degree (CHOLMOD's AMD)
//   metis              nested dissection by METIS_NodeND
//   nesdis             CHOLMOD's nested dissection (METIS partitions + constrained minimum degree)
//   nested-dissection  ARAP's geometric nested dissection (recursive median splits of the vertices)
//   colamd             column approximate minimum degree (SuperLU's COLAMD)
//   mmd-ata            multiple minimum degree on the pattern of AᵀA (SuperLU)
//   mmd-at-plus-a      multiple minimum degree on the pattern of Aᵀ+A (SuperLU; for symmetric patterns)
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "spinmotor/core/option_names.hpp"

namespace spinmotor {

enum class Ordering { Auto, Natural, AMD, METIS, NESDIS, NestedDissection, COLAMD, MMD_AtA, MMD_AtPlusA };

inline constexpr OptionNames<Ordering, 9> kOrderingNames{"ordering",
                                                         {{{Ordering::Auto, "auto"},
                                                           {Ordering::Natural, "natural"},
                                                           {Ordering::AMD, "amd"},
                                                           {Ordering::METIS, "metis"},
                                                           {Ordering::NESDIS, "nesdis"},
                                                           {Ordering::NestedDissection, "nested-dissection"},
                                                           {Ordering::COLAMD, "colamd"},
                                                           {Ordering::MMD_AtA, "mmd-ata"},
                                                           {Ordering::MMD_AtPlusA, "mmd-at-plus-a"}}}};
constexpr const auto& option_names(Ordering) { return kOrderingNames; }

/// Inputs: an ordering, the ones a solver supports, the solver's name for the message.
/// Throws Error (BadInput) "<who>: ordering 'x' is not supported here (one of: a, b)" unless
/// `supported` contains `ordering`.
void require_ordering(Ordering ordering, std::span<const Ordering> supported, std::string_view who);

/// Inputs: an ordering's name, the ones a caller accepts, the caller's name for the message.
/// Output: the ordering. Throws Error (BadInput) "<who>: unknown ordering 'x' (one of: a, b)" when
/// `name` names none of `supported`, listing only those (for a binding or CLI that accepts a subset).
[[nodiscard]] Ordering parse_ordering(std::string_view name, std::span<const Ordering> supported,
                                      std::string_view who);

/// The names of `supported`, in its order (for a CLI's choices or a Python option list).
[[nodiscard]] std::vector<std::string> ordering_values(std::span<const Ordering> supported);

}  // namespace spinmotor

#include "spinmotor/linalg/graph_ordering.hpp"

#include <cholmod.h>

#include <numeric>
#include <string>

#include "ordering_scope.hpp"
#include "spinmotor/core/error.hpp"

namespace spinmotor {

Eigen::VectorXi graph_ordering(Eigen::Index n, std::span<int> colptr, std::span<int> rowind,
                               Ordering ordering, std::string_view who) {
  require_ordering(ordering, kGraphOrderings, who);
  if (n < 0 || colptr.size() != static_cast<std::size_t>(n) + 1 || colptr[0] != 0 ||
      static_cast<std::size_t>(colptr[static_cast<std::size_t>(n)]) != rowind.size())
    throw Error(std::string(who) +
                ": graph_ordering: colptr must hold n + 1 offsets ending at rowind's size");
  Eigen::VectorXi perm(n);
  if (ordering == Ordering::Natural || n == 0) {
    std::iota(perm.begin(), perm.end(), 0);
    return perm;
  }
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  c.error_handler = nullptr;
  cholmod_sparse A{};
  A.nrow = A.ncol = static_cast<size_t>(n);
  A.nzmax = rowind.size();
  A.p = colptr.data();
  A.i = rowind.data();
  A.stype = 1;  // symmetric, upper triangle read
  A.itype = CHOLMOD_INT;
  A.xtype = CHOLMOD_PATTERN;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  int ok = 0;
  {
    const detail::OrderingScope scope;  // METIS traps SIGTERM (ordering_scope.hpp)
    ok = ordering == Ordering::AMD ? cholmod_amd(&A, nullptr, 0, perm.data(), &c)
                                   : cholmod_metis(&A, nullptr, 0, 1, perm.data(), &c);
  }
  cholmod_finish(&c);
  if (!ok) throw numerical_error(std::string(who) + ": CHOLMOD could not order the graph");
  return perm;
}

}  // namespace spinmotor

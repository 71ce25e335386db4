#pragma once
// Free motions of a singular model, told in the user's terms: which joints turn or slide,
// which links are not held, and whether an end effector moves.
#include <string>
#include <vector>

#include "assembly/assembler.hpp"

namespace stiffmsa::detail {

struct FreeMotions {
  int count = -1;  // dimension of the null space; −1 where it was not computed
  std::vector<std::string> descriptions;
};

FreeMotions describe_free_motions(const Model& model, const Topology& topology, const SparseMatrix& matrix);

}  // namespace stiffmsa::detail

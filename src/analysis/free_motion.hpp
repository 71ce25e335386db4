#pragma once
// What makes a model's system singular, told in the user's terms. A null vector of the system
// either moves something (a free motion: joints turn or slide, links are not held) or only
// changes wrenches (an over-constrained rigid loop whose internal wrenches the model does not
// determine, while every deflection stays unique).
#include <string>
#include <vector>

#include "assembly/assembler.hpp"

namespace stiffmsa::detail {

struct SingularStructure {
  bool analysed = false;   // false above the size where the dense analysis is affordable
  MatX motions;            // unscaled null vectors with a deflection part, one per column
  MatX redundancies;       // unscaled null vectors that change wrenches only
  MatX left_null;          // unscaled basis of the left null space (the equations' dependencies)
  std::vector<std::string> descriptions;
};

SingularStructure analyse_singular_structure(const Model& model, const Topology& topology, const SparseMatrix& matrix);

}  // namespace stiffmsa::detail

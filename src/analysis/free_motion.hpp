#pragma once
// What makes a model's system singular, told in the user's terms. A null vector of the system
// either moves something (a free motion: joints turn or slide, links are not held) or only
// changes wrenches (an over-constrained rigid loop whose internal wrenches the model does not
// determine, while every deflection stays unique).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "assembly/assembler.hpp"
#include "tolerances.hpp"

namespace stiffmsa::detail {

struct SingularStructure {
  bool analysed = false;  // false above the size where the dense analysis is affordable
  MatX motions;           // unscaled null vectors with a deflection part, one per column
  MatX redundancies;      // unscaled null vectors that change wrenches only
  MatX left_null;         // unscaled basis of the left null space (the equations' dependencies)
  std::vector<std::string> descriptions;
};

// Orthonormal bases of the right and left null spaces of a square matrix, computed on its
// equilibrated form: densely for small systems, by sparse rank-revealing QR for large ones
// (nullopt for large ones where SuiteSparse is not built in). Empty bases where the matrix is
// regular to working precision.
struct NullSpaces {
  MatX right_equilibrated;  // in equilibrated unknowns: entries are comparable across units
  VecX column_scale;
  MatX left;  // unscaled: each column u has uᵀ·A = 0
  MatX right() const { return column_scale.asDiagonal() * right_equilibrated; }
};
std::optional<NullSpaces> null_spaces(const SparseMatrix& matrix);

// How the description of a free motion that moves no end effector tells the user to accept
// it; a solve that has accepted it says so instead.
inline constexpr std::string_view kAcceptIdleMotionHint =
    "(an idle motion: accept it with `options: {accept_idle_motions: true}` in the model or "
    "SolveOptions::accept_idle_motions)";
inline constexpr std::string_view kAcceptIdleMotionsHint =
    "(idle motions: accept them with `options: {accept_idle_motions: true}` in the model or "
    "SolveOptions::accept_idle_motions)";
inline constexpr std::string_view kAcceptedIdleMotionTag = "(an idle motion, accepted)";
inline constexpr std::string_view kAcceptedIdleMotionsTag = "(idle motions, accepted)";

SingularStructure analyse_singular_structure(const Model& model, const Topology& topology,
                                             const SparseMatrix& matrix);

}  // namespace stiffmsa::detail

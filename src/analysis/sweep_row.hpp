#pragma once
// The solve of one sweep pose: a structure's workspace at one set of values, with only what a
// sweep's row takes of the result.
#include <span>

#include "stiffmsa/analysis.hpp"

namespace stiffmsa::detail {

// What a solve fills of its Result: everything, or what a sweep's row takes (measure() in
// sweep.cpp): the end effectors' compliance, stiffness, deflection and directional stiffness,
// the link ends' deflections (for the large-deflection warning), the support reactions (for the
// equilibrium check), the report's checks and warnings. A row's Result has no joint results,
// link wrenches, internal forces, reduced stiffness, results in own axes or parameters, and
// names only its end effectors; its notes may name nothing. Its numbers are those of the full
// solve, bit for bit.
enum class ResultScope { everything, sweep_row };

// solve(workspace, values, options) with ResultScope::sweep_row, `options` validated by the
// caller. A model that gets its critical load or the loaded mode is solved in full, as those
// start from the full linear result.
Result solve_sweep_row(Workspace& workspace, std::span<const double> values,
                       const SolveOptions& options);

}  // namespace stiffmsa::detail

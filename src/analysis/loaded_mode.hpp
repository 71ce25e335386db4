#pragma once
// The loaded mode (docs/theory.md §15): a load case's equilibrium in the deformed geometry,
// reached in load steps of Newton iterations on the loaded blocks (elements/loaded_blocks.hpp),
// and the tangent compliance and stiffness of every end effector there.
#include "analysis/case_loads.hpp"
#include "assembly/topology.hpp"
#include "stiffmsa/analysis.hpp"
#include "stiffmsa/result.hpp"

namespace stiffmsa::detail {

// The external wrench at every link end (global axes, moment about the end) of the model's own
// `loads`: the unnamed load case's end loads.
std::vector<Vec6> end_loads(const Model& model, const Topology& topology);

// The loaded results of a load case from `linear`, the linear result of the same case, which
// the loaded result keeps as Result::linear and whose layout, notes and names it takes.
// `loads`: the case's wrench applied at every link end (end_loads for the unnamed case; no
// equivalent end loads), `link_loads` its loads along links and self-weight, dead, whose clamp
// wrenches follow each link's geometry (§15.9); preloads and support settlements come from the
// model. `load_steps`: the number of equal steps to start
// from (each is cut in halves where Newton's iterations do not converge). Throws
// NoEquilibriumError where no equilibrium is found or the path passes a critical point.
Result loaded_result(const Model& model, const Topology& topology, const SolveOptions& options,
                     const Result& linear, const std::vector<Vec6>& loads, int load_steps,
                     const std::vector<ResolvedLinkLoad>& link_loads = {});

// The number of load steps the loaded mode starts from where neither the model nor the caller
// gives one: one step, cut where Newton's iterations do not converge.
inline constexpr int kDefaultLoadSteps = 1;

}  // namespace stiffmsa::detail

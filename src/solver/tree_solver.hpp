#pragma once
// The tree solve: where the links and connection groups of a model form a tree whose root is
// its one support (a serial robot, a chain, a branched arm), the mixed system is solved
// without factorising it. Every wrench follows from equilibrium, passed from the leaves to
// the support, and every deflection from the support's, passed back out; each element block
// solves its own equations for the link ends it hands on (ElementBlock::pass_*). It costs a
// few 6×6 products per link end and load case, and sums the transported compliances the way a
// hand-condensed serial model does, carrying every running sum exactly (TwoSum), so it loses no
// digits on long chains. Its solution is checked against every block's equations, without
// assembling them (check_tree_solution).
#include <cstdint>
#include <optional>
#include <vector>

#include "assembly/assembler.hpp"

namespace stiffmsa::detail {

struct TreeOrder {
  int root = -1;                 // the support's connection group
  std::vector<int> groups;       // breadth first from the root, the root first
  std::vector<int> toward_root;  // per entry of `groups`: its link end on the path to the root (−1 at the root)
};

// The order of a tree solve; nullopt where the links and connection groups do not form a tree
// or where there is not exactly one support.
std::optional<TreeOrder> tree_order(const Topology& topology);

// Whether every block can take part in a tree solve (no passive joint or support).
bool passes_tree(const Blocks& blocks);

// The load cases of a solve: the model's loads in kLoadCase, then a unit wrench in each of the 6
// directions at every end effector.
EndWrenches load_cases(const Model& model, const Topology& topology);

// The unknowns (unknowns × external.columns(), the mixed system's layout) under the external
// wrenches of each column, with the preloads added to kLoadCase.
RowMajorMatX tree_solve(const Blocks& blocks, int link_count, const TreeOrder& order, const EndWrenches& external,
                        Index unknowns);

// The check of a solution against the equations it solves, one block at a time, so that the
// system is never assembled: each block's rows hold only its own link ends' unknowns.
struct TreeCheck {
  double relative_residual = 0;  // the largest over the columns, as relative_residual() defines it
  long nonzeros = 0;             // nonzero coefficients of the equations
  std::uint64_t pattern = 0;     // pattern_fingerprint of the blocks
};
// A hash of the positions the blocks write, in order (explicit zeros included): blocks of a
// model whose numbers changed but whose pattern did not give the same fingerprint.
std::uint64_t pattern_fingerprint(const Blocks& blocks);

TreeCheck check_tree_solution(const Blocks& blocks, const Topology& topology, const RowMajorMatX& x,
                              const EndWrenches& external);

}  // namespace stiffmsa::detail

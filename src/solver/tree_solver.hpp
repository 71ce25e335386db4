#pragma once
// The tree solve: where the links and connection groups of a model form a tree (a serial
// robot, a chain, a branched arm; a parallel robot whose legs meet at its platform and close
// their loops through the ground), the mixed system is solved without factorising it. Every
// wrench follows from equilibrium, passed from the leaves to the root support, and every
// deflection from the root's, passed back out; each element block's equations are solved for
// the link ends it hands on (solver/tree_passes.hpp). It costs a few 6×6 products per link
// end and load case, and sums the transported compliances the way a hand-condensed serial model
// does. On a deep tree it carries every running sum exactly (TwoSum), so that it loses no digits
// on long chains.
//
// Where the passes cannot solve a block alone (a passive joint's free motion, a second support,
// a passive support at the root), the block is cut (cut_unknowns, tree_passes.hpp): the passes take
// its free motion or reaction as given and leave as many of its equations. A first run of the
// passes, with each cut unknown set to 1 in a column of its own besides the load cases, gives
// these equations' residuals as an affine function of the cut unknowns: a small dense system,
// solved by an LU with partial pivoting. A second run with the cut unknowns solved gives the
// solution. This is the force method of hand calculation, with the loop closures and the free
// motions as redundants, on the paper's equations.
//
// Every solution is checked against every block's equations, without assembling them
// (check_block_by_block).
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/LU>

#include "assembly/assembler.hpp"
#include "solver/tree_passes.hpp"

namespace stiffmsa::detail {

struct TreeOrder {
  int root = -1;            // the first support's connection group
  std::vector<int> groups;  // breadth first from the root, the root first
  std::vector<int>
      toward_root;  // per entry of `groups`: its link end on the path to the root (−1 at the root)
  int depth = 0;    // the most links on a path from the root
};

// The order of a tree solve; nullopt where the links and connection groups do not form a tree
// (a loop not through the ground, or parts not connected) or where there is no support.
std::optional<TreeOrder> tree_order(const Topology& topology);

// A model with more cut unknowns than this is left to the factorising solve. The passes cost
// about as much per column as a sparse LU's solve does, and the cut solve runs them over
// 2k + m columns (k load cases, m cut unknowns) where the LU solves k after one factorisation:
// measured on one core, the tripteron (m = 21) takes ~0.4× KLU's time, the Gough–Stewart
// platform (m = 50) ~1.8× (bench/README.md, round 5).
inline constexpr Index kMostCutUnknowns = 32;

// Trees at least this deep carry their running sums in two parts (TreeState). A sum over d links
// rounds d times, to a relative error of about d·1e-16: no digit a result reports on a robot's
// few links, while two-part sums cost about a third of a serial robot's passes.
inline constexpr int kCompensatedFromDepth = 32;

// Whether every block can take part in a tree solve, cut where it must be (a stiffness-only
// CAD link cannot).
bool passes_tree(const Blocks& blocks);

// The load cases of a solve: the model's loads in kLoadCase, then a unit wrench in each of the 6
// directions at every end effector.
EndWrenches load_cases(const Model& model, const Topology& topology);
// The same into `cases`, whose buffers are kept.
void load_cases_into(const Model& model, const Topology& topology, EndWrenches& cases);

// What a tree solve and its check write, kept from one solve to the next (a workspace holds
// one; the frame solve writes its solution to x and checks it the same way): poses of one
// model then allocate none of it once the first has sized it. Buffers of long models are
// released after each solve (release_large), so that a workspace kept between solves does not
// hold hundreds of megabytes.
struct TreeScratch {
  RowMajorMatX x;      // the solution
  RowMajorMatX x_low;  // the passes' low parts (see TreeState)
  // The cut solve's first run, over the load cases and the cut unknowns: its unknowns, their
  // low parts, and one block's right-hand side (wider than the check's, so kept apart: Eigen
  // reallocates a buffer whose size changes).
  RowMajorMatX first_run, first_run_low, cut_rhs;
  // The check's: one block's residual and right-hand side.
  RowMajorMatX block_residual, block_rhs;
  VecX row_sums, column;
  // The passes' 6 × k increment; the load cases of a pose.
  RowMajorMatX increment;
  EndWrenches load_case_wrenches;
  // The cut solve's: its load cases widened by the cut unknowns' columns, the cut unknowns'
  // values of each run, the cut rows' residuals and their small dense system.
  EndWrenches widened;
  RowMajorMatX unit_values, zero_values, cut_values, cut_residuals;
  MatX cut_matrix, cut_load, cut_solution;
  VecX row_scale, column_scale, condition_bound;
  Eigen::PartialPivLU<MatX> cut_lu;
  std::vector<Index> cut_first, cut_rows, cut_targets;
  // Frees each buffer above 1 MiB; smaller ones are kept for the next pose.
  void release_large();
};

// Solves into scratch.x (unknowns × external.columns(), the mixed system's layout) the
// unknowns under the external wrenches of each column, with the preloads added to kLoadCase;
// returns the number of cut unknowns solved for. Running sums are carried in two parts where
// the tree is at least `compensated_from_depth` links deep. Nullopt, for the factorising solve
// to decide, where there are more than `most_cut_unknowns` cut unknowns or their system's
// equilibrated reciprocal condition estimate is below `least_rcond` (a mechanism, a structure
// held rigidly twice over, or nearly so); scratch.x then holds nothing of this model's.
std::optional<Index> tree_solve(const Blocks& blocks, const Topology& topology,
                                const TreeOrder& order, const EndWrenches& external,
                                double least_rcond, TreeScratch& scratch,
                                Index most_cut_unknowns = kMostCutUnknowns,
                                int compensated_from_depth = kCompensatedFromDepth);

// A lower bound on lu.rcond(), the reciprocal condition estimate of `a` from its LU, that costs
// two triangular solves where the estimate (Hager's method with Higham's refinement) takes
// about ten: |(LU)⁻¹| ≤ M(U)⁻¹·M(L)⁻¹ entry by entry, M(T) being T's comparison matrix
// (|diagonal|, −|off-diagonal|), whose inverse is nonnegative, so ‖A⁻¹‖₁ = ‖(LU)⁻¹‖₁ ≤
// ‖M(L)⁻ᵀ·M(U)⁻ᵀ·e‖∞ (e all ones; P only orders the columns); the estimate is at most ‖A⁻¹‖₁.
// The bound's sums have nonnegative terms and round by a few ε; the estimate's solves round by
// about n³·ε·growth·cond (≲ 1e-12·cond for n ≤ kMostCutUnknowns). 0 where a pivot is zero or
// anything is not finite. `scratch` is a buffer of the caller's.
double rcond_lower_bound(const MatX& a, const Eigen::PartialPivLU<MatX>& lu, VecX& scratch);

// How far rcond_lower_bound must clear the least reciprocal condition for the estimate to be
// skipped: the estimate's rounding is then a thousandth of its value at most, far from moving
// it across the threshold, so that the decision is the estimate's in every case.
inline constexpr double kConditionBoundMargin = 1e-3;

// tree_solve of other columns on the very blocks (the same numbers) that the last tree_solve
// into `solved` cut and solved: that solve's equilibrated, factorised cut system is taken as it
// is, so that the first run has no column per cut unknown and nothing is factorised. The same
// operations on each column as tree_solve's, so the same solution. Nullopt where `solved` holds
// no cut system of this size (nothing was cut); the caller checks the solution, as after
// tree_solve. `scratch` is not `solved`.
std::optional<Index> tree_solve_with_cut_system_of(const TreeScratch& solved, const Blocks& blocks,
                                                   const Topology& topology, const TreeOrder& order,
                                                   const EndWrenches& external,
                                                   TreeScratch& scratch);

// The check of a solution against the equations it solves, one block at a time, so that the
// system is never assembled: each block's rows hold only its own link ends' unknowns.
struct BlockCheck {
  double relative_residual = 0;  // the largest over the columns, as relative_residual() defines it
  long nonzeros = 0;             // nonzero coefficients of the equations
  std::uint64_t pattern = 0;     // pattern_fingerprint of the blocks
};
// A hash of the positions the blocks write, in order (explicit zeros included): blocks of a
// model whose numbers changed but whose pattern did not give the same fingerprint.
std::uint64_t pattern_fingerprint(const Blocks& blocks);

// `x` may be scratch.x: the check writes only the scratch's block buffers.
BlockCheck check_block_by_block(const Blocks& blocks, const Topology& topology,
                                const RowMajorMatX& x, const EndWrenches& external,
                                TreeScratch& scratch);

}  // namespace stiffmsa::detail

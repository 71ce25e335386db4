#pragma once
// The tree solve's passes (solver/tree_solver.hpp) over the element kinds: where links and
// connections form a tree with a support at its root, every wrench follows from equilibrium,
// passed from the leaves to the root, and every deflection from the support's, passed back out,
// each block's equations solved for the ends it hands on (with cuts where they cannot be, see
// cut_unknowns). The passes read each kind's numbers (elements/element_kinds.hpp): a link's
// transport d and compliance C, a joint's free directions and spring, a support's directions,
// spring and settlement.
#include <vector>

#include "assembly/assembler.hpp"
#include "elements/element_block.hpp"
#include "stiffmsa/types.hpp"

namespace stiffmsa::detail {

// The load cases of a tree solve (tree_solver.hpp) are columns: the first
// EndWrenches::state_columns() hold the model's load cases with its preloads and settlements
// (kLoadCase, the first, where there is one), the others loads alone (the robot's self-weight)
// or a unit wrench at an end effector each.
inline constexpr Index kLoadCase = 0;

// The external wrenches at the link ends, 6 × k per loaded end (k load cases).
class EndWrenches {
 public:
  EndWrenches(int end_count = 0, Index columns = 0);
  // No wrench at any of `end_count` ends in `columns` columns, the first `state_columns` of
  // which carry the preloads and settlements; buffers are kept, so that the load cases of the
  // next pose allocate nothing.
  void reset(int end_count, Index columns, Index state_columns = 1);
  Index columns() const { return zero_.cols(); }
  Index state_columns() const { return state_columns_; }
  bool any_at(int end) const { return slot_[static_cast<std::size_t>(end)] >= 0; }
  void add(int end, Index column, const Vec6& wrench);
  // 6 × k: the wrenches at `end`, zero where none is applied.
  const MatX& at(int end) const;
  // The same wrenches with zero columns appended up to `columns`, into `wide` (its buffers kept).
  void widen_into(Index columns, EndWrenches& wide) const;

 private:
  std::vector<int> slot_;     // per link end: index into values_, or −1
  std::vector<MatX> values_;  // the first `used_` in use; the others kept for the next reset
  std::size_t used_ = 0;
  MatX zero_;
  Index state_columns_ = 1;
};

// The state of a tree solve: the unknowns x (n × k, the mixed system's layout, one column per
// load case) and the external wrenches. A block asked to pass something writes only the rows
// the pass names. Values passed along a long chain are running sums: where `compensated`, x
// holds each rounded to double and x_low what the rounding left out, so that ten thousand
// links add no more error than one; else x_low is not read or written.
struct TreeState {
  // `increment` is the caller's buffer (a workspace's, kept from pose to pose), sized here.
  TreeState(RowMajorMatX& x_, RowMajorMatX& x_low_, const EndWrenches& external_, bool compensated_,
            RowMajorMatX& increment_)
      : x(x_),
        x_low(x_low_),
        external(external_),
        compensated(compensated_),
        increment(increment_) {
    increment.resize(6, x.cols());
  }

  RowMajorMatX& x;
  RowMajorMatX& x_low;
  const EndWrenches& external;
  bool compensated;
  RowMajorMatX& increment;  // 6 × k scratch of the passes, for set_sum

  // The values of the current block's cut unknowns (see cut_unknowns below), one row
  // per unknown and a column per load case; set by the solve before it calls a cut block.
  const RowMajorMatX* cut_values = nullptr;
  Index cut_first = 0;
  auto cut(Index first, Index count) const {
    return cut_values->middleRows(cut_first + first, count);
  }

  auto deflection(int end) { return x.middleRows<6>(deflection_column(end)); }
  auto wrench(int end) { return x.middleRows<6>(wrench_column(end)); }
  // The rows of `target` (a deflection or wrench column) become sign·(rows of `source`) +
  // `increment`; where the state is compensated, both parts, the increment formed from rounded
  // values and the sum not rounded.
  void set_sum(Index target, Index source, double sign);
  void set_copy(Index target, Index source);  // both parts where compensated
  template <class Derived>                    // low part zero where compensated
  void set_value(Index target, const Eigen::MatrixBase<Derived>& value) {
    x.middleRows<6>(target) = value;
    if (compensated) x_low.middleRows<6>(target).setZero();
  }
  // W at `toward_root` of link ends joined as one (a joint, or a support that is not the root)
  // from Σ W_k = Σ W_ext,k + R, as a running sum through the first of the other ends. R is a
  // support's reaction, its cut unknowns (`with_reaction`), else zero.
  void set_joined_wrench(const std::vector<int>& ends, int toward_root, bool with_reaction);
};

// Whether the block's equations can be solved by the passes, with the block cut where it must
// be: every kind but a stiffness-only CAD link.
bool passes_tree(const ElementBlock& block);

// A cut: where the passes cannot solve all of a block's equations — a passive joint's free
// motion, a second support that closes a loop through the ground, a passive support at the
// root — they take as given as many unknowns of the block's own (a free motion, a reaction),
// read from TreeState::cut, and leave as many of its equations, its cut rows, to a small dense
// system that the solve forms and solves first (solver/tree_solver.hpp). `toward_root` is the
// block's link end on the path to the root support (−1 at the root).
// The number of cut unknowns in the block's place.
Index cut_unknowns(const ElementBlock& block, int toward_root);
// Appends the block's cut rows there, counted from its first row, as many as its unknowns.
void add_cut_rows(const ElementBlock& block, int toward_root, std::vector<Index>& rows);

// One block's steps: sets W at `toward_root` from W at the block's other ends and the external
// wrenches; sets Δt at the block's other ends from Δt at `toward_root` and the wrenches; the
// root (a support) sets Δt at its ends from their wrenches.
void pass_wrench_to_root(const ElementBlock& block, int toward_root, TreeState& state);
void pass_deflection_from_root(const ElementBlock& block, int toward_root, TreeState& state);
void set_root_deflection(const ElementBlock& block, TreeState& state);

struct TreeOrder;
// The two passes over the tree in `order` into x (unknowns × external.columns()), with the cut
// unknowns' values of each column (null where nothing is cut; cut_first: per entry of the order,
// where its block's cut unknowns start). x_low is scratch, used where `compensated`; x holds the
// sums of both parts on return.
void run_passes(const Blocks& blocks, int link_count, const TreeOrder& order,
                const std::vector<Index>& cut_first, const RowMajorMatX* cut_values,
                const EndWrenches& external, Index unknowns, bool compensated, RowMajorMatX& x,
                RowMajorMatX& x_low, RowMajorMatX& increment);

}  // namespace stiffmsa::detail

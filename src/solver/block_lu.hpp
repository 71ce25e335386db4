#pragma once
// A block LU with partial pivoting for square matrices written as dense row blocks over groups
// of 12 columns (docs/theory.md §15.10): the loaded mode's tangent, whose blocks are the element
// blocks' rows and whose column groups are the link ends. It eliminates one column group at a
// time, in an order fixed per layout (a greedy least-front order, leaves first on a tree): the
// rows of every block touching the group, original or left by earlier steps, make one dense
// front; its 12 columns are factorised with partial pivoting over all the front's rows, and the
// rows not chosen, updated, become a block over the front's other groups. The pivots and the
// row order give the determinant's sign.
#include <vector>

#include "stiffmsa/types.hpp"

namespace stiffmsa::detail {

using Index = Eigen::Index;

// The columns per group: a link end's δx, δθ, δW.
inline constexpr int kBlockColumns = 12;
// A pivot below this, on a matrix whose columns and rows are scaled to a largest entry near 1,
// has lost ten digits to cancellation: the matrix is singular to within the rounding of its
// entries' computation, and the factors are not trusted (the caller falls back on a solver that
// equilibrates and pivots over the whole matrix).
inline constexpr double kBlockLuTinyPivot = 1e-10;
// The elimination order's analysis scores every group against every block at each step (its
// cost grows as groups² × blocks): past this many groups a sparse LU's own ordering is the
// cheaper way, and callers take it.
inline constexpr int kBlockLuMostGroups = 128;

// The power of two that brings `largest` into [0.5, 1); 1 for a zero (or non-finite) size:
// the block LU's scale of a row or column whose largest entry is `largest`.
double power_of_two_scale(double largest);

// The blocks of a matrix, in the order of its rows: block b has `rows[b]` rows and touches the
// column groups `groups[b]` (each 12 columns, group g at columns 12·g …). Its values are a
// rows[b] × 12·groups[b].size() column-major matrix, 12 columns per group in that order.
struct BlockLayout {
  int group_count = 0;
  std::vector<int> rows;
  std::vector<std::vector<int>> groups;
};

// Power-of-two scales of a matrix's rows and columns (12·group_count each).
struct BlockScaling {
  VecX row, column;
};

class BlockLU {
 public:
  enum class Outcome {
    factorised,
    // A pivot below kBlockLuTinyPivot of its (equilibrated) column's size: near-singular; the
    // factors are not usable.
    tiny_pivot,
    // Fewer rows than columns meet at some step, or an exact zero pivot.
    singular,
  };

  // The elimination order and every step's front for `layout`; kept while it stays the same.
  void analyze(const BlockLayout& layout);
  const BlockLayout& layout() const { return layout_; }

  // Factorises the matrix with the given blocks' values (layout().rows[b] ×
  // 12·layout().groups[b].size() each), scaled by powers of two: by its own scaling (the
  // largest entry of each column, then of each row, near 1), or by `kept`, another matrix's
  // (`scaling()` of an earlier factorisation of this layout), for a matrix of the same family
  // whose entries differ little from that one's. A power-of-two scaling rounds nothing: it
  // decides which rows partial pivoting compares as larger and what a pivot's size is read
  // against. A stale one may pivot less well, read a fair pivot as tiny (the caller then scales
  // afresh) or, where a column shrank since, a pivot that a fresh scaling would call tiny as
  // fair: the outcome near the threshold then depends on the kept scaling's matrix.
  Outcome factorise(const std::vector<MatX>& values, const BlockScaling* kept = nullptr);
  // The scaling of the last factorisation.
  const BlockScaling& scaling() const { return scaling_; }

  // Solves the last factorised matrix for the columns of b, in place.
  void solve(MatX& b) const;

  // The sign of the last factorised matrix's determinant (+1 or −1).
  double determinant_sign() const { return sign_; }
  // The smallest pivot of the last factorisation over its column's size after equilibration.
  double smallest_pivot() const { return smallest_pivot_; }

 private:
  // Where a block's rows come from in a front: an original block (`source` < 0: block
  // −source−1) or the rows a step left (`source`: that step).
  struct Part {
    int source = 0;
    int first_row = 0;  // in the front
    int rows = 0;
    std::vector<int> column_groups;  // per group of the part, its place in the front's groups
    std::vector<int> zero_groups;    // the front's groups it does not touch
  };
  struct Step {
    int group = 0;            // the column group eliminated
    std::vector<int> groups;  // the front's groups: `group` first, then the others
    std::vector<Part> parts;
    int rows = 0;
    MatX front;                // after factorisation: L, U and the rows left
    std::vector<int> pivots;   // row swaps, LAPACK style (12)
    std::vector<int> row_ids;  // the matrix's row of each front row, after the swaps
  };

  // The two-pass scaling of `values` into scaling_, the column-scaled
  // values into column_scaled_; false where an entry is not finite.
  bool equilibrate(const std::vector<MatX>& values);
  // The front of step `s`: from column_scaled_ (`unscaled` null) or from the blocks' values
  // `unscaled` times the kept column scales, then times the row scales.
  void assemble_front(Step& s, const std::vector<MatX>* unscaled);
  // One part of it (`PartRows` > 0: its rows, at compile time).
  template <int PartRows>
  void assemble_part(Step& s, const Part& part, const std::vector<MatX>* unscaled);
  // Factorises the front's first 12 columns and updates the rest; `sign` takes the pivots'
  // signs. False on a zero pivot.
  bool eliminate(Step& s, double& sign);

  BlockLayout layout_;
  bool structurally_singular_ = false;
  int n_ = 0;
  std::vector<int> first_row_;  // per block
  std::vector<Step> steps_;
  int column_parity_ = 1;  // of the column order of the elimination
  BlockScaling scaling_;
  std::vector<MatX> column_scaled_;  // per block, its values times the column scales
  VecX block_scratch_;               // one block's columns' sizes or scales
  double sign_ = 0;
  double smallest_pivot_ = 0;
  std::vector<int> row_order_;  // the matrix's rows in pivot order
  // The solve's right-hand side of each step's front, reduced: its 12 pivot rows, then the
  // rows it leaves to a later step.
  mutable std::vector<MatX> rhs_;
};

}  // namespace stiffmsa::detail

#pragma once
// The contract between element kinds and the assembler. Unknowns are 12 per link end, laid out
// as [Δt (6), W (6)], so link end k owns columns 12k .. 12k+11. Every element block emits its
// equation rows (paper eq. 18) starting at a row the assembler gives it. The sequence of
// (row, column) positions an element writes depends only on the topology, never on values:
// explicit zeros are written too, so a model whose numbers change keeps its sparsity pattern.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "stiffmsa/types.hpp"

namespace stiffmsa {
struct Kinematics;
}

namespace stiffmsa::detail {

using Index = Eigen::Index;
struct FreeDirections;

inline Index deflection_column(int end_id) { return 12 * static_cast<Index>(end_id); }
inline Index wrench_column(int end_id) { return 12 * static_cast<Index>(end_id) + 6; }

// A block of coefficients as an element writes it, at most 12×6 (a CAD stiffness link's half
// of K12): seen in place where the element holds it by columns, else evaluated on the stack,
// so that writing a pose copies and allocates nothing it need not.
using CoefficientMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 12, 6>;
using CoefficientBlock = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>;

// Receives a block's coefficients, a dense block or an identity at a time, each times a scale
// (a sign, mostly), so that a writer pays one virtual call per block the element writes, not
// per coefficient. Every call sequence of an element depends only on the topology (see above).
class EquationWriter {
 public:
  virtual ~EquationWriter() = default;
  // Coefficients scale·block(i, j) at (row + i, column + j).
  virtual void add_coefficients(Index row, Index column, const CoefficientBlock& block,
                                double scale) = 0;
  virtual void add_identity(Index row, Index column, Index size, double scale) = 0;

  template <class Derived>
  void add_block(Index row, Index column, const Eigen::MatrixBase<Derived>& block,
                 double scale = 1.0) {
    static_assert(
        Derived::MaxRowsAtCompileTime != Eigen::Dynamic && Derived::MaxRowsAtCompileTime <= 12 &&
            Derived::MaxColsAtCompileTime != Eigen::Dynamic && Derived::MaxColsAtCompileTime <= 6,
        "an element writes blocks of at most 12x6 coefficients");
    constexpr bool in_place =
        (Derived::Flags & Eigen::DirectAccessBit) && !(Derived::Flags & Eigen::RowMajorBit);
    if constexpr (in_place) {
      add_coefficients(row, column,
                       CoefficientBlock(block.derived().data(), block.rows(), block.cols(),
                                        Eigen::OuterStride<>(block.derived().outerStride())),
                       scale);
    } else {
      const CoefficientMatrix values(block);
      add_coefficients(row, column,
                       CoefficientBlock(values.data(), values.rows(), values.cols(),
                                        Eigen::OuterStride<>(values.rows())),
                       scale);
    }
  }
  void add_identity(Index row, Index column, Index size) { add_identity(row, column, size, 1.0); }
};

// A writer that takes every coefficient, in the order written, through Derived::put, inlined
// into the loops over a block.
template <class Derived>
class CoefficientWriter : public EquationWriter {
 public:
  using EquationWriter::add_identity;
  void add_coefficients(Index row, Index column, const CoefficientBlock& block,
                        double scale) override {
    for (Index i = 0; i < block.rows(); ++i)
      for (Index j = 0; j < block.cols(); ++j) self().put(row + i, column + j, scale * block(i, j));
  }
  void add_identity(Index row, Index column, Index size, double scale) override {
    for (Index i = 0; i < size; ++i) self().put(row + i, column + i, scale);
  }

 private:
  Derived& self() { return static_cast<Derived&>(*this); }
};

// The load cases of a tree solve (solver/tree_solver.hpp) are columns: the first
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

// Unknowns stored by rows: a link end's deflections and wrenches in every load case are
// adjacent, as the tree solve visits them end by end.
using RowMajorMatX = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

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

  // The values of the current block's cut unknowns (see ElementBlock::cut_unknowns), one row
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

class ElementBlock {
 public:
  virtual ~ElementBlock() = default;
  virtual Index equation_count() const = 0;
  virtual void write_equations(Index first_row, EquationWriter& out) const = 0;
  // Right-hand side of an external wrench applied at link end `end_id`, which this block must
  // hold (only connection blocks — joints, supports, free ends — hold link ends' loads).
  virtual void add_external_wrench(Index first_row, int end_id, const Vec6& wrench,
                                   VecX& rhs) const;
  // Right-hand side of the block's preload, if any (has_preload: whether there is one to add,
  // so that a caller can skip the rows of the many blocks without).
  virtual void add_preload(Index /*first_row*/, VecX& /*rhs*/) const {}
  virtual bool has_preload() const { return false; }
  // A joint's or support's free and constrained directions in this pose (the results read them
  // back rather than recomputing them); null for other blocks.
  virtual const FreeDirections* directions() const { return nullptr; }
  // The kinematics those directions were computed from (free_directions), where they were:
  // a refill with the same kinematics keeps them (refill_blocks). Null for other blocks.
  virtual const Kinematics* kinematics() const { return nullptr; }
  // A flexible link's stiffness K12 (paper eq. 1), [W_i; W_j] = K12·[Δt_i; Δt_j] in the global
  // frame, for the frame solve (solver/frame_solver.hpp); nullopt for a rigid link and for
  // connection blocks.
  virtual std::optional<Mat12> end_stiffness() const { return std::nullopt; }
  // Whether end_stiffness() has one, without forming it (a frame's plan asks every link).
  virtual bool has_end_stiffness() const { return false; }
  // A support's settlement (the ground's prescribed motion, in every load case); nullopt for
  // every other block.
  virtual std::optional<Vec6> settlement() const { return std::nullopt; }

  // The tree solve: where links and connections form a tree with a support at its root, every
  // wrench follows from equilibrium, passed from the leaves to the root, and every deflection
  // from the support's, passed back out, each block solving its own equations for the ends it
  // hands on (with cuts where it cannot, see cut_unknowns). `toward_root` is the block's link
  // end on the path to the support.
  // Whether the block's equations can be solved so, with the block cut where it must be.
  virtual bool passes_tree() const { return false; }
  // A cut: where the passes cannot solve all of a block's equations — a passive joint's free
  // motion, a second support that closes a loop through the ground, a passive support at the
  // root — they take as given as many unknowns of the block's own (a free motion, a reaction),
  // read from TreeState::cut, and leave as many of its equations, its cut rows, to a small
  // dense system that the solve forms and solves first (solver/tree_solver.hpp).
  // The number of cut unknowns in the block's place (`toward_root` = −1 at the root).
  virtual Index cut_unknowns(int /*toward_root*/) const { return 0; }
  // Appends the block's cut rows there, counted from its first row, as many as its unknowns.
  virtual void add_cut_rows(int /*toward_root*/, std::vector<Index>& /*rows*/) const {}
  // Sets W at `toward_root` from W at the block's other ends and the external wrenches.
  virtual void pass_wrench_to_root(int toward_root, TreeState& state) const;
  // Sets Δt at the block's other ends from Δt at `toward_root` and the wrenches.
  virtual void pass_deflection_from_root(int toward_root, TreeState& state) const;
  // The root (a support): sets Δt at its ends from their wrenches.
  virtual void set_root_deflection(TreeState& state) const;
};

}  // namespace stiffmsa::detail

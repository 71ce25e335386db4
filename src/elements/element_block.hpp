#pragma once
// The contract between element kinds and the assembler. Unknowns are 12 per link end, laid out
// as [Δt (6), W (6)], so link end k owns columns 12k .. 12k+11. Every element block emits its
// equation rows (paper eq. 18) starting at a row the assembler gives it. The sequence of
// (row, column) positions an element writes depends only on the topology, never on values:
// explicit zeros are written too, so a model whose numbers change keeps its sparsity pattern.
#include <Eigen/Core>
#include <optional>

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

// The closed set of element kinds. A layer above the elements (the tree solve, the frame solve)
// reads a block's numbers by its kind (visit_block, elements/element_kinds.hpp) instead of
// asking every element for its part of each solve: an element writes its equations, no more.
enum class BlockKind { link, stiffness_link, constraint_joint, elastic_joint, support, free_end };

class ElementBlock {
 public:
  virtual ~ElementBlock() = default;
  BlockKind kind() const { return kind_; }
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
  // A support's settlement (the ground's prescribed motion, in every load case); nullopt for
  // every other block.
  virtual std::optional<Vec6> settlement() const { return std::nullopt; }

 protected:
  explicit ElementBlock(BlockKind kind) : kind_(kind) {}
  ElementBlock(const ElementBlock&) = default;
  ElementBlock& operator=(const ElementBlock&) = default;

 private:
  BlockKind kind_;
};

}  // namespace stiffmsa::detail

#pragma once
// The contract between element kinds and the assembler. Unknowns are 12 per link end, laid out
// as [Δt (6), W (6)], so link end k owns columns 12k .. 12k+11. Every element block emits its
// equation rows (paper eq. 18) starting at a row the assembler gives it. The sequence of
// (row, column) positions an element writes depends only on the topology, never on values:
// explicit zeros are written too, so a model whose numbers change keeps its sparsity pattern.
#include <Eigen/Core>

#include "stiffmsa/types.hpp"

namespace stiffmsa::detail {

using Index = Eigen::Index;

inline Index deflection_column(int end_id) { return 12 * static_cast<Index>(end_id); }
inline Index wrench_column(int end_id) { return 12 * static_cast<Index>(end_id) + 6; }

class EquationWriter {
 public:
  virtual ~EquationWriter() = default;
  virtual void add(Index row, Index column, double value) = 0;

  template <class Derived>
  void add_block(Index row, Index column, const Eigen::MatrixBase<Derived>& block) {
    for (Index i = 0; i < block.rows(); ++i)
      for (Index j = 0; j < block.cols(); ++j) add(row + i, column + j, block(i, j));
  }
  void add_identity(Index row, Index column, Index size, double scale = 1.0) {
    for (Index i = 0; i < size; ++i) add(row + i, column + i, scale);
  }
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
  // Right-hand side of the block's preload, if any.
  virtual void add_preload(Index /*first_row*/, VecX& /*rhs*/) const {}
};

}  // namespace stiffmsa::detail

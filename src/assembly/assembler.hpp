#pragma once
// Aggregation (paper eq. 18): the element blocks stacked into one sparse square system, with
// no merging of rows and columns. The pattern is recorded once; refilling values for a model
// of the same topology reuses it (and so the solver's symbolic analysis).
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "assembly/topology.hpp"
#include "stiffmsa/types.hpp"

namespace stiffmsa::detail {

// A model solved in a workspace built for another topology: the numbering and the sparsity
// pattern would not fit. (A matrix link whose stiffness changes which block is singular
// changes the pattern too.)
[[noreturn]] void throw_topology_changed();

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Blocks = std::vector<std::unique_ptr<ElementBlock>>;
// Unknowns of several load cases stored by rows: a link end's deflections and wrenches in every
// load case are adjacent, as the tree solve visits them end by end and a residual updates them.
using RowMajorMatX = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

class Assembler {
 public:
  // Records the pattern; throws Error when the blocks do not give a square system.
  Assembler(const Blocks& blocks, Index unknowns);

  // Writes the blocks' values into `matrix` (which gets the recorded pattern). Throws
  // InputError when the blocks write a different pattern (the topology changed).
  void fill(const Blocks& blocks, SparseMatrix& matrix) const;

  // Right-hand side of external wrenches at link ends (pairs of end id and wrench) and, when
  // asked, of the preloads.
  VecX right_hand_side(const Blocks& blocks, const Topology& topology,
                       const std::vector<std::pair<int, Vec6>>& wrenches, bool with_preloads) const;

  // Adds the right-hand side of `wrench` at link end `end` to `rhs`.
  void add_wrench(const Blocks& blocks, const Topology& topology, int end, const Vec6& wrench,
                  VecX& rhs) const;

  SystemSize size() const;
  Index unknowns() const { return unknowns_; }
  const std::vector<Index>& first_rows() const { return first_rows_; }

 private:
  Index unknowns_ = 0;
  std::vector<Index> first_rows_;   // per block
  std::vector<int> slots_;          // per write, in writing order: its index in the value array
  std::vector<int> outer_, inner_;  // the compressed column pattern
};

}  // namespace stiffmsa::detail

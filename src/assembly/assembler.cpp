#include "assembly/assembler.hpp"

#include <algorithm>
#include <numeric>
#include <span>

namespace stiffmsa::detail {

void throw_topology_changed() {
  throw InputError({}, "",
                   "these values change the model's topology (its points, links, joints, supports, "
                   "end effectors, or which blocks of a matrix link's stiffness are singular) from "
                   "that of the model the analysis was set up for (in a sweep: the model at the "
                   "parameters' defaults); one analysis solves models of one topology");
}

namespace {

// The first pass over the blocks' writes: how many land in each column, and whether any
// lands outside the system. Knowing the counts, the second pass can put every write straight
// into its column (a counting sort without a record of all columns), in memory of exact size.
class ColumnCounter final : public CoefficientWriter<ColumnCounter> {
 public:
  explicit ColumnCounter(Index unknowns)
      : column_start(static_cast<std::size_t>(unknowns) + 1, 0), unknowns_(unknowns) {}
  void put(Index row, Index column, double) {
    if (row < 0 || row >= unknowns_ || column < 0 || column >= unknowns_) {
      outside = true;
      return;
    }
    ++column_start[static_cast<std::size_t>(column) + 1];
    ++writes;
  }

  std::vector<int> column_start;  // per column: its writes' count, at the next column's index
  std::size_t writes = 0;
  bool outside = false;

 private:
  Index unknowns_;
};

// A write's row and its number in the writing order.
struct Position {
  int row;
  int write;
};

// The second pass: every write into its column's range of `by_column`. The blocks write the
// same positions in the same order on every pass (element_block.hpp), so the ranges fit.
class ColumnSorter final : public CoefficientWriter<ColumnSorter> {
 public:
  ColumnSorter(std::vector<int>& next_in_column, std::vector<Position>& by_column)
      : next_(next_in_column), by_column_(by_column) {}
  void put(Index row, Index column, double) {
    by_column_[static_cast<std::size_t>(next_[static_cast<std::size_t>(column)]++)] = {
        static_cast<int>(row), written_++};
  }

 private:
  std::vector<int>& next_;
  std::vector<Position>& by_column_;
  int written_ = 0;
};

// Checks every write against the recorded sequence: write k must land in slot slots[k], the
// one position (row, column) of the pattern that the k-th write of the recording went to.
class ValueWriter final : public CoefficientWriter<ValueWriter> {
 public:
  ValueWriter(const std::vector<int>& slots, const std::vector<int>& outer,
              const std::vector<int>& inner, double* values)
      : slots_(slots), outer_(outer), inner_(inner), values_(values) {}
  void put(Index row, Index column, double value) {
    if (next_ >= slots_.size() || column < 0 || column + 1 >= static_cast<Index>(outer_.size()))
      throw_topology_changed();
    const int slot = slots_[next_++];
    if (slot < outer_[static_cast<std::size_t>(column)] ||
        slot >= outer_[static_cast<std::size_t>(column) + 1] ||
        inner_[static_cast<std::size_t>(slot)] != row)
      throw_topology_changed();
    values_[slot] += value;
  }
  std::size_t written() const { return next_; }

 private:
  const std::vector<int>& slots_;
  const std::vector<int>& outer_;
  const std::vector<int>& inner_;
  double* values_;
  std::size_t next_ = 0;
};

}  // namespace

Assembler::Assembler(const Blocks& blocks, Index unknowns) : unknowns_(unknowns) {
  ColumnCounter counter(unknowns);
  first_rows_.reserve(blocks.size());
  Index row = 0;
  for (const auto& block : blocks) {
    first_rows_.push_back(row);
    block->write_equations(row, counter);
    row += block->equation_count();
  }
  if (row != unknowns)
    throw Error("internal error: the element blocks give " + std::to_string(row) +
                " equations for " + std::to_string(unknowns) + " unknowns");
  if (counter.outside) throw Error("internal error: an element block writes outside the system");

  // The writes by column, each column's by row; repeated positions share one slot.
  std::vector<int>& column_start = counter.column_start;
  std::partial_sum(column_start.begin(), column_start.end(), column_start.begin());
  std::vector<Position> by_column(counter.writes);
  {
    // Filling advances each column's start to its end, which is the next column's start: one
    // shift afterwards restores the starts without a second array of them.
    ColumnSorter sorter(column_start, by_column);
    for (std::size_t b = 0; b < blocks.size(); ++b)
      blocks[b]->write_equations(first_rows_[b], sorter);
    std::copy_backward(column_start.begin(), column_start.end() - 1, column_start.end());
    column_start.front() = 0;
  }
  const auto n = static_cast<std::size_t>(unknowns);
  const auto column = [&](std::size_t j) {
    return std::span<Position>(by_column).subspan(
        static_cast<std::size_t>(column_start[j]),
        static_cast<std::size_t>(column_start[j + 1] - column_start[j]));
  };
  std::size_t stored = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const auto writes = column(j);
    std::sort(writes.begin(), writes.end(),
              [](const Position& a, const Position& b) { return a.row < b.row; });
    for (std::size_t k = 0; k < writes.size(); ++k)
      if (k == 0 || writes[k].row != writes[k - 1].row) ++stored;
  }
  slots_.assign(counter.writes, -1);
  outer_.assign(n + 1, 0);
  inner_.reserve(stored);
  for (std::size_t j = 0; j < n; ++j) {
    const auto writes = column(j);
    for (std::size_t k = 0; k < writes.size(); ++k) {
      if (k == 0 || writes[k].row != writes[k - 1].row) inner_.push_back(writes[k].row);
      slots_[static_cast<std::size_t>(writes[k].write)] = static_cast<int>(inner_.size()) - 1;
    }
    outer_[j + 1] = static_cast<int>(inner_.size());
  }
}

void Assembler::fill(const Blocks& blocks, SparseMatrix& matrix) const {
  if (matrix.rows() != unknowns_ || matrix.nonZeros() != static_cast<Index>(inner_.size())) {
    matrix = SparseMatrix(unknowns_, unknowns_);
    matrix.resizeNonZeros(static_cast<Index>(inner_.size()));
    std::copy(outer_.begin(), outer_.end(), matrix.outerIndexPtr());
    std::copy(inner_.begin(), inner_.end(), matrix.innerIndexPtr());
  }
  std::fill_n(matrix.valuePtr(), inner_.size(), 0.0);
  ValueWriter writer(slots_, outer_, inner_, matrix.valuePtr());
  if (blocks.size() != first_rows_.size()) throw_topology_changed();
  for (std::size_t b = 0; b < blocks.size(); ++b)
    blocks[b]->write_equations(first_rows_[b], writer);
  if (writer.written() != slots_.size()) throw_topology_changed();
}

void Assembler::add_wrench(const Blocks& blocks, const Topology& topology, int end,
                           const Vec6& wrench, VecX& rhs) const {
  const int group = topology.group_of_end[static_cast<std::size_t>(end)];
  const std::size_t block = static_cast<std::size_t>(topology.link_count + group);
  blocks[block]->add_external_wrench(first_rows_[block], end, wrench, rhs);
}

VecX Assembler::right_hand_side(const Blocks& blocks, const Topology& topology,
                                const std::vector<std::pair<int, Vec6>>& wrenches,
                                bool with_preloads) const {
  VecX rhs = VecX::Zero(unknowns_);
  for (const auto& [end, wrench] : wrenches) add_wrench(blocks, topology, end, wrench, rhs);
  if (with_preloads)
    for (std::size_t b = 0; b < blocks.size(); ++b) blocks[b]->add_preload(first_rows_[b], rhs);
  return rhs;
}

SystemSize Assembler::size() const {
  return {static_cast<long>(unknowns_), static_cast<long>(unknowns_),
          static_cast<long>(inner_.size())};
}

}  // namespace stiffmsa::detail

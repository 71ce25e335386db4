#include "assembly/assembler.hpp"

#include <algorithm>
#include <numeric>

namespace stiffmsa::detail {

void throw_topology_changed() {
  throw InputError({}, "",
                   "these values change the model's topology (its points, links, joints, supports, "
                   "end effectors, or which blocks of a matrix link's stiffness are singular) from "
                   "that of the model the analysis was set up for (in a sweep: the model at the "
                   "parameters' defaults); one analysis solves models of one topology");
}


namespace {

class PositionRecorder final : public EquationWriter {
 public:
  std::vector<int> rows, columns;
  void add(Index row, Index column, double) override {
    rows.push_back(static_cast<int>(row));
    columns.push_back(static_cast<int>(column));
  }
};

// Checks every write against the recorded sequence: write k must land in slot slots[k], the
// one position (row, column) of the pattern that the k-th write of the recording went to.
class ValueWriter final : public EquationWriter {
 public:
  ValueWriter(const std::vector<int>& slots, const std::vector<int>& outer, const std::vector<int>& inner,
              double* values)
      : slots_(slots), outer_(outer), inner_(inner), values_(values) {}
  void add(Index row, Index column, double value) override {
    if (next_ >= slots_.size() || column < 0 || column + 1 >= static_cast<Index>(outer_.size()))
      throw_topology_changed();
    const int slot = slots_[next_++];
    if (slot < outer_[static_cast<std::size_t>(column)] || slot >= outer_[static_cast<std::size_t>(column) + 1] ||
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
  PositionRecorder recorder;
  Index row = 0;
  for (const auto& block : blocks) {
    first_rows_.push_back(row);
    block->write_equations(row, recorder);
    row += block->equation_count();
  }
  if (row != unknowns)
    throw Error("internal error: the element blocks give " + std::to_string(row) +
                " equations for " + std::to_string(unknowns) + " unknowns");
  const std::vector<int>& rows = recorder.rows;
  const std::vector<int>& columns = recorder.columns;
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (rows[k] < 0 || rows[k] >= unknowns || columns[k] < 0 || columns[k] >= unknowns)
      throw Error("internal error: an element block writes outside the system");

  // The positions by column (a counting sort: linear in their number), each column's by row;
  // repeated positions share one slot.
  const auto n = static_cast<std::size_t>(unknowns);
  std::vector<int> column_start(n + 1, 0);
  for (int c : columns) ++column_start[static_cast<std::size_t>(c) + 1];
  std::partial_sum(column_start.begin(), column_start.end(), column_start.begin());
  std::vector<int> order(rows.size());
  {
    std::vector<int> next(column_start.begin(), column_start.end() - 1);
    for (std::size_t k = 0; k < columns.size(); ++k)
      order[static_cast<std::size_t>(next[static_cast<std::size_t>(columns[k])]++)] = static_cast<int>(k);
  }
  slots_.assign(rows.size(), -1);
  outer_.assign(n + 1, 0);
  for (std::size_t j = 0; j < n; ++j) {
    const auto begin = order.begin() + column_start[j], end = order.begin() + column_start[j + 1];
    std::sort(begin, end, [&](int a, int b) { return rows[static_cast<std::size_t>(a)] < rows[static_cast<std::size_t>(b)]; });
    for (auto k = begin; k != end; ++k) {
      const int r = rows[static_cast<std::size_t>(*k)];
      if (k == begin || r != rows[static_cast<std::size_t>(*(k - 1))]) inner_.push_back(r);
      slots_[static_cast<std::size_t>(*k)] = static_cast<int>(inner_.size()) - 1;
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
  if (blocks.size() != first_rows_.size())
    throw_topology_changed();
  for (std::size_t b = 0; b < blocks.size(); ++b) blocks[b]->write_equations(first_rows_[b], writer);
  if (writer.written() != slots_.size())
    throw_topology_changed();
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
  return {static_cast<long>(unknowns_), static_cast<long>(unknowns_), static_cast<long>(inner_.size())};
}

}  // namespace stiffmsa::detail

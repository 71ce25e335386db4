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

class ValueWriter final : public EquationWriter {
 public:
  ValueWriter(const std::vector<int>& rows, const std::vector<int>& columns,
              const std::vector<int>& slots, double* values)
      : rows_(rows), columns_(columns), slots_(slots), values_(values) {}
  void add(Index row, Index column, double value) override {
    if (next_ >= rows_.size() || rows_[next_] != row || columns_[next_] != column)
      throw_topology_changed();
    values_[slots_[next_++]] += value;
  }
  std::size_t written() const { return next_; }

 private:
  const std::vector<int>& rows_;
  const std::vector<int>& columns_;
  const std::vector<int>& slots_;
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
  rows_ = std::move(recorder.rows);
  columns_ = std::move(recorder.columns);

  // Sort positions by (column, row) and merge duplicates into one slot each.
  std::vector<int> order(rows_.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return columns_[a] != columns_[b] ? columns_[a] < columns_[b] : rows_[a] < rows_[b];
  });
  slots_.assign(rows_.size(), -1);
  outer_.assign(static_cast<std::size_t>(unknowns) + 1, 0);
  for (std::size_t k = 0; k < order.size(); ++k) {
    const int e = order[k];
    const bool repeat = k > 0 && rows_[order[k - 1]] == rows_[e] && columns_[order[k - 1]] == columns_[e];
    if (!repeat) {
      inner_.push_back(rows_[e]);
      ++outer_[static_cast<std::size_t>(columns_[e]) + 1];
    }
    slots_[e] = static_cast<int>(inner_.size()) - 1;
  }
  std::partial_sum(outer_.begin(), outer_.end(), outer_.begin());
}

void Assembler::fill(const Blocks& blocks, SparseMatrix& matrix) const {
  if (matrix.rows() != unknowns_ || matrix.nonZeros() != static_cast<Index>(inner_.size())) {
    matrix = SparseMatrix(unknowns_, unknowns_);
    matrix.resizeNonZeros(static_cast<Index>(inner_.size()));
    std::copy(outer_.begin(), outer_.end(), matrix.outerIndexPtr());
    std::copy(inner_.begin(), inner_.end(), matrix.innerIndexPtr());
  }
  std::fill_n(matrix.valuePtr(), inner_.size(), 0.0);
  ValueWriter writer(rows_, columns_, slots_, matrix.valuePtr());
  if (blocks.size() != first_rows_.size())
    throw_topology_changed();
  for (std::size_t b = 0; b < blocks.size(); ++b) blocks[b]->write_equations(first_rows_[b], writer);
  if (writer.written() != rows_.size())
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

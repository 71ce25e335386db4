#include "elements/element_block.hpp"

#include <algorithm>

#include "stiffmsa/errors.hpp"

namespace stiffmsa::detail {

void ElementBlock::add_external_wrench(Index, int, const Vec6&, VecX&) const {
  throw Error("internal error: an external wrench was routed to a block that holds no link end");
}

void ElementBlock::pass_wrench_to_root(int, TreeState&) const {
  throw Error("internal error: a block that does not pass the tree solve was asked for a wrench");
}
void ElementBlock::pass_deflection_from_root(int, TreeState&) const {
  throw Error(
      "internal error: a block that does not pass the tree solve was asked for a deflection");
}
void ElementBlock::set_root_deflection(TreeState&) const {
  throw Error("internal error: a block that is no support was made the root of a tree solve");
}

namespace {
// Knuth's TwoSum per value: high + low = sign·(high_in + low_in) + step exactly, to the rounding
// of step + sign·low_in. The runs never overlap (a target's rows are never its source's), and
// saying so lets the loop run two values at a time.
void two_sums(Index count, double sign, const double* __restrict high_in,
              const double* __restrict low_in, const double* __restrict step,
              double* __restrict high_out, double* __restrict low_out) {
  for (Index i = 0; i < count; ++i) {
    const double a = sign * high_in[i];
    const double b = step[i] + sign * low_in[i];
    const double sum = a + b;
    const double b_part = sum - a;
    low_out[i] = (a - (sum - b_part)) + (b - b_part);
    high_out[i] = sum;
  }
}

void plain_sums(Index count, double sign, const double* __restrict high_in,
                const double* __restrict step, double* __restrict high_out) {
  for (Index i = 0; i < count; ++i) high_out[i] = sign * high_in[i] + step[i];
}
}  // namespace

void TreeState::set_sum(Index target, Index source, double sign) {
  eigen_assert(target != source);
  // Rows are adjacent: 6 rows of k columns are one run.
  if (compensated)
    two_sums(6 * x.cols(), sign, x.row(source).data(), x_low.row(source).data(), increment.data(),
             x.row(target).data(), x_low.row(target).data());
  else
    plain_sums(6 * x.cols(), sign, x.row(source).data(), increment.data(), x.row(target).data());
}

void TreeState::set_copy(Index target, Index source) {
  x.middleRows<6>(target) = x.middleRows<6>(source);
  if (compensated) x_low.middleRows<6>(target) = x_low.middleRows<6>(source);
}

void TreeState::set_joined_wrench(const std::vector<int>& ends, int toward_root,
                                  bool with_reaction) {
  if (with_reaction)
    increment = cut(0, 6);
  else
    increment.setZero();
  int through = -1;
  for (int end : ends) {
    if (external.any_at(end)) increment += external.at(end);
    if (end == toward_root) continue;
    if (through < 0)
      through = end;
    else if (compensated)
      increment -= wrench(end) + x_low.middleRows<6>(wrench_column(end));
    else
      increment -= wrench(end);
  }
  if (through < 0)  // one end: no running sum to carry
    set_value(wrench_column(toward_root), increment);
  else
    set_sum(wrench_column(toward_root), wrench_column(through), -1.0);
}

EndWrenches::EndWrenches(int end_count, Index columns) { reset(end_count, columns); }

void EndWrenches::reset(int end_count, Index columns, Index state_columns) {
  state_columns_ = std::min(state_columns, columns);
  slot_.assign(static_cast<std::size_t>(end_count), -1);
  used_ = 0;
  zero_.setZero(6, columns);
}

void EndWrenches::add(int end, Index column, const Vec6& wrench) {
  int& slot = slot_[static_cast<std::size_t>(end)];
  if (slot < 0) {
    slot = static_cast<int>(used_++);
    if (used_ > values_.size())
      values_.push_back(zero_);
    else
      values_[used_ - 1].setZero(6, zero_.cols());
  }
  values_[static_cast<std::size_t>(slot)].col(column) += wrench;
}

void EndWrenches::widen_into(Index columns, EndWrenches& wide) const {
  wide.reset(static_cast<int>(slot_.size()), columns, state_columns_);
  wide.slot_ = slot_;
  wide.used_ = used_;
  if (wide.values_.size() < used_) wide.values_.resize(used_);
  for (std::size_t i = 0; i < used_; ++i) {
    wide.values_[i].setZero(6, columns);
    wide.values_[i].leftCols(values_[i].cols()) = values_[i];
  }
}

const MatX& EndWrenches::at(int end) const {
  const int slot = slot_[static_cast<std::size_t>(end)];
  return slot < 0 ? zero_ : values_[static_cast<std::size_t>(slot)];
}

}  // namespace stiffmsa::detail

#include "solver/tree_passes.hpp"

#include <algorithm>

#include "elements/element_kinds.hpp"
#include "solver/tree_solver.hpp"
#include "stiffmsa/errors.hpp"

namespace stiffmsa::detail {

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

namespace {

// ---- links: W_i + Dᵀ·W_j = 0 and D·Δt_i − Δt_j + C·W_j = 0 (elements/link_blocks.hpp) ----

// W_i + Dᵀ·W_j = 0 solved for the end toward the root: W_i = −W_j − [0; d×F_j], or
// W_j = −W_i + [0; d×F_i].
void wrench_to_root(const LinkBlock& link, int toward_root, TreeState& state) {
  const int far = toward_root == link.end_i() ? link.end_j() : link.end_i();
  const double sign = toward_root == link.end_i() ? -1.0 : 1.0;
  RowMajorMatX& increment = state.increment;
  increment.topRows<3>().setZero();
  const Mat3 moment_arm = sign * skew(link.d());
  increment.bottomRows<3>().noalias() = moment_arm.lazyProduct(state.wrench(far).topRows<3>());
  state.set_sum(wrench_column(toward_root), wrench_column(far), -1.0);
}

// D·Δt_i − Δt_j + C·W_j = 0 solved for the end away from the root, with D·Δt = Δt + [−d×Δφ; 0]:
// Δt_j = Δt_i + [−d×Δφ_i; 0] + C·W_j, or Δt_i = Δt_j − C·W_j + [d×Δφ_i; 0], Δφ_i = Δφ_j −
// (C·W_j)_φ.
void deflection_from_root(const LinkBlock& link, int toward_root, TreeState& state) {
  const int end_i = link.end_i(), end_j = link.end_j();
  const Mat3 d_cross = skew(link.d());
  RowMajorMatX& increment = state.increment;
  if (link.compliance())
    increment.noalias() = link.compliance()->lazyProduct(state.wrench(end_j));
  else
    increment.setZero();
  if (toward_root == end_i) {
    increment.topRows<3>().noalias() -=
        d_cross.lazyProduct(state.deflection(end_i).bottomRows<3>());
    state.set_sum(deflection_column(end_j), deflection_column(end_i), 1.0);
  } else {
    increment = -increment;
    increment.topRows<3>().noalias() +=
        d_cross.lazyProduct(state.deflection(end_j).bottomRows<3>());
    increment.topRows<3>().noalias() += d_cross.lazyProduct(increment.bottomRows<3>());
    state.set_sum(deflection_column(end_i), deflection_column(end_j), 1.0);
  }
}

// ---- rigid and passive joints (eqs. 4–8). A passive joint is cut: each end beyond the root's
// takes its free motion q_k (p unknowns) as given, and leaves its Λ_p·W_k rows. ----

// Σ W_k = Σ W_ext,k, all six components: a rigid joint's equilibrium, and a passive joint's
// with its free components' rows (Λ_p·W_k = Λ_p·W_ext,k) left to the cut, but their sum.
void wrench_to_root(const ConstraintJointBlock& joint, int toward_root, TreeState& state) {
  state.set_joined_wrench(joint.ends(), toward_root, false);
}

// Δt_k = Δt_1 where rigid; a passive joint adds each other end's free motion Λ_pᵀ·q_k, its cut
// unknowns (Λ_r·Λ_pᵀ = 0: the rows of Λ_r are the orthogonal complement of Λ_p's).
void deflection_from_root(const ConstraintJointBlock& joint, int toward_root, TreeState& state) {
  const Index p = joint.p();
  Index motion = 0;
  for (int end : joint.ends()) {
    if (end == toward_root) continue;
    if (p == 0) {
      state.set_copy(deflection_column(end), deflection_column(toward_root));
      continue;
    }
    state.increment.noalias() =
        joint.directions()->free().transpose().lazyProduct(state.cut(motion, p));
    state.set_sum(deflection_column(end), deflection_column(toward_root), 1.0);
    motion += p;
  }
}

Index cut_unknowns_of(const ConstraintJointBlock& joint, int) {
  return joint.p() * (static_cast<Index>(joint.ends().size()) - 1);
}

// The free components' rows of the ends beyond the root's: Λ_p·W_k = Λ_p·W_ext,k (+ preload).
void cut_rows_of(const ConstraintJointBlock& joint, int toward_root, std::vector<Index>& rows) {
  const std::vector<int>& ends = joint.ends();
  const Index m = static_cast<Index>(ends.size()), r = joint.r(), p = joint.p();
  for (Index k = 0; k < m; ++k) {
    if (ends[static_cast<std::size_t>(k)] == toward_root) continue;
    for (Index i = 0; i < p; ++i) rows.push_back(r * m + k * p + i);
  }
}

// ---- elastic joints (eqs. 9–11) ----

// W_1 + W_2 = W_ext,1 + W_ext,2 solved for the end toward the root.
void wrench_to_root(const ElasticJointBlock& joint, int toward_root, TreeState& state) {
  const int other = toward_root == joint.end_1() ? joint.end_2() : joint.end_1();
  state.increment = state.external.at(joint.end_1()) + state.external.at(joint.end_2());
  state.set_sum(wrench_column(toward_root), wrench_column(other), -1.0);
}

// The relative deflection δ = Δt_2 − Δt_1 from Λ_r·δ = 0 and G·K·Λ_p·δ = Λ_p·(W_1 − W_ext,1) −
// G·w_0.
void deflection_from_root(const ElasticJointBlock& joint, int toward_root, TreeState& state) {
  const int end_1 = joint.end_1(), end_2 = joint.end_2();
  const SpringCompliance spring =
      spring_compliance(*joint.directions(), joint.spring(), joint.preload());
  // δ is added to end 1's deflection, or taken from end 2's.
  const double sign = toward_root == end_1 ? 1.0 : -1.0;
  const Mat6 compliance = sign * spring.compliance;
  RowMajorMatX& delta = state.increment;
  delta.noalias() = compliance.lazyProduct(state.wrench(end_1));
  if (state.external.any_at(end_1))
    delta.noalias() -= compliance.lazyProduct(state.external.at(end_1));
  for (Index c = 0; c < state.external.state_columns(); ++c)
    delta.col(c) -= sign * spring.preload_motion;
  if (toward_root == end_1)
    state.set_sum(deflection_column(end_2), deflection_column(end_1), 1.0);
  else
    state.set_sum(deflection_column(end_1), deflection_column(end_2), 1.0);
}

// ---- supports (eqs. 12–16). Every support passes. At the root, a passive one is cut: its free
// motion (p unknowns) is taken as given and its Λ_p rows are left. Any other support closes a
// loop through the ground and is cut there: its ends are joined as one and its reaction
// R = Σ(W_k − W_ext,k) (6 unknowns) is taken as given, leaving its last 6 rows, which hold it to
// the ground. ----

// The ends move as one: Δt = 0 when rigid (plus the settlement d in each load case: it has no
// part along the free directions); when elastic, Λ_r·Δt = 0 and
// G·K·Λ_p·Δt = G·w_0 − Λ_p·R, with R = Σ(W_k − W_ext,k) the reaction; when passive, Δt = Λ_pᵀ·q
// with q its cut unknowns.
void root_deflection(const SupportBlock& support, TreeState& state) {
  const FreeDirections& directions = *support.directions();
  MatX deflection = MatX::Zero(6, state.x.cols());
  if (support.passive()) {
    deflection.noalias() =
        directions.free().transpose().lazyProduct(state.cut(0, directions.free().rows()));
  } else if (directions.free().rows() > 0) {
    const SpringCompliance spring =
        spring_compliance(directions, *support.spring(), support.preload());
    MatX reaction = MatX::Zero(6, state.x.cols());
    for (int end : support.ends()) reaction += state.wrench(end) - state.external.at(end);
    deflection.noalias() = (-spring.compliance).lazyProduct(reaction);
    for (Index c = 0; c < state.external.state_columns(); ++c)
      deflection.col(c) += spring.preload_motion;
  }
  if (const std::optional<Vec6> settlement = support.settlement())
    for (Index c = 0; c < state.external.state_columns(); ++c) deflection.col(c) += *settlement;
  for (int end : support.ends()) state.set_value(deflection_column(end), deflection);
}

// Σ W_k = Σ W_ext,k + R, the reaction R being the cut unknowns.
void wrench_to_root(const SupportBlock& support, int toward_root, TreeState& state) {
  state.set_joined_wrench(support.ends(), toward_root, true);
}

void deflection_from_root(const SupportBlock& support, int toward_root, TreeState& state) {
  for (int end : support.ends())
    if (end != toward_root) state.set_copy(deflection_column(end), deflection_column(toward_root));
}

Index cut_unknowns_of(const SupportBlock& support, int toward_root) {
  if (toward_root >= 0) return 6;
  return support.passive() ? support.directions()->free().rows() : 0;
}

// Not the root: its last 6 rows (Λ_r·Δt_1 = 0 and the free directions' balance). A passive
// root: its last p rows (Λ_p·Σ W_k = Λ_p·Σ W_ext,k).
void cut_rows_of(const SupportBlock& support, int toward_root, std::vector<Index>& rows) {
  const Index count = cut_unknowns_of(support, toward_root);
  const Index end_rows = 6 * static_cast<Index>(support.ends().size());
  for (Index i = end_rows - count; i < end_rows; ++i) rows.push_back(i);
}

// ---- free ends: W = W_ext ----

void wrench_to_root(const FreeEndBlock&, int toward_root, TreeState& state) {
  state.set_value(wrench_column(toward_root), state.external.at(toward_root));
}

void deflection_from_root(const FreeEndBlock&, int, TreeState&) {}

// ---- what no pass reaches ----

// A stiffness-only CAD link writes W − K12·Δt = 0, which gives neither end's wrench from the
// other's: it does not pass (passes_tree).
[[noreturn]] void not_passed() {
  throw Error("internal error: a block that does not pass the tree solve was passed");
}
void wrench_to_root(const StiffnessLinkBlock&, int, TreeState&) { not_passed(); }
void deflection_from_root(const StiffnessLinkBlock&, int, TreeState&) { not_passed(); }

// Blocks that are never cut.
template <class Block>
Index cut_unknowns_of(const Block&, int) {
  return 0;
}
template <class Block>
void cut_rows_of(const Block&, int, std::vector<Index>&) {}

// A link block as the passes read it: every link of a tree that passes is a LinkBlock.
const LinkBlock& link_of(const ElementBlock& block) {
  if (block.kind() != BlockKind::link) not_passed();
  return static_cast<const LinkBlock&>(block);
}

}  // namespace

bool passes_tree(const ElementBlock& block) { return block.kind() != BlockKind::stiffness_link; }

Index cut_unknowns(const ElementBlock& block, int toward_root) {
  return visit_block(block,
                     [&](const auto& kind) -> Index { return cut_unknowns_of(kind, toward_root); });
}

void add_cut_rows(const ElementBlock& block, int toward_root, std::vector<Index>& rows) {
  visit_block(block, [&](const auto& kind) { cut_rows_of(kind, toward_root, rows); });
}

void pass_wrench_to_root(const ElementBlock& block, int toward_root, TreeState& state) {
  visit_block(block, [&](const auto& kind) { wrench_to_root(kind, toward_root, state); });
}

void pass_deflection_from_root(const ElementBlock& block, int toward_root, TreeState& state) {
  visit_block(block, [&](const auto& kind) { deflection_from_root(kind, toward_root, state); });
}

void set_root_deflection(const ElementBlock& block, TreeState& state) {
  if (block.kind() != BlockKind::support)
    throw Error("internal error: a block that is no support was made the root of a tree solve");
  root_deflection(static_cast<const SupportBlock&>(block), state);
}

void run_passes(const Blocks& blocks, int link_count, const TreeOrder& order,
                const std::vector<Index>& cut_first, const RowMajorMatX* cut_values,
                const EndWrenches& external, Index unknowns, bool compensated, RowMajorMatX& x,
                RowMajorMatX& x_low, RowMajorMatX& increment) {
  // Not zeroed: the passes set every link end's rows (both parts where compensated).
  x.resize(unknowns, external.columns());
  if (compensated) x_low.resize(unknowns, external.columns());
  TreeState state(x, x_low, external, compensated, increment);
  state.cut_values = cut_values;
  // The group at entry k of the order, its cut unknowns made the current ones.
  auto enter_group = [&](std::size_t k) -> const ElementBlock& {
    state.cut_first = cut_first[k];
    return *blocks[static_cast<std::size_t>(link_count + order.groups[k])];
  };
  auto link_block = [&](int end) -> const LinkBlock& {
    return link_of(*blocks[static_cast<std::size_t>(end / 2)]);
  };
  // Leaves first: a group's other ends got their wrenches from the links beyond them.
  for (std::size_t k = order.groups.size(); k-- > 1;) {
    const int end = order.toward_root[k];
    pass_wrench_to_root(enter_group(k), end, state);
    wrench_to_root(link_block(end), end ^ 1, state);
  }
  set_root_deflection(enter_group(0), state);
  for (std::size_t k = 1; k < order.groups.size(); ++k) {
    const int end = order.toward_root[k];
    deflection_from_root(link_block(end), end ^ 1, state);
    pass_deflection_from_root(enter_group(k), end, state);
  }
  if (compensated) x += x_low;
}

}  // namespace stiffmsa::detail

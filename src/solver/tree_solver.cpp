#include "solver/tree_solver.hpp"

#include <algorithm>

namespace stiffmsa::detail {

std::optional<TreeOrder> tree_order(const Topology& topology) {
  const auto group_count = static_cast<int>(topology.groups.size());
  TreeOrder order;
  for (int g = 0; g < group_count; ++g) {
    if (topology.groups[static_cast<std::size_t>(g)].kind != ConnectionGroup::Kind::support) continue;
    if (order.root >= 0) return std::nullopt;  // two supports close a loop through the ground
    order.root = g;
  }
  if (order.root < 0 || group_count != topology.link_count + 1) return std::nullopt;
  std::vector<char> reached(static_cast<std::size_t>(group_count), 0);
  order.groups.reserve(static_cast<std::size_t>(group_count));
  order.toward_root.reserve(static_cast<std::size_t>(group_count));
  order.groups.push_back(order.root);
  order.toward_root.push_back(-1);
  reached[static_cast<std::size_t>(order.root)] = 1;
  for (std::size_t next = 0; next < order.groups.size(); ++next) {
    const ConnectionGroup& group = topology.groups[static_cast<std::size_t>(order.groups[next])];
    for (int end : group.ends) {
      if (end == order.toward_root[next]) continue;
      const int far_end = end ^ 1;  // the other end of the same link
      const int far_group = topology.group_of_end[static_cast<std::size_t>(far_end)];
      if (reached[static_cast<std::size_t>(far_group)]) return std::nullopt;  // a loop
      reached[static_cast<std::size_t>(far_group)] = 1;
      order.groups.push_back(far_group);
      order.toward_root.push_back(far_end);
    }
  }
  if (order.groups.size() != static_cast<std::size_t>(group_count)) return std::nullopt;  // not connected
  return order;
}

bool passes_tree(const Blocks& blocks) {
  return std::all_of(blocks.begin(), blocks.end(), [](const auto& block) { return block->passes_tree(); });
}

MatX tree_solve(const Blocks& blocks, int link_count, const TreeOrder& order, const EndWrenches& external,
                Index unknowns, Index preload_column) {
  MatX x = MatX::Zero(unknowns, external.columns());
  MatX x_low = MatX::Zero(unknowns, external.columns());
  TreeColumns state(x, x_low, external, preload_column);
  auto group_block = [&](int group) -> const ElementBlock& {
    return *blocks[static_cast<std::size_t>(link_count + group)];
  };
  auto link_block = [&](int end) -> const ElementBlock& { return *blocks[static_cast<std::size_t>(end / 2)]; };
  // Leaves first: a group's other ends got their wrenches from the links beyond them.
  for (std::size_t k = order.groups.size(); k-- > 1;) {
    const int end = order.toward_root[k];
    group_block(order.groups[k]).pass_wrench_to_root(end, state);
    link_block(end).pass_wrench_to_root(end ^ 1, state);
  }
  group_block(order.root).set_root_deflection(state);
  for (std::size_t k = 1; k < order.groups.size(); ++k) {
    const int end = order.toward_root[k];
    link_block(end).pass_deflection_from_root(end ^ 1, state);
    group_block(order.groups[k]).pass_deflection_from_root(end, state);
  }
  x += x_low;
  return x;
}

}  // namespace stiffmsa::detail

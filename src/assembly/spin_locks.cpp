// The rods whose idle spin a solve may hold (topology.hpp, SpinLock).
#include <variant>

#include "assembly/topology.hpp"

namespace stiffmsa::detail {

namespace {

// A passive ball joint between exactly two link ends, or a passive ball support of one: it
// passes no moment at all.
bool is_free_ball(const Model& model, const ConnectionGroup& group) {
  const Connection* c = nullptr;
  if (group.kind == ConnectionGroup::Kind::joint && group.ends.size() == 2)
    c = &model.joints[static_cast<std::size_t>(group.source)].connection;
  else if (group.kind == ConnectionGroup::Kind::support && group.ends.size() == 1)
    c = &model.supports[static_cast<std::size_t>(group.source)].connection;
  return c && c->kinematics.type == JointType::spherical && !c->stiffness && !c->is_actuated &&
         !c->preload;
}

}  // namespace

std::vector<SpinLock> find_spin_locks(const Model& model, const Topology& topology) {
  std::vector<bool> end_acted_on(static_cast<std::size_t>(topology.end_count()), false);
  for (int end : topology.load_ends) end_acted_on[static_cast<std::size_t>(end)] = true;
  for (int end : topology.effector_ends) end_acted_on[static_cast<std::size_t>(end)] = true;
  // A joint already holding a spin, or left free as the far end of a held rod.
  std::vector<bool> taken(topology.groups.size(), false);
  std::vector<SpinLock> locks;
  for (int l = 0; l < topology.link_count; ++l) {
    if (std::holds_alternative<MatrixLink>(model.links[static_cast<std::size_t>(l)].kind)) continue;
    const int from = 2 * l, to = from + 1;
    if (end_acted_on[static_cast<std::size_t>(from)] || end_acted_on[static_cast<std::size_t>(to)])
      continue;
    const int held = topology.group_of_end[static_cast<std::size_t>(from)];
    const int other = topology.group_of_end[static_cast<std::size_t>(to)];
    if (held == other || taken[static_cast<std::size_t>(held)] ||
        taken[static_cast<std::size_t>(other)])
      continue;
    if (!is_free_ball(model, topology.groups[static_cast<std::size_t>(held)]) ||
        !is_free_ball(model, topology.groups[static_cast<std::size_t>(other)]))
      continue;
    taken[static_cast<std::size_t>(held)] = taken[static_cast<std::size_t>(other)] = true;
    const auto position = [&](int end) -> const Vec3& {
      return model
          .points[static_cast<std::size_t>(topology.end_points[static_cast<std::size_t>(end)])]
          .position;
    };
    Eigen::Index least_aligned = 0;
    (position(to) - position(from)).cwiseAbs().minCoeff(&least_aligned);
    locks.push_back({l, held, other, Vec3::Unit(least_aligned)});
  }
  return locks;
}

}  // namespace stiffmsa::detail

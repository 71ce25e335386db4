#include "assembly/topology.hpp"

#include <algorithm>
#include <cstring>
#include <type_traits>
#include <typeinfo>
#include <utility>

#include "elements/beam_element.hpp"
#include "elements/cad_link.hpp"
#include "elements/connection_blocks.hpp"
#include "elements/link_blocks.hpp"
#include "model/link_ends.hpp"

namespace stiffmsa::detail {

namespace {

[[noreturn]] void fail(const Origin& origin, std::string key_path, std::string message) {
  throw InputError(origin.location, std::move(key_path), std::move(message));
}

// The key path of a joint, support or end effector ("joints.A1"), spelt out only on failure.
struct EntityPath {
  const char* collection;
  const std::string& name;
  std::string str() const { return std::string(collection) + "." + name; }
};

std::vector<int> named_ends(const ModelIndex& index, const std::string& point,
                            const std::vector<std::string>& link_names, const Origin& origin,
                            const EntityPath& path) {
  std::vector<int> ends;
  if (link_names.empty()) {
    const auto at_point = index.ends_at(point);
    if (at_point.empty()) fail(origin, path.str(), "no link end is at point '" + point + "'");
    ends.reserve(at_point.size());
    for (const auto& e : at_point) ends.push_back(e.id());
    return ends;
  }
  ends.reserve(link_names.size());
  for (const auto& name : link_names) {
    std::string problem;
    const auto end = index.resolve(point, name, problem);
    if (!end) fail(origin, path.str() + ".links", problem);
    ends.push_back(end->id());
  }
  return ends;
}

template <class KeyPath>
int end_of(const ModelIndex& index, const std::string& point,
           const std::optional<std::string>& link, const Origin& origin, const KeyPath& key_path) {
  std::string problem;
  const auto end = index.resolve(point, link, problem);
  if (!end) fail(origin, key_path(), problem);
  return end->id();
}

}  // namespace

Topology build_topology(const Model& model) { return build_topology(model, ModelIndex(model)); }

Topology build_topology(const Model& model, const ModelIndex& index) {
  Topology t;
  t.link_count = static_cast<int>(model.links.size());
  t.group_of_end.assign(static_cast<std::size_t>(t.end_count()), -1);
  t.end_points.resize(static_cast<std::size_t>(t.end_count()));
  for (int end = 0; end < t.end_count(); ++end) {
    const int point = index.point_of_end(end);
    if (point < 0) {
      const Link& link = model.links[static_cast<std::size_t>(end / 2)];
      fail(link.origin, "links." + link.name,
           "no point named '" + (end % 2 == 0 ? link.from : link.to) + "'");
    }
    t.end_points[static_cast<std::size_t>(end)] = point;
  }

  // Every link end is in one group; the joints and supports, then one per point at most.
  t.groups.reserve(model.joints.size() + model.supports.size() + model.points.size());
  auto claim = [&](ConnectionGroup group, const Origin& origin, const auto& key_path) {
    const int index = static_cast<int>(t.groups.size());
    for (int end : group.ends) {
      int& owner = t.group_of_end[static_cast<std::size_t>(end)];
      if (owner >= 0)
        fail(origin, key_path(),
             "the end of link '" + model.links[static_cast<std::size_t>(end / 2)].name + "' at '" +
                 group.point + "' is already held by another joint or support");
      owner = index;
    }
    t.groups.push_back(std::move(group));
  };

  for (std::size_t j = 0; j < model.joints.size(); ++j) {
    const Joint& joint = model.joints[j];
    const EntityPath path{"joints", joint.name};
    claim({ConnectionGroup::Kind::joint, static_cast<int>(j), joint.at,
           named_ends(index, joint.at, joint.links, joint.origin, path)},
          joint.origin, [&] { return path.str(); });
  }
  for (std::size_t s = 0; s < model.supports.size(); ++s) {
    const Support& support = model.supports[s];
    const EntityPath path{"supports", support.name};
    claim({ConnectionGroup::Kind::support, static_cast<int>(s), support.at,
           named_ends(index, support.at, support.links, support.origin, path)},
          support.origin, [&] { return path.str(); });
  }

  // Link ends named nowhere: rigidly connected at their point, or free when alone there. The
  // points in the order of their first such end.
  std::vector<bool> point_done(model.points.size(), false);
  for (int first = 0; first < t.end_count(); ++first) {
    if (t.group_of_end[static_cast<std::size_t>(first)] >= 0) continue;
    const int point = t.end_points[static_cast<std::size_t>(first)];
    if (point_done[static_cast<std::size_t>(point)]) continue;
    point_done[static_cast<std::size_t>(point)] = true;
    const Point& p = model.points[static_cast<std::size_t>(point)];
    const auto at_point = index.ends_at(point);
    std::vector<int> ends;
    ends.reserve(at_point.size());
    bool some_held = false;
    for (const auto& e : at_point) {
      if (t.group_of_end[static_cast<std::size_t>(e.id())] >= 0)
        some_held = true;
      else
        ends.push_back(e.id());
    }
    if (some_held)
      fail(p.origin, "points." + p.name,
           "some link ends at this point are held by a joint or support and others (link '" +
               model.links[static_cast<std::size_t>(first / 2)].name +
               "') by nothing; name every end at the point in a joint or support");
    const auto kind = ends.size() == 1 ? ConnectionGroup::Kind::free_end
                                       : ConnectionGroup::Kind::rigid_connection;
    claim({kind, -1, p.name, std::move(ends)}, {}, [&] { return "points." + p.name; });
  }

  t.load_ends.reserve(model.loads.size());
  for (std::size_t i = 0; i < model.loads.size(); ++i) {
    const Load& load = model.loads[i];
    t.load_ends.push_back(end_of(index, load.at, load.link, load.origin,
                                 [&] { return "loads[" + std::to_string(i) + "]"; }));
  }
  const auto link_of = [&](const LinkLoad& load, const std::string& key) {
    const int link = index.link(load.link);
    if (link < 0) fail(load.origin, key, "no link named '" + load.link + "'");
    return link;
  };
  t.link_load_links.reserve(model.link_loads.size());
  for (std::size_t i = 0; i < model.link_loads.size(); ++i)
    t.link_load_links.push_back(
        link_of(model.link_loads[i], "loads[link " + std::to_string(i) + "]"));
  for (const LoadCase& c : model.load_cases) {
    std::vector<int>& ends = t.case_load_ends.emplace_back();
    for (std::size_t i = 0; i < c.loads.size(); ++i)
      ends.push_back(end_of(index, c.loads[i].at, c.loads[i].link, c.loads[i].origin, [&] {
        return "load_cases." + c.name + "[" + std::to_string(i) + "]";
      }));
    std::vector<int>& links = t.case_link_load_links.emplace_back();
    for (std::size_t i = 0; i < c.link_loads.size(); ++i)
      links.push_back(link_of(c.link_loads[i], "load_cases." + c.name));
  }
  t.effector_ends.reserve(model.end_effectors.size());
  for (const auto& effector : model.end_effectors)
    t.effector_ends.push_back(end_of(index, effector.at, effector.link, effector.origin,
                                     [&] { return "end_effectors." + effector.name; }));
  return t;
}

namespace {

// The block in `slot` becomes a Block with these numbers: refilled in place where it is one
// already (a workspace's blocks from the pose before, whose buffers it keeps), else made.
template <class Block, class Refill, class... Arguments>
void place(std::unique_ptr<ElementBlock>& slot, const Refill& refill, Arguments&&... arguments) {
  if (slot && typeid(*slot) == typeid(Block))
    refill(static_cast<Block&>(*slot));
  else
    slot = std::make_unique<Block>(std::forward<Arguments>(arguments)...);
}

// Blocks whose members are all of fixed size: refilled by assignment.
template <class Block, class... Arguments>
void place_fixed(std::unique_ptr<ElementBlock>& slot, Arguments&&... arguments) {
  if (slot && typeid(*slot) == typeid(Block))
    static_cast<Block&>(*slot) = Block(std::forward<Arguments>(arguments)...);
  else
    slot = std::make_unique<Block>(std::forward<Arguments>(arguments)...);
}

void place_link_block(const Model& model, const Topology& topology, int link_number,
                      std::unique_ptr<ElementBlock>& slot) {
  const Link& link = model.links[static_cast<std::size_t>(link_number)];
  const int i = 2 * link_number, j = 2 * link_number + 1;
  const Vec3& from =
      model.points[static_cast<std::size_t>(topology.end_points[static_cast<std::size_t>(i)])]
          .position;
  const Vec3& to =
      model.points[static_cast<std::size_t>(topology.end_points[static_cast<std::size_t>(j)])]
          .position;
  const Vec3 d = to - from;
  std::visit(
      [&](const auto& kind) {
        using Kind = std::decay_t<decltype(kind)>;
        if constexpr (std::is_same_v<Kind, RigidLink>) {
          place_fixed<LinkBlock>(slot, i, j, d, std::nullopt);
        } else if constexpr (std::is_same_v<Kind, BeamLink>) {
          place_fixed<LinkBlock>(slot, i, j, d, beam_global_compliance(kind, from, to));
        } else if constexpr (std::is_same_v<Kind, ComplianceLink>) {
          place_fixed<LinkBlock>(slot, i, j, d, compliance_link_global_compliance(kind, from, to));
        } else {
          const Mat12 K = matrix_link_global_stiffness(kind, from, to);
          if (auto compliance = clamped_compliance(K))
            place_fixed<LinkBlock>(slot, i, j, d, *compliance);
          else
            place_fixed<StiffnessLinkBlock>(slot, i, j, K);
        }
      },
      link.kind);
}

const FreeDirections& locked() {
  static const FreeDirections rigid = free_directions(Kinematics::rigid());
  return rigid;
}

// Bit for bit, so that directions kept by a refill are those free_directions would give.
template <class Vector>
bool same_bits(const Vector& a, const Vector& b) {
  return std::memcmp(a.data(), b.data(),
                     sizeof(typename Vector::Scalar) * static_cast<std::size_t>(a.size())) == 0;
}

bool same_kinematics(const Kinematics& a, const Kinematics& b) {
  if (a.type != b.type || !same_bits(a.axis, b.axis) || !same_bits(a.axis_b, b.axis_b) ||
      !same_bits(a.normal, b.normal) || a.free_rows.size() != b.free_rows.size())
    return false;
  for (std::size_t i = 0; i < a.free_rows.size(); ++i)
    if (!same_bits(a.free_rows[i], b.free_rows[i])) return false;
  return true;
}

// free_directions(kinematics), kept from the block in `slot` where it was made from the same
// kinematics: a joint's axes are often the same in every pose.
FreeDirections directions_of(const Kinematics& kinematics,
                             const std::unique_ptr<ElementBlock>& slot) {
  if (slot)
    if (const Kinematics* made = slot->kinematics(); made && same_kinematics(*made, kinematics))
      return *slot->directions();
  return free_directions(kinematics);
}

// `kinematics`: what `directions` were computed from, if anything.
void place_constraint_joint(std::unique_ptr<ElementBlock>& slot, const std::vector<int>& ends,
                            const FreeDirections& directions, const std::optional<VecX>& preload,
                            const Kinematics* kinematics = nullptr) {
  place<ConstraintJointBlock>(
      slot, [&](ConstraintJointBlock& block) { block.refill(directions, preload); }, ends,
      directions, preload);
  static_cast<ConstraintJointBlock&>(*slot).set_kinematics(kinematics);
}

void place_support(std::unique_ptr<ElementBlock>& slot, const std::vector<int>& ends,
                   const FreeDirections& directions, const std::optional<MatX>& stiffness,
                   const std::optional<VecX>& preload, const Kinematics* kinematics = nullptr,
                   const std::optional<Vec6>& settlement = std::nullopt) {
  place<SupportBlock>(
      slot, [&](SupportBlock& block) { block.refill(directions, stiffness, preload, settlement); },
      ends, directions, stiffness, preload, settlement);
  static_cast<SupportBlock&>(*slot).set_kinematics(kinematics);
}

void place_connection_block(const Model& model, const ConnectionGroup& g,
                            std::unique_ptr<ElementBlock>& slot) {
  switch (g.kind) {
    case ConnectionGroup::Kind::free_end: place_fixed<FreeEndBlock>(slot, g.ends.front()); return;
    case ConnectionGroup::Kind::rigid_connection:
      place_constraint_joint(slot, g.ends, locked(), std::nullopt);
      return;
    case ConnectionGroup::Kind::joint: {
      const Connection& c = model.joints[static_cast<std::size_t>(g.source)].connection;
      if (c.stiffness) {
        if (g.ends.size() != 2)
          throw InputError(model.joints[static_cast<std::size_t>(g.source)].origin.location,
                           "joints." + model.joints[static_cast<std::size_t>(g.source)].name,
                           "an elastic joint connects exactly two link ends");
        const FreeDirections directions = directions_of(c.kinematics, slot);
        place<ElasticJointBlock>(
            slot,
            [&](ElasticJointBlock& block) { block.refill(directions, *c.stiffness, c.preload); },
            g.ends[0], g.ends[1], directions, *c.stiffness, c.preload);
        static_cast<ElasticJointBlock&>(*slot).set_kinematics(&c.kinematics);
        return;
      }
      if (c.is_actuated)
        place_constraint_joint(slot, g.ends, locked(), std::nullopt);
      else
        place_constraint_joint(slot, g.ends, directions_of(c.kinematics, slot), c.preload,
                               &c.kinematics);
      return;
    }
    case ConnectionGroup::Kind::support: {
      const Support& support = model.supports[static_cast<std::size_t>(g.source)];
      const Connection& c = support.connection;
      if (c.is_actuated && !c.stiffness)
        place_support(slot, g.ends, locked(), std::nullopt, std::nullopt, nullptr,
                      support.displacement);
      else
        place_support(slot, g.ends, directions_of(c.kinematics, slot), c.stiffness, c.preload,
                      &c.kinematics, support.displacement);
      return;
    }
  }
}

// A rod's ball joint (or support) that holds its spin (SpinLock): the rotations across the rod's
// axis in this pose are its free directions.
void place_spin_holding_block(const Model& model, const Topology& topology, const SpinLock& lock,
                              std::unique_ptr<ElementBlock>& slot) {
  const int from = 2 * lock.rod;
  const auto position = [&](int end) -> const Vec3& {
    return model
        .points[static_cast<std::size_t>(topology.end_points[static_cast<std::size_t>(end)])]
        .position;
  };
  const FreeDirections directions =
      rotations_across(position(from + 1) - position(from), lock.across);
  const ConnectionGroup& group = topology.groups[static_cast<std::size_t>(lock.group)];
  if (group.kind == ConnectionGroup::Kind::support)
    place_support(slot, group.ends, directions, std::nullopt, std::nullopt, nullptr,
                  model.supports[static_cast<std::size_t>(group.source)].displacement);
  else
    place_constraint_joint(slot, group.ends, directions, std::nullopt);
}

}  // namespace

std::vector<std::unique_ptr<ElementBlock>> make_blocks(const Model& model, const Topology& topology,
                                                       const std::vector<SpinLock>& locks) {
  std::vector<std::unique_ptr<ElementBlock>> blocks;
  refill_blocks(model, topology, locks, blocks);
  return blocks;
}

void refill_blocks(const Model& model, const Topology& topology, const std::vector<SpinLock>& locks,
                   std::vector<std::unique_ptr<ElementBlock>>& blocks) {
  blocks.resize(static_cast<std::size_t>(topology.link_count) + topology.groups.size());
  for (int l = 0; l < topology.link_count; ++l)
    place_link_block(model, topology, l, blocks[static_cast<std::size_t>(l)]);
  for (std::size_t g = 0; g < topology.groups.size(); ++g) {
    const auto lock = std::find_if(locks.begin(), locks.end(), [&](const SpinLock& s) {
      return s.group == static_cast<int>(g);
    });
    auto& slot = blocks[static_cast<std::size_t>(topology.link_count) + g];
    if (lock == locks.end())
      place_connection_block(model, topology.groups[g], slot);
    else
      place_spin_holding_block(model, topology, *lock, slot);
  }
}

}  // namespace stiffmsa::detail

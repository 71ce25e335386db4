#include "assembly/topology.hpp"

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

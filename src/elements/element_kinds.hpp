#pragma once
// The element kinds as a closed set: visit_block calls `visitor` with the block as its own kind,
// so that a solve above the elements (solver/tree_passes.hpp, solver/frame_solver.hpp) reads the
// numbers it needs from each kind — a link's compliance and transport, a joint's free directions
// and spring, a support's directions — and keeps its own steps to itself.
#include "elements/connection_blocks.hpp"
#include "elements/link_blocks.hpp"
#include "stiffmsa/errors.hpp"

namespace stiffmsa::detail {

// `visitor` takes each kind's block (an overload per kind, or a generic lambda); its results
// have one type.
template <class Visitor>
decltype(auto) visit_block(const ElementBlock& block, Visitor&& visitor) {
  switch (block.kind()) {
    case BlockKind::link: return visitor(static_cast<const LinkBlock&>(block));
    case BlockKind::stiffness_link: return visitor(static_cast<const StiffnessLinkBlock&>(block));
    case BlockKind::constraint_joint:
      return visitor(static_cast<const ConstraintJointBlock&>(block));
    case BlockKind::elastic_joint: return visitor(static_cast<const ElasticJointBlock&>(block));
    case BlockKind::support: return visitor(static_cast<const SupportBlock&>(block));
    case BlockKind::free_end: return visitor(static_cast<const FreeEndBlock&>(block));
  }
  throw Error("internal error: an element block of no known kind");
}

}  // namespace stiffmsa::detail

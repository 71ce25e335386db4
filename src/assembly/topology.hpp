#pragma once
// The element blocks of a model's topology (model/topology.hpp), and the spin locks that hold a
// rod's idle spin in one of its ball joints.
#include <memory>
#include <vector>

#include "elements/element_block.hpp"
#include "model/topology.hpp"

namespace stiffmsa::detail {

// A rod with passive ball joints at both ends (the rods of a Delta robot's parallelograms)
// spins freely about the line through its two ball centres: an idle motion, which moves no other
// link and whose moment nothing can carry. Holding that one direction in the ball joint at one
// end (as a universal joint whose missing direction is the rod's axis) leaves every other
// unknown as it was: the rod's balance of moments about its own axis makes the held direction's
// moment zero, as long as the ball joint at the rod's other end is not held too and nothing is
// applied at the rod's ends. The spin locks of a model are fixed by its topology; the axis is
// each pose's.
struct SpinLock {
  int rod = -1;          // the link
  int group = -1;        // the connection group of its ball joint (or support) that holds the spin
  int other_group = -1;  // the ball joint (or support) at its other end, left free
  // The global axis least aligned with the rod in the model the locks were found for: the held
  // joint's free directions are taken from its part across the rod in every pose
  // (rotations_across), so that they turn with the rod instead of jumping between poses.
  Vec3 across = Vec3::UnitX();
};

// The rods whose spin can be held so: a beam, rigid or compliance link (a matrix link's block
// depends on its values) both of whose ends are in passive, unpreloaded spherical joints of two
// link ends each or spherical supports of one, with no load or end effector at either end; each
// joint or support takes part in at most one rod's lock. Empty for most models.
std::vector<SpinLock> find_spin_locks(const Model& model, const Topology& topology);

// The element blocks of a model in assembly order: one per link, then one per connection group;
// the ball joints that `locks` name hold their rod's spin.
std::vector<std::unique_ptr<ElementBlock>> make_blocks(const Model& model, const Topology& topology,
                                                       const std::vector<SpinLock>& locks = {});
// The same blocks written into `blocks`: those already of the right kind (another pose's of
// this topology) are refilled with the model's numbers and keep their buffers, so that a pose
// allocates no block; the others are made.
void refill_blocks(const Model& model, const Topology& topology, const std::vector<SpinLock>& locks,
                   std::vector<std::unique_ptr<ElementBlock>>& blocks);

}  // namespace stiffmsa::detail

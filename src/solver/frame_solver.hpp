#pragma once
// The frame solve: where every link is flexible and every connection welds its link ends
// rigidly (default connections, rigid joints, locked actuators, rigid supports, free ends) —
// a frame or a truss of beams, the structures frame programs take — the mixed system condenses
// to the displacement method: one 6-vector of deflections per connection that is not a
// support, K·u = F with K = Σ K12 of the links (paper eq. 1) symmetric positive definite, and a
// sparse Cholesky factorisation (CHOLMOD's supernodal one; Eigen's simplicial LDLᵀ where
// stiffmsa is built without SuiteSparse) of 6 unknowns per connection instead of an LU of 24
// per link. The link ends' wrenches follow link by link, [W_i; W_j] = K12·[Δt_i; Δt_j], and
// the whole solution is checked against every block's equations like the tree solve's
// (check_block_by_block).
//
// Condensing squares what the mixed system keeps apart: K's condition grows as the links get
// shorter and more numerous (a 10 000-link chain's loses every digit, as bench/README.md
// records), and a backward-stable Cholesky leaves a small residual however many digits it
// lost, so the check alone cannot see it. The solve therefore estimates K's condition (Hager's
// estimate on the factors, K scaled to a unit diagonal so that units do not count) and declines
// below kFrameLeastRcond; the factorising solve then decides. Trees are solved on the tree before
// this is tried.
#include <optional>
#include <vector>

#include "assembly/topology.hpp"
#include "solver/tree_solver.hpp"
#include "tolerances.hpp"

namespace stiffmsa::detail {

// A link block's stiffness K12 (paper eq. 1), [W_i; W_j] = K12·[Δt_i; Δt_j] in the global frame:
// free_free_stiffness(C, d) of a flexible link, a CAD stiffness link's matrix; nullopt for a
// rigid link and for connection blocks.
std::optional<Mat12> end_stiffness(const ElementBlock& link);

// Which link ends share a deflection: the value-independent part of a frame solve.
struct FramePlan {
  std::vector<int>
      node_of_end;  // per link end: its connection's node, −1 where a rigid support holds it
  int nodes = 0;    // connections that are not supports, 6 unknowns each
  // K's pattern, compressed by columns (both triangles, rows sorted): a dense 6×6 block for every
  // pair of nodes that a link joins, and for every node with itself.
  std::vector<int> column_starts;  // 6·nodes + 1
  std::vector<int> rows;
  // Per link and part (a, b) of its K12 (4·l + 2·a + b), where that 6×6 part goes in K's values:
  // entry (i, j) at first + j·stride + i; first −1 where an end has no node.
  struct Part {
    int first = -1;
    int stride = 0;
  };
  std::vector<Part> parts;
};

// The plan where the model is a frame as above with at least one rigid support and one node;
// nullopt else.
std::optional<FramePlan> frame_plan(const Topology& topology, const Blocks& blocks);

struct FrameSolution {
  double reciprocal_condition = 0;  // of K, scaled by its diagonal (Hager's estimate)
};

// Solves into x (unknowns × external.columns(), the mixed system's layout) the deflections
// and wrenches under the external wrenches of each column (a frame holds no preload; a rigid
// support's settlement moves its ends in the first external.state_columns() columns). Nullopt,
// with x unspecified, where the blocks are not those of a frame (a pose of other blocks than
// the plan's), K is not positive definite or its reciprocal condition estimate is below
// `least_rcond`.
std::optional<FrameSolution> frame_solve(const Blocks& blocks, const Topology& topology,
                                         const FramePlan& plan, const EndWrenches& external,
                                         RowMajorMatX& x, double least_rcond = kFrameLeastRcond);

}  // namespace stiffmsa::detail

#pragma once
// Which sparse factorisation a solve uses: its own header, so that the solver layer (below the
// analyses) names it without including the analyses' header. stiffmsa/analysis.hpp includes it.
#include <optional>
#include <string>

namespace stiffmsa {

// `automatic` solves a model whose links and connections form a tree on its one support (serial
// robots, chains) without factorising (docs/theory.md §7.1), and one that is a tree with several
// supports or passive joints (parallel robots whose legs meet at the platform) through a small
// dense system for its cut reactions and free motions (§7.2), where that system is regular and
// at most 32 unknowns; a frame (every link flexible, every connection a weld: a building, a
// truss with welded joints) by the condensed displacement system of frame programs, where its
// stiffness keeps about 10 digits (§7.3); others it factorises with KLU, or with Eigen's SparseLU
// where KLU's ordering predicts heavy fill. The others force that factorisation. The result's
// report names what was used.
enum class SolverKind { automatic, sparse_lu, umfpack, klu };
const char* to_string(SolverKind s);
std::optional<SolverKind> solver_kind_from_string(const std::string& s);
bool solver_available(SolverKind s);

}  // namespace stiffmsa

#pragma once
// The critical load factor of a load case in the linear mode (docs/theory.md §14): the smallest
// positive λ for which the structure under λ times the case's loads and preloads, linearised at
// the unloaded geometry, has a non-trivial deflection with no further load,
// (K + λ·K_G)·Δt = 0, K_G the geometric stiffness of the beams under their axial forces and the
// load-dependent stiffness of links carried as levers and of joints, all at the linear solution
// of the case (λ = 1).
#include <string>
#include <vector>

#include "analysis/case_loads.hpp"
#include "assembly/topology.hpp"
#include "solver/tree_solver.hpp"
#include "stiffmsa/analysis.hpp"
#include "stiffmsa/result.hpp"

namespace stiffmsa::detail {

// The sum of the model's loads (Model::loads) at each link end.
std::vector<Vec6> loads_at_ends(const Model& model, const Topology& topology);

// The critical load of the load case whose linear results `result` holds (its link ends'
// wrenches), with `end_loads` that case's loads at each link end (loads_at_ends for the
// model's own), from which the joints' reactions follow. No factor where none is positive (a
// tension, no load at all). Where it cannot be found (the unloaded system is singular, a wrench
// of the linear solution is undetermined), no factor either, and `notes` gets the reason.
// `locks`: the spin locks the solve held (Topology's find_spin_locks).
// `method`: how the condensed eigenproblem is solved (theory.md §14.3): reduced to where K_L
// lives and all its eigenvalues found densely where that leaves at most 6·kMostDenseNodes load
// directions, else Arnoldi's iteration on every node's unknowns; the tests ask for either.
enum class EigenMethod { automatic, dense, iterative };
// What the linear solve of the same model lends, so that the critical load repeats none of its
// work: its blocks (make_blocks of the model, `locks` held), the tree order of its topology, and
// a tree solve's buffers kept from one pose to the next, its cut system. Each may be null: it is
// then made here. The factor and its mode are the same either way.
struct CriticalLoadReuse {
  const Blocks* blocks = nullptr;
  const TreeOrder* tree = nullptr;
  TreeScratch* scratch = nullptr;
  // The linear solve's tree scratch where its tree solve cut and solved the cut system on these
  // very blocks (solver "tree_with_cuts"): its factorised cut system serves the critical load's
  // columns (tree_solve_with_cut_system_of).
  const TreeScratch* cut_system = nullptr;
};
CriticalLoad critical_load(const Model& model, const Topology& topology,
                           const std::vector<SpinLock>& locks, const SolveOptions& options,
                           const Result& result, const std::vector<Vec6>& end_loads,
                           std::vector<std::string>& notes,
                           EigenMethod method = EigenMethod::automatic,
                           const CriticalLoadReuse& reuse = {});

// Result::critical_load of `result` and of each of its load cases (Result::load_cases, those
// of Model::load_cases in order): each case's factor from its own loads (case_loads.hpp; the
// joints' reactions from the loads applied at link ends). The top level's is the unnamed case's
// where the model has one (any load, load along a link or gravity) or no named case, else a copy
// of the first case's, as the top-level results are.
// `cases`: case_loads(model, topology), as the solve computed them.
void add_critical_loads(const Model& model, const Topology& topology,
                        const std::vector<SpinLock>& locks, const SolveOptions& options,
                        const std::vector<CaseLoads>& cases, Result& result,
                        const CriticalLoadReuse& reuse = {});

// Every eigenvalue of the small dense square matrix `a` (the critical load's reduced
// eigenproblem, docs/theory.md §14.3), in no particular order: Householder reflections to
// Hessenberg form, then Francis's double-shift QR iteration on the part not yet split off only
// (no Schur vectors, nothing above the window). Where it does not converge, Eigen's EigenSolver.
// None (an empty vector) for a matrix with a non-finite entry or where Eigen's iteration fails too.
struct Eigenvalues {
  Eigen::VectorXcd values;
  // The QR iteration did not converge within kMostQrSweepsPerEigenvalue sweeps per eigenvalue:
  // the values are Eigen's EigenSolver's (or none). The tests read it.
  bool by_eigen_solver = false;
};
Eigenvalues eigenvalues_of(MatX a);

// Makes the solves on `workspace` find no critical load factor, asked for or not: a sweep's
// (sweep.hpp), whose PoseResult keeps none, so that the poses of a model whose results have the
// factor unasked (always_finds_critical_load: the loaded mode, issue 22's loads) do not compute
// one to throw it away.
void skip_critical_loads(Workspace& workspace);

}  // namespace stiffmsa::detail

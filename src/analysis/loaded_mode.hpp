#pragma once
// The loaded mode (docs/theory.md §15): a load case's equilibrium in the deformed geometry,
// reached in load steps of Newton iterations on the loaded blocks (elements/loaded_blocks.hpp),
// and the tangent compliance and stiffness of every end effector there.
#include <memory>
#include <optional>

#include "analysis/case_loads.hpp"
#include "assembly/topology.hpp"
#include "elements/loaded_blocks.hpp"
#include "solver/block_lu.hpp"
#include "solver/sparse_solver.hpp"
#include "stiffmsa/analysis.hpp"
#include "stiffmsa/result.hpp"

namespace stiffmsa::detail {

// The Newton tangent of the loaded mode, which a workspace keeps from one pose to the next
// (docs/theory.md §15.7, §15.10): the layout of its blocks, their tangents, and the
// factorisations of the last tangent.
// - With the automatic solver, a block LU (solver/block_lu.hpp) whose elimination order is
//   kept per layout; every Newton tangent is equilibrated and pivoted afresh, so a case's
//   results depend on its pose alone. The unloaded tangent, whose determinant's sign alone is
//   used, takes the last unloaded tangent's scaling (afresh where that does not factorise).
//   Where a fresh scaling meets a tiny pivot, the tangent goes to the sparse path.
// - The sparse path (a solver the options name, or the block LU's fallback: KLU where built
//   in): the Newton tangents of a load case: the first after `begin` is the reference,
//   equilibrated from scratch and pivoted afresh; later ones take its scaling as it is and keep
//   its pivot order where that stays stable (KluLU in sparse_solver.cpp). The unloaded tangent,
//   whose determinant's sign alone is used (the critical-point check), starts its equilibration
//   from the last unloaded tangent's scaling and keeps the pivot order of the last one factorised
//   afresh (a sign does not depend on the pivots).
class LoadedTangent {
 public:
  explicit LoadedTangent(SolverKind kind) : kind_(kind) {}
  SolverKind kind() const { return kind_; }

  // Takes `blocks` (kept by reference until the next begin) over `unknowns` unknowns (12 per
  // link end): the elimination order, or the sparse pattern, is made again only where the
  // blocks' rows and ends differ from the last ones'. The next Newton tangent is the reference.
  void begin(const std::vector<std::unique_ptr<LoadedBlock>>& blocks, Index unknowns);
  // Lets go of the blocks taken by `begin` (the layout, the analyses and the references stay).
  void end() { blocks_ = nullptr; }

  // The residual at `in` (and, with `factorise`, the tangent there, factorised). False where
  // the tangent is singular (a zero pivot).
  bool evaluate(const LoadedInputs& in, VecX& residual, bool factorise);

  // The sign of the determinant of the tangent at `in` (the unloaded pose under no load); 0
  // where it is singular (a zero pivot).
  double unloaded_determinant_sign(const LoadedInputs& in);

  // Solves the last factorised Newton tangent for the columns of b, in place.
  void solve(MatX& b) const;
  // The same, refined (at most `refinement_steps` times) against the tangent as evaluated until
  // every column's normwise backward error is at rounding level; `relative_residual` gets the
  // largest, ‖b − J·x‖∞ / (‖J‖∞·‖x‖∞ + ‖b‖∞).
  MatX solve_checked(const MatX& b, int refinement_steps, double& relative_residual) const;

  // The sign of the determinant of the last Newton tangent factorised by `evaluate` (an
  // `evaluate` without factorising leaves it as it was). Throws UsageError where none has been
  // since `begin` or the unloaded tangent's, or the last one asked failed.
  double determinant_sign() const;
  Index first_row(std::size_t block) const { return first_row_[block]; }
  // The factorisation of the last Newton tangent: "block_lu", or the sparse solver's name.
  const char* solver_name() const;

 private:
  bool uses_block_lu() const {
    return kind_ == SolverKind::automatic && n_ <= Index{kBlockColumns} * kBlockLuMostGroups;
  }
  // The sparse pattern of the layout, where not yet recorded (the sparse path is taken).
  void record_pattern();
  // The blocks' tangents at `in` into tangents_, their residuals into `residual`.
  void assemble(const LoadedInputs& in, VecX& residual, bool with_tangent);
  // tangents_ into matrix_.
  void scatter();
  // scaled_ = S_r·matrix_·S_c.
  void scale(const Equilibration& scaling);
  // ‖J‖∞ of the tangent as evaluated.
  double norm_inf() const;
  // b − J·x, per column, and the backward errors' largest (`a_norm`: ‖J‖∞).
  double backward_error(const MatX& b, const MatX& x, double a_norm, MatX& residual) const;

  SolverKind kind_;
  const std::vector<std::unique_ptr<LoadedBlock>>* blocks_ = nullptr;
  Index n_ = 0;
  // Per block: its rows, its number of ends and the ends; the analyses are made for these.
  std::vector<int> layout_;
  std::vector<Index> first_row_;
  std::vector<MatX> tangents_;  // per block, as LoadedBlock::evaluate writes it
  BlockLU block_lu_;
  bool newton_by_block_lu_ = false;  // whether the last Newton tangent was factorised by it
  // Whether the last evaluate that was asked to factorise its tangent did (by either path):
  // what determinant_sign reads.
  bool newton_factorised_ = false;
  // The block LU's scaling of the last unloaded tangent scaled afresh, which the next
  // unloaded tangents take (kept per layout).
  BlockScaling unloaded_block_scaling_;
  bool unloaded_reference_ = false;
  // The sparse path. Where each entry of every block's tangent (in the order of the blocks,
  // each column-major) goes in the compressed matrix's values; empty until the path is taken.
  std::vector<int> positions_;
  SparseMatrix matrix_, scaled_;
  std::optional<Equilibration> scaling_;  // the Newton tangents', from their reference
  std::unique_ptr<LinearSolver> solver_;
  std::optional<Equilibration> unloaded_scaling_;
  std::unique_ptr<LinearSolver> unloaded_solver_;
};

// The loaded blocks of `model`: its links' (in their order), then its connection groups'
// (topology.groups' order); `along`: per link, its loads along the link.
std::vector<std::unique_ptr<LoadedBlock>> make_loaded_blocks(
    const Model& model, const Topology& topology,
    const std::vector<std::vector<LoadAlongLink>>& along);

// The external wrench at every link end (global axes, moment about the end) of the model's own
// `loads`: the unnamed load case's end loads.
std::vector<Vec6> end_loads(const Model& model, const Topology& topology);

// The loaded results of a load case from `linear`, the linear result of the same case, which
// the loaded result keeps as Result::linear and whose layout, notes and names it takes.
// `loads`: the case's wrench applied at every link end (end_loads for the unnamed case; no
// equivalent end loads), `link_loads` its loads along links and self-weight, dead, whose clamp
// wrenches follow each link's geometry (§15.9); preloads and support settlements come from the
// model. The path starts from λ·`linear`'s state, the linear solution of the step's loads, in
// place of the unloaded pose. `load_steps`: the number of equal steps to start from (each is cut
// in halves where Newton's iterations do not converge). Throws NoEquilibriumError where no
// equilibrium is found or the path passes a critical point. `tangent`: the workspace's (its
// solver kind options.solver's).
Result loaded_result(const Model& model, const Topology& topology, const SolveOptions& options,
                     const Result& linear, const std::vector<Vec6>& loads, int load_steps,
                     LoadedTangent& tangent, const std::vector<ResolvedLinkLoad>& link_loads = {});

// The number of load steps the loaded mode starts from where neither the model nor the caller
// gives one: one step, cut where Newton's iterations do not converge.
inline constexpr int kDefaultLoadSteps = 1;

}  // namespace stiffmsa::detail

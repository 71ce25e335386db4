#pragma once
// Analyses are free functions of a model and a reusable Workspace. The workspace keeps what
// depends only on topology (index maps, sparsity pattern, symbolic factorisation), so a model
// whose numbers change but whose topology does not is solved without re-analysis.
#include <memory>
#include <span>
#include <string>

#include "stiffmsa/model.hpp"
#include "stiffmsa/result.hpp"
#include "stiffmsa/solver_kind.hpp"
#include "stiffmsa/structure.hpp"

namespace stiffmsa {

namespace detail {
struct WorkspaceAccess;  // src/analysis/workspace_access.hpp
class ModelIndex;        // src/model/link_ends.hpp
}  // namespace detail

// A tree solve (solver "tree" or "tree_with_cuts") factorises no sparse system: singular_rcond,
// refinement_steps and the condition warning of warn_condition apply only to factorised
// systems (a cut system whose condition exceeds warn_condition is left to them, but a
// well-conditioned cut system says nothing of the whole system's condition); its solution is
// checked against max_relative_residual, and the end effectors' stiffness spread against
// warn_condition, like any other. A frame solve (solver "frame") factorises the condensed
// stiffness, not the mixed system: it is declined below a fixed reciprocal condition of 1e-6
// (singular_rcond and refinement_steps do not apply), and warn_condition is compared with that
// stiffness's condition.
struct SolveOptions {
  SolverKind solver = SolverKind::automatic;
  // Below this reciprocal condition estimate of the equilibrated system, it is singular.
  double singular_rcond = 1e-14;
  // A solve whose relative residual stays above this after refinement is reported as failed.
  double max_relative_residual = 1e-10;
  // At most this many iterative refinement steps, with the same factorisation. Refinement runs
  // (on every right-hand side) only where some column's backward error times the condition
  // estimate exceeds 1e-14, a heuristic sign that digits were lost (docs/theory.md §7).
  int refinement_steps = 2;
  // Solve despite idle free motions (see ModelOptions); either this or the model's own
  // option turns it on.
  bool accept_idle_motions = false;
  // Above this condition estimate (1/reciprocal condition) a solve gets a warning.
  double warn_condition = 1e12;
  // Also report every end effector's stiffness along this direction (global axes; any
  // length): EndEffectorResult::along_direction.
  std::optional<Vec3> direction;
  // The analysis mode; unset: the model's own (ModelOptions::mode).
  std::optional<AnalysisMode> mode;
  // Whether to find every load case's critical load factor (Result::critical_load):
  // - unset (the default): where the result file's contract has it — a model with load cases,
  //   loads along links, gravity or settlements, and the loaded mode —, else not;
  // - true: always;
  // - false: never, also where the contract has it: a caller that does not read the factor
  //   saves its cost (about a third of a loaded 6-axis pose, bench/README.md); every other
  //   number of the result is the same, and a result file written from it has no
  //   critical_load_factor.
  // Read it as `options.critical_load == true` for "asked for"; a bare `if
  // (options.critical_load)` only says whether it is set.
  std::optional<bool> critical_load;

  // Throws UsageError with a sentence when an option is out of range.
  void validate() const;
};

class Workspace {
 public:
  // Builds the topology of a validated model: unknown and equation numbering and element
  // blocks; the sparsity pattern follows when a factorising solve first needs it (a tree solve
  // needs none). Throws InputError on an invalid model.
  explicit Workspace(const Model& model);
  // The workspace of a structure's poses (solve(Workspace&, values)): the topology is the
  // structure's, its blocks those of the structure's default values.
  explicit Workspace(const Structure& structure);
  ~Workspace();
  Workspace(Workspace&&) noexcept;
  Workspace& operator=(Workspace&&) noexcept;

  SystemSize size() const;

  struct Impl;  // the analysis's own (src/analysis), opaque to callers

 private:
  friend struct detail::WorkspaceAccess;
  // The same with the model's name index, which a one-shot solve keeps for its results.
  Workspace(const Model& model, const detail::ModelIndex& index);
  std::unique_ptr<Impl> impl_;
};

// Validates, assembles and reports the system size without solving.
SystemSize check(const Model& model);

// Deflections, wrenches, compliance and stiffness of every end effector (model-format.md).
// Throws InputError for invalid models and SingularModelError for mechanisms.
Result solve(const Model& model, const SolveOptions& options = {});

// The same with a workspace built for a model of identical topology: only numbers are
// refilled and the factorisation is redone numerically.
Result solve(Workspace& workspace, const Model& model, const SolveOptions& options = {});

// The solve of one pose of a structure: the workspace's structure (Workspace(const Structure&))
// with these values, one per value slot. Only the values are checked (InputError names the
// slot's key and the structure's source location); nothing of the structure is redone.
Result solve(Workspace& workspace, std::span<const double> values,
             const SolveOptions& options = {});
// The same, saying which structure the values are of: UsageError when the workspace was not
// built for it.
Result solve(const Structure& structure, Workspace& workspace, std::span<const double> values,
             const SolveOptions& options = {});

// Stiffness against a pure force (translational) and a pure moment (rotational): eigenvalues,
// ascending, of the inverses of the 3×3 diagonal blocks of a compliance matrix. An entry is
// +inf where that block is singular (a rigidly held direction). The directions are the
// blocks' unit eigenvectors in global axes, column i that of value i, each signed so that its
// largest component is positive (docs/theory.md, "Principal and directional stiffness").
struct PrincipalStiffness {
  Vec3 translational;
  Vec3 rotational;
  Mat3 translational_directions = Mat3::Identity();
  Mat3 rotational_directions = Mat3::Identity();

  // Largest over smallest translational stiffness: how unevenly the end effector resists a
  // force across directions (1: alike in all; +inf where a direction is held rigidly).
  double translational_condition() const { return translational(2) / translational(0); }
};
PrincipalStiffness principal_stiffness(const Mat6& compliance);

// The principal axes of a 3×3 block of a compliance matrix (the translational one draws the
// compliance ellipsoid): compliances ascending, their unit directions as columns, and the
// stiffness along each (+inf where principal_stiffness gives +inf).
struct PrincipalAxes {
  Vec3 compliance;
  Mat3 directions;
  Vec3 stiffness;
};
PrincipalAxes principal_axes(const Mat3& compliance_block);
// Stiffness along a direction (DirectionalStiffness; normalised here). Throws UsageError for a
// zero or non-finite direction.
DirectionalStiffness directional_stiffness(const Mat6& compliance, const Vec3& direction);

}  // namespace stiffmsa

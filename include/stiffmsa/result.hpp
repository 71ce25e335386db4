#pragma once
// What an analysis returns. Everything is keyed by the user's names, in model order. A value
// that the model does not determine (free motion, indeterminate internal wrench) is nullopt.
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "stiffmsa/model.hpp"

namespace stiffmsa {

struct LinkEndResult {
  std::optional<Vec6> deflection;  // Δt = [Δp; Δφ]
  std::optional<Vec6> wrench;      // W applied to the link at this end
};

// Internal forces of a flexible link at a station: the wrench [N, Vy, Vz, T, My, Mz] in the
// link's local axes that the part beyond the station exerts on the part before it (N > 0 is
// tension; docs/theory.md §12).
struct InternalForces {
  double position = 0;  // a fraction of the length from the `from` end
  Vec6 forces = Vec6::Zero();
};

struct LinkResult {
  std::string name;
  LinkEndResult from, to;
  // Beams: at evenly spaced stations from end to end (and at point loads); empty otherwise.
  std::vector<InternalForces> internal_forces;
};

struct JointResult {
  std::string name;
  // q per end after the first, against the first (one entry for a two-end joint).
  std::optional<std::vector<VecX>> relative_deflection;
  std::optional<Vec6> wrench;  // applied by the joint to the first link end listed
  std::optional<VecX> effort;  // actuated joints: generalised force along the free directions
  // Whether the joint is actuated, so that a result file can tell an undetermined effort
  // (null) from a joint that has none (no "effort" key).
  bool actuated = false;
};

struct SupportResult {
  std::string name;
  std::optional<Vec6> reaction;  // applied by the ground to the link end (or group)
};

// Where an end effector is held rigidly in some directions (its stiffness is unbounded, null),
// the stiffness on the directions it can move in (model-format.md, theory.md §8.1): T's rows are
// orthonormal motions [Δp; Δφ] spanning the range of the compliance C (unit coordinate axes
// where the held directions are coordinate axes, as in a planar robot), and K_r = (T·C·Tᵀ)⁻¹:
// the wrench components T·W per unit motion q, for the motion Δt = Tᵀ·q.
struct ReducedStiffness {
  MatX directions;  // r×6, r < 6
  MatX matrix;      // r×r
};

// Stiffness along a unit direction u: the force along u over the displacement along u when a
// force along u alone acts, 1 / (uᵀ·C_tt·u), and likewise against a moment about u,
// 1 / (uᵀ·C_rr·u); +inf where u is held rigidly (docs/theory.md, "Principal and directional
// stiffness").
struct DirectionalStiffness {
  Vec3 direction = Vec3::Zero();  // unit, global axes
  double translational = 0;       // N/m
  double rotational = 0;          // N·m/rad
};

struct EndEffectorResult {
  std::string name;
  std::string point;
  std::string link;
  LinkEnd end = LinkEnd::to;
  std::optional<Mat6> compliance;  // Δt_e per unit wrench at e
  std::optional<Mat6> stiffness;   // eq. (21); nullopt where unbounded or undetermined
  std::optional<Vec6> deflection;  // under the model's loads and preloads
  // Given where `stiffness` is null because some directions are held rigidly and others not.
  std::optional<ReducedStiffness> reduced_stiffness;
  // With SolveOptions::direction, where the compliance is determined: the stiffness along it.
  std::optional<DirectionalStiffness> along_direction;
  // Under the self-weight loads alone (Load::self_weight), where the model has any.
  std::optional<Vec6> deflection_gravity;
  // The same in the end effector's own axes, where the model gives them (EndEffector::axes).
  struct InAxes {
    Mat3 axes = Mat3::Identity();
    std::optional<Mat6> compliance, stiffness;
    std::optional<Vec6> deflection, deflection_gravity;
  };
  std::optional<InAxes> in_own_axes;
  // In the loaded mode: the size of the non-symmetric part of the tangent stiffness,
  // ‖K − Kᵀ‖_F / ‖K + Kᵀ‖_F of K with rotations weighted by the model size (docs/theory.md
  // §15.7); nullopt in the linear mode and where the stiffness is unbounded.
  std::optional<double> stiffness_asymmetry;
};

// The method that solved a system (SolverKind chooses among them; docs/theory.md §7): the tree
// passes, the tree passes with a dense system for the cuts, the frame's condensed stiffness,
// or a sparse LU of the whole system. `none` in a report that no solve filled.
enum class SolverUsed { none, tree, tree_with_cuts, frame, klu, sparse_lu, umfpack, block_lu };
// The names results and messages give them: "tree", "tree_with_cuts", "frame", "klu",
// "sparse_lu", "umfpack", "block_lu" (the loaded mode's tangent) ("" for none).
const char* to_string(SolverUsed solver);
std::optional<SolverUsed> solver_used_from_string(std::string_view name);

// How the solve went: accuracy checks and notes for the user.
struct SolveReport {
  double relative_residual = 0;  // max over all solves of ‖Ax−b‖∞ / (‖A‖∞‖x‖∞ + ‖b‖∞)
  double equilibrium_error = 0;  // ‖Σ reactions + Σ loads‖ / scale (moments about the origin)
  double reciprocal_condition =
      0;  // 1-norm estimate for the equilibrated system; 0 where no
          // sparse system was factorised (solver "tree", "tree_with_cuts");
          // for "frame", that of the condensed stiffness (unit diagonal)
  SolverUsed solver = SolverUsed::none;
  std::vector<std::string> notes;  // e.g. free motions accepted, values left null
  std::vector<std::string> warnings;
  // Those warnings that say an accuracy check failed (the residual above
  // SolveOptions::max_relative_residual, loads and reactions out of balance beyond 1e-8): the
  // numbers of such a result are not to be trusted.
  std::vector<std::string> failed_checks;
  // The warning that some deflection under the loads is beyond the range of the linear method
  // (also in warnings; docs/model-format.md, "Plausibility warnings"); empty where none is.
  // It starts with kLargeDeflectionWarning, by which a sweep's row read back tells it.
  std::string large_deflection;

  // Whether the numbers passed every accuracy check (failed_checks is empty). A result with
  // large deflections is usable: its numbers are those of the linear method, read with care.
  bool usable() const { return failed_checks.empty(); }
};
inline constexpr std::string_view kLargeDeflectionWarning =
    "the deflections under the loads are too large for the linear method";

// How a result was found: the linear method at the unloaded pose, or the loaded mode's
// equilibrium reached in load steps and Newton iterations.
struct AnalysisInfo {
  AnalysisMode mode = AnalysisMode::linear;
  int load_steps = 0;
  int iterations = 0;
};

// The smallest positive multiplier λ of a load case's loads (from the unloaded state) at which
// the structure buckles or reaches a limit point; no factor where none is positive.
struct CriticalLoad {
  std::optional<double> factor;
  // The buckling mode in the user's terms ("link 'column' bends about its local y axis", …).
  std::string mode;
};

struct Result {
  std::string model;
  // The load case these results are of ("" for the model's unnamed case).
  std::string load_case;
  AnalysisInfo analysis;
  // The parameters of a model built from a family, at their values (Model::parameters, copied
  // by solve), so that a result tells which member it is. Empty otherwise.
  std::vector<ParameterValue> parameters;
  // The diagonal of the box around the model's points (at least 1 mm): the lever that makes
  // moments comparable with forces, and rotations with translations.
  double model_size = 0;
  SystemSize system;
  std::vector<EndEffectorResult> end_effectors;
  std::vector<LinkResult> links;
  std::vector<JointResult> joints;
  std::vector<SupportResult> supports;
  SolveReport report;
  // Computed where SolveOptions::critical_load asks for it.
  std::optional<CriticalLoad> critical_load;
  // Every named load case's results (their own load_cases empty), in model order. With the
  // unnamed case absent the top-level results are a copy of the first's.
  std::vector<Result> load_cases;
  // In the loaded mode: the linear results of the same case, with the same layout.
  std::shared_ptr<const Result> linear;

  // The results of the load case of that name (NameError when there is none).
  const Result& load_case_result(std::string_view name) const;

  // The result of the entity of that name; NameError (with the nearest name) when there is
  // none. The vectors above give them in model order.
  const EndEffectorResult& end_effector(std::string_view name) const;
  const LinkResult& link(std::string_view name) const;
  const JointResult& joint(std::string_view name) const;
  const SupportResult& support(std::string_view name) const;
};

}  // namespace stiffmsa

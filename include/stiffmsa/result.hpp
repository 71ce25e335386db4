#pragma once
// What an analysis returns. Everything is keyed by the user's names, in model order. A value
// that the model does not determine (free motion, indeterminate internal wrench) is nullopt.
#include <optional>
#include <string>
#include <vector>

#include "stiffmsa/model.hpp"

namespace stiffmsa {

struct SystemSize {
  long unknowns = 0;
  long equations = 0;
  long nonzeros = 0;
};

struct LinkEndResult {
  std::optional<Vec6> deflection;  // Δt = [Δp; Δφ]
  std::optional<Vec6> wrench;      // W applied to the link at this end
};

struct LinkResult {
  std::string name;
  LinkEndResult from, to;
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

struct EndEffectorResult {
  std::string name;
  std::string point;
  std::string link;
  LinkEnd end = LinkEnd::to;
  std::optional<Mat6> compliance;  // Δt_e per unit wrench at e
  std::optional<Mat6> stiffness;   // eq. (21); nullopt where unbounded or undetermined
  std::optional<Vec6> deflection;  // under the model's loads and preloads
  // Under the self-weight loads alone (Load::self_weight), where the model has any.
  std::optional<Vec6> deflection_gravity;
  // The same in the end effector's own axes, where the model gives them (EndEffector::axes).
  struct InAxes {
    Mat3 axes = Mat3::Identity();
    std::optional<Mat6> compliance, stiffness;
    std::optional<Vec6> deflection, deflection_gravity;
  };
  std::optional<InAxes> in_own_axes;
};

// How the solve went: accuracy checks and notes for the user.
struct SolveReport {
  double relative_residual = 0;    // max over all solves of ‖Ax−b‖∞ / (‖A‖∞‖x‖∞ + ‖b‖∞)
  double equilibrium_error = 0;    // ‖Σ reactions + Σ loads‖ / scale (moments about the origin)
  double reciprocal_condition = 0; // 1-norm estimate for the equilibrated system; 0 where no
                                   // sparse system was factorised (solver "tree", "tree_with_cuts");
                                   // for "frame", that of the condensed stiffness (unit diagonal)
  std::string solver;              // "tree", "tree_with_cuts", "frame", or the sparse LU: "klu",
                                   // "sparse_lu", "umfpack"
  std::vector<std::string> notes;  // e.g. free motions accepted, values left null
  std::vector<std::string> warnings;
  // Those warnings that say an accuracy check failed (the residual above
  // SolveOptions::max_relative_residual, loads and reactions out of balance beyond 1e-8): the
  // numbers of such a result are not to be trusted.
  std::vector<std::string> failed_checks;
};

struct Result {
  std::string model;
  SystemSize system;
  std::vector<EndEffectorResult> end_effectors;
  std::vector<LinkResult> links;
  std::vector<JointResult> joints;
  std::vector<SupportResult> supports;
  SolveReport report;
};

}  // namespace stiffmsa

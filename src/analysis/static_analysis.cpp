// The analyses of model-format.md: deflections and wrenches under the model's loads, and the
// compliance and Cartesian stiffness (paper eqs. 20–21) at every end effector.
#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "analysis/cartesian.hpp"
#include "analysis/case_loads.hpp"
#include "analysis/critical_load.hpp"
#include "analysis/free_motion.hpp"
#include "analysis/loaded_mode.hpp"
#include "analysis/plausibility.hpp"
#include "analysis/sweep_row.hpp"
#include "analysis/workspace_access.hpp"
#include "assembly/assembler.hpp"
#include "elements/free_directions.hpp"
#include "model/link_ends.hpp"
#include "model/structure_impl.hpp"
#include "solver/frame_solver.hpp"
#include "solver/sparse_solver.hpp"
#include "solver/tree_solver.hpp"
#include "stiffmsa/analysis.hpp"
#include "stiffmsa/config.hpp"
#include "stiffmsa/validate.hpp"

namespace stiffmsa {

using detail::Index;

bool solver_available(SolverKind s) {
  return s == SolverKind::automatic || s == SolverKind::sparse_lu || STIFFMSA_HAVE_SUITESPARSE;
}

void SolveOptions::validate() const {
  if (!solver_available(solver))
    throw UsageError(std::string("the solver '") + to_string(solver) +
                     "' is not built into this stiffmsa");
  if (!(singular_rcond >= 0 && singular_rcond < 1))
    throw UsageError("singular_rcond must be in [0, 1)");
  if (!(max_relative_residual > 0)) throw UsageError("max_relative_residual must be positive");
  if (refinement_steps < 0 || refinement_steps > 20)
    throw UsageError("refinement_steps must be between 0 and 20");
  if (!(warn_condition > 1)) throw UsageError("warn_condition must be greater than 1");
  if (direction && !(direction->allFinite() && direction->norm() > 0))
    throw UsageError("the direction of a directional stiffness must be a finite, non-zero vector");
}

struct Workspace::Impl {
  detail::Topology topology;
  // The pattern of the reference's blocks (`reference`: recorded_blocks, or the blocks a
  // one-shot solve took from there), recorded when first needed: a tree solve needs none. Never
  // from another model's blocks, whose pattern may differ and is checked against this one.
  mutable std::unique_ptr<detail::Assembler> assembler;
  detail::Assembler& pattern(const detail::Blocks& reference) const {
    if (!assembler) assembler = std::make_unique<detail::Assembler>(reference, topology.unknowns());
    return *assembler;
  }
  detail::SparseMatrix matrix;
  std::unique_ptr<detail::FactorizedSystem> system;
  SolverKind solver_kind = SolverKind::automatic;
  // The blocks of the model the workspace was built from: its pattern, and the reference
  // matrix that fixes the scaling start and pivot order of every solver the workspace uses
  // (FactorizedSystem), so that a pose's results do not depend on the poses solved before it.
  // A one-shot solve takes them, as its own blocks.
  detail::Blocks recorded_blocks;
  // Where links and connections form a tree on the one support, `auto` solves by passing
  // wrenches and deflections along it (solver/tree_solver.hpp) instead of factorising.
  std::optional<detail::TreeOrder> tree;
  // The pattern_fingerprint of the reference's blocks, once a tree or frame solve needs it: a
  // model whose blocks write other positions has changed topology, however it is solved.
  std::optional<std::uint64_t> block_pattern;
  // The tree solve's buffers, kept from one pose to the next.
  detail::TreeScratch tree_scratch;
  // The blocks of the pose solved last, refilled with the next pose's numbers (refill_blocks).
  detail::Blocks pose_blocks;
  // Where the model is no tree but a frame (every link flexible, every connection a weld), `auto`
  // solves the condensed displacement system first (solver/frame_solver.hpp).
  std::optional<detail::FramePlan> frame;
  // The rods whose idle spin this workspace's blocks hold (empty in the model's own workspace).
  std::vector<detail::SpinLock> spin_locks;
  // A structure's workspace: the structure, and the model its poses' values are written into.
  std::optional<Structure> structure;
  Model member;
  // Where the model has rods with ball joints at both ends: the same model with their spins held,
  // which `auto` solves, where idle motions are accepted, instead of analysing the free motions
  // of a singular system at every pose. Its own workspace, as its blocks have another pattern.
  std::unique_ptr<Impl> spin_locked;
  // The loaded mode's Newton tangent (its pattern, analysis and buffers), made at the first
  // loaded solve.
  std::unique_ptr<detail::LoadedTangent> loaded_tangent;
  // The critical load's tree solve buffers, kept from one pose to the next; and whether its
  // solves skip it (detail::skip_critical_loads: a sweep's).
  detail::TreeScratch critical_load_scratch;
  bool skip_critical_loads = false;

  // The blocks of `model` (this topology's), and what the solves without factorising need.
  void record(const Model& model) {
    recorded_blocks = detail::make_blocks(model, topology, spin_locks);
    tree = detail::tree_order(topology);
    // A tree that the tree solve cannot take (a stiffness-only CAD link) may still be a frame.
    if (!tree || !detail::passes_tree(recorded_blocks))
      frame = detail::frame_plan(topology, recorded_blocks);
  }
};

namespace {
// The rest of a workspace once its topology is known.
void prepare(Workspace::Impl& ws, const Model& model) {
  ws.record(model);
  std::vector<detail::SpinLock> locks = detail::find_spin_locks(model, ws.topology);
  if (!locks.empty()) {
    ws.spin_locked = std::make_unique<Workspace::Impl>();
    ws.spin_locked->topology = ws.topology;
    ws.spin_locked->spin_locks = std::move(locks);
    ws.spin_locked->record(model);
  }
}
}  // namespace

Workspace::Workspace(const Model& model) : Workspace(model, detail::ModelIndex(model)) {}

Workspace::Workspace(const Model& model, const detail::ModelIndex& index)
    : impl_(std::make_unique<Impl>()) {
  detail::validate(model, index);
  impl_->topology = detail::build_topology(model, index);
  prepare(*impl_, model);
}

Workspace::Workspace(const Structure& structure) : impl_(std::make_unique<Impl>()) {
  impl_->structure = structure;
  impl_->member = structure.model();
  // The reader's notices are the model's at the structure's defaults, not a pose's.
  impl_->member.warnings.clear();
  impl_->topology = structure.impl().topology;
  prepare(*impl_, impl_->member);
}
Workspace::~Workspace() = default;
Workspace::Workspace(Workspace&&) noexcept = default;
Workspace& Workspace::operator=(Workspace&&) noexcept = default;

SystemSize Workspace::size() const { return impl_->pattern(impl_->recorded_blocks).size(); }

namespace {

using detail::deflection_column;
using detail::wrench_column;

// Of a solution vector (a VecX, or a column of the tree solve's unknowns stored by rows).
template <class Column>
Vec6 deflection_of(const Column& x, int end) {
  return x.template segment<6>(deflection_column(end));
}
template <class Column>
Vec6 wrench_of(const Column& x, int end) {
  return x.template segment<6>(wrench_column(end));
}

// Where each link end sits.
std::vector<Vec3> end_positions(const Model& model, const detail::Topology& topology) {
  std::vector<Vec3> positions;
  positions.reserve(topology.end_points.size());
  for (int point : topology.end_points)
    positions.push_back(model.points[static_cast<std::size_t>(point)].position);
  return positions;
}

long count_nonzero_values(const detail::SparseMatrix& a) {
  long count = 0;
  for (Index k = 0; k < a.nonZeros(); ++k) count += a.valuePtr()[k] != 0.0;
  return count;
}

// Everything one solve needs: the model's blocks, assembled and factorised.
struct Problem {
  const Model& model;
  Workspace::Impl& ws;
  const SolveOptions& options;
  detail::ResultScope scope;
  detail::Blocks blocks;
  // The load cases, one right-hand side column each (case_loads.hpp): the unnamed case where
  // there is one, every named case, and the robot's self-weight alone where it has one. The
  // solve's own (CaseSolve::cases), which the critical load and the loaded mode take too.
  std::vector<detail::CaseLoads>& cases;
  Index state_columns = 0;                // the cases that carry the preloads and settlements
  bool loaded = false;                    // any nonzero load, preload or settlement
  bool blocks_are_the_reference = false;  // a one-shot solve's: its own pattern

  // The blocks of the model the workspace was built from.
  const detail::Blocks& reference_blocks() const {
    return blocks_are_the_reference ? blocks : ws.recorded_blocks;
  }

  // `topology_known`: the workspace was built from this very model.
  Problem(const Model& m, Workspace::Impl& w, const SolveOptions& o, detail::ResultScope s,
          bool topology_known, std::vector<detail::CaseLoads>& case_storage)
      : model(m), ws(w), options(o), scope(s), cases(case_storage) {
    if (topology_known && !ws.recorded_blocks.empty()) {
      blocks = std::move(ws.recorded_blocks);
      ws.recorded_blocks.clear();
      blocks_are_the_reference = true;
    } else {
      blocks = std::move(ws.pose_blocks);
      detail::refill_blocks(model, ws.topology, ws.spin_locks, blocks);
    }
    cases = detail::case_loads(model, ws.topology);
    for (const detail::CaseLoads& c : cases) {
      loaded |= c.loaded;
      state_columns += c.with_state;
    }
    for (const auto& j : model.joints)
      loaded |= j.connection.preload && !j.connection.preload->isZero(0);
    for (const auto& s : model.supports)
      loaded |= s.connection.preload && !s.connection.preload->isZero(0);
    check_settlements();
  }

  Index load_columns() const { return static_cast<Index>(cases.size()); }

  Problem(const Problem&) = delete;
  Problem& operator=(const Problem&) = delete;
  // A model of more blocks than this (a long chain, a large frame) does not keep a second set
  // in its workspace between solves, as its tree solve's large buffers are not kept either: a
  // robot's blocks are tens, kept to be refilled by its next pose.
  static constexpr std::size_t kMostKeptBlocks = 4096;
  ~Problem() {
    if (!blocks_are_the_reference && blocks.size() <= kMostKeptBlocks)
      ws.pose_blocks = std::move(blocks);
  }

  VecX load_rhs(const detail::CaseLoads& c) const {
    std::vector<std::pair<int, Vec6>> wrenches;
    for (std::size_t e = 0; e < c.external.size(); ++e)
      if (!c.external[e].isZero(0)) wrenches.emplace_back(static_cast<int>(e), c.external[e]);
    return ws.assembler->right_hand_side(blocks, ws.topology, wrenches, c.with_state);
  }

  // A settlement moves the ground along the directions the support holds; along a free one
  // nothing would hold the ground's motion (validate() says so with the file's place first).
  void check_settlements() {
    const detail::Topology& t = ws.topology;
    for (std::size_t g = 0; g < t.groups.size(); ++g) {
      if (t.groups[g].kind != detail::ConnectionGroup::Kind::support) continue;
      const Support& support = model.supports[static_cast<std::size_t>(t.groups[g].source)];
      if (!support.displacement) continue;
      loaded |= !support.displacement->isZero(0);
      const detail::FreeDirections* directions =
          blocks[static_cast<std::size_t>(t.link_count) + g]->directions();
      if (directions && directions->p > 0 &&
          (directions->free() * *support.displacement).norm() >
              detail::kRankTolerance * support.displacement->norm())
        throw InputError(support.origin.of("displacement"), "supports." + support.name,
                         "a settlement (displacement) must be zero along the support's free "
                         "directions: the support does not hold the ground's motion there");
    }
  }

  // Columns: the right-hand sides of a unit wrench at `end` in each of the 6 directions.
  MatX unit_wrench_rhs(int end) const {
    MatX b = MatX::Zero(ws.topology.unknowns(), 6);
    for (int c = 0; c < 6; ++c) {
      VecX column = VecX::Zero(ws.topology.unknowns());
      ws.assembler->add_wrench(blocks, ws.topology, end, Vec6::Unit(c), column);
      b.col(c) = column;
    }
    return b;
  }
};

// The results of one load case from its column of the solution. Its loads along links entered
// as equivalent end loads (case_loads.hpp): the solved end wrenches plus the fixed-end wrenches
// are the true ones; a joint's wrench and a support's reaction, which count those end loads as
// applied at the ends, need no correction.
template <class Column>
void fill_state_results(const Problem& problem, const Column& x, const detail::CaseLoads& loads,
                        Result& result) {
  const Model& model = problem.model;
  const detail::Topology& t = problem.ws.topology;
  const std::vector<Vec6>& external = loads.external;
  const bool sweep_row = problem.scope == detail::ResultScope::sweep_row;
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    const int from = 2 * static_cast<int>(l), to = from + 1;
    if (sweep_row) {  // the deflections, for the large-deflection warning
      result.links[l].from.deflection = deflection_of(x, from);
      result.links[l].to.deflection = deflection_of(x, to);
      continue;
    }
    result.links[l].from = {deflection_of(x, from), wrench_of(x, from)};
    result.links[l].to = {deflection_of(x, to), wrench_of(x, to)};
    if (!loads.fixed_end.empty()) {
      *result.links[l].from.wrench += loads.fixed_end[static_cast<std::size_t>(from)];
      *result.links[l].to.wrench += loads.fixed_end[static_cast<std::size_t>(to)];
    }
  }
  for (std::size_t g = 0; g < t.groups.size(); ++g) {
    const detail::ConnectionGroup& group = t.groups[g];
    if (group.kind == detail::ConnectionGroup::Kind::joint && !sweep_row) {
      const Joint& joint = model.joints[static_cast<std::size_t>(group.source)];
      // The joint's block holds its directions, except a locked actuator's, which it holds rigidly:
      // its effort is still along the joint's own free directions.
      const bool locked = joint.connection.is_actuated && !joint.connection.stiffness;
      const detail::FreeDirections* held =
          problem.blocks[static_cast<std::size_t>(t.link_count) + g]->directions();
      const detail::FreeDirections directions =
          locked || !held ? detail::free_directions(joint.connection.kinematics) : *held;
      JointResult& r = result.joints[static_cast<std::size_t>(group.source)];
      const int first = group.ends.front();
      std::vector<VecX> q;
      for (std::size_t k = 1; k < group.ends.size(); ++k)
        q.push_back(directions.free() *
                    (deflection_of(x, group.ends[k]) - deflection_of(x, first)));
      r.relative_deflection = std::move(q);
      r.wrench = wrench_of(x, first) - external[static_cast<std::size_t>(first)];
      if (joint.connection.is_actuated)
        r.effort = VecX(directions.gram().ldlt().solve(directions.free() * *r.wrench));
    } else if (group.kind == detail::ConnectionGroup::Kind::support) {
      Vec6 reaction = Vec6::Zero();
      for (int end : group.ends)
        reaction += wrench_of(x, end) - external[static_cast<std::size_t>(end)];
      result.supports[static_cast<std::size_t>(group.source)].reaction = reaction;
    }
  }
  for (std::size_t e = 0; e < model.end_effectors.size(); ++e)
    result.end_effectors[e].deflection = deflection_of(x, t.effector_ends[e]);
}

// ‖Σ reactions + Σ loads‖, forces and moments (about the origin) each relative to their scale;
// a load along a link counts with its true resultant.
double equilibrium_error(const Problem& problem, const detail::CaseLoads& loads,
                         const Result& result) {
  Vec3 force = Vec3::Zero(), moment = Vec3::Zero();
  double force_scale = 0, moment_scale = 0;
  const std::vector<Vec3> positions = end_positions(problem.model, problem.ws.topology);
  auto add = [&](const Vec3& at, const Vec6& w) {
    force += w.head<3>();
    const Vec3 m = w.tail<3>() + at.cross(w.head<3>());
    moment += m;
    force_scale += w.head<3>().norm();
    moment_scale += w.tail<3>().norm() + at.norm() * w.head<3>().norm();
  };
  const std::vector<Vec6>& applied = loads.applied_at_ends();
  for (std::size_t e = 0; e < applied.size(); ++e)
    if (!applied[e].isZero(0)) add(positions[e], applied[e]);
  for (const detail::ResolvedLinkLoad& load : loads.link_loads) {
    const detail::LoadResultant r = detail::resultant(problem.model, problem.ws.topology, load);
    add(r.at, r.wrench);
  }
  for (const auto& group : problem.ws.topology.groups)
    if (group.kind == detail::ConnectionGroup::Kind::support) {
      const auto& reaction = result.supports[static_cast<std::size_t>(group.source)].reaction;
      if (reaction) add(positions[static_cast<std::size_t>(group.ends.front())], *reaction);
    }
  double error = 0;
  if (force_scale > 0) error = std::max(error, force.norm() / force_scale);
  if (moment_scale > 0) error = std::max(error, moment.norm() / moment_scale);
  return error;
}

Result empty_result(const Model& model, const Workspace::Impl& ws, detail::ResultScope scope) {
  Result result;
  result.end_effectors.reserve(model.end_effectors.size());
  if (scope == detail::ResultScope::sweep_row) {
    // Unnamed: what a row takes is the end effectors' results and the warnings, which take
    // the names from the model.
    result.links.resize(model.links.size());
    result.joints.resize(model.joints.size());
    result.supports.resize(model.supports.size());
  } else {
    result.model = model.name;
    result.links.reserve(model.links.size());
    result.joints.reserve(model.joints.size());
    result.supports.reserve(model.supports.size());
    for (const auto& l : model.links) result.links.push_back({l.name, {}, {}, {}});
    for (const auto& j : model.joints) {
      JointResult joint;
      joint.name = j.name;
      joint.actuated = j.connection.is_actuated;
      result.joints.push_back(std::move(joint));
    }
    for (const auto& s : model.supports) result.supports.push_back({s.name, std::nullopt});
  }
  for (std::size_t e = 0; e < model.end_effectors.size(); ++e) {
    const auto& effector = model.end_effectors[e];
    const int end = ws.topology.effector_ends[e];
    EndEffectorResult effector_result;
    effector_result.name = effector.name;
    effector_result.point = effector.at;
    effector_result.link = model.links[static_cast<std::size_t>(end / 2)].name;
    effector_result.end = static_cast<LinkEnd>(end % 2);
    result.end_effectors.push_back(std::move(effector_result));
  }
  return result;
}

// The parts streamed into one string; a stream is built only for a message that is given.
template <class... Parts>
std::string message(const Parts&... parts) {
  std::ostringstream text;
  (text << ... << parts);
  return text.str();
}

void check_accuracy(const SolveOptions& options, Result& result) {
  const double rcond = result.report.reciprocal_condition;
  if (rcond > 0 && rcond * options.warn_condition < 1)
    result.report.warnings.push_back(message(
        "the system is ill-conditioned (condition estimate ", 1 / rcond,
        "): likely a near-mechanism (joint axes almost aligned, a link almost along a joint's free "
        "direction) or stiffness values many decades apart; check the digits of the results"));
  if (result.report.relative_residual > options.max_relative_residual)
    result.report.failed_checks.push_back(
        message("the relative residual ", result.report.relative_residual, " exceeds ",
                options.max_relative_residual, "; results may be inaccurate"));
  if (result.report.equilibrium_error > detail::kEquilibriumTolerance)
    result.report.failed_checks.push_back(message("loads and support reactions balance only to ",
                                                  result.report.equilibrium_error,
                                                  " relative; results may be inaccurate"));
  result.report.warnings.insert(result.report.warnings.end(), result.report.failed_checks.begin(),
                                result.report.failed_checks.end());
}

// The results of every load case (one per Problem::cases), filled alike where they share a value.
using CaseResults = std::vector<Result>;

// The right-hand sides: each load case's loads (with the preloads and settlements where the case
// carries them) in columns 0 .. k−1, then a unit wrench in each of the 6 directions at every end
// effector.
MatX load_and_unit_wrench_rhs(const Problem& problem) {
  const auto& t = problem.ws.topology;
  const std::size_t effectors = problem.model.end_effectors.size();
  const Index k = problem.load_columns();
  MatX rhs(t.unknowns(), k + 6 * static_cast<Index>(effectors));
  for (Index c = 0; c < k; ++c)
    rhs.col(c) = problem.load_rhs(problem.cases[static_cast<std::size_t>(c)]);
  for (std::size_t e = 0; e < effectors; ++e)
    rhs.middleCols<6>(k + 6 * static_cast<Index>(e)) = problem.unit_wrench_rhs(t.effector_ends[e]);
  return rhs;
}

// The same as the tree and frame solves take them, into `wrenches` (its buffers kept).
void load_and_unit_wrenches(const Problem& problem, detail::EndWrenches& wrenches) {
  const auto& t = problem.ws.topology;
  const Index k = problem.load_columns();
  wrenches.reset(t.end_count(), k + 6 * static_cast<Index>(t.effector_ends.size()),
                 problem.state_columns);
  for (Index c = 0; c < k; ++c) {
    const std::vector<Vec6>& external = problem.cases[static_cast<std::size_t>(c)].external;
    for (std::size_t e = 0; e < external.size(); ++e)
      if (!external[e].isZero(0)) wrenches.add(static_cast<int>(e), c, external[e]);
  }
  for (std::size_t e = 0; e < t.effector_ends.size(); ++e)
    for (int c = 0; c < 6; ++c)
      wrenches.add(t.effector_ends[e], k + 6 * static_cast<Index>(e) + c, Vec6::Unit(c));
}

// Deflections, wrenches, compliance and stiffness from the solutions of those right-hand sides
// (a MatX, or the tree solve's RowMajorMatX).
template <class Solution>
void fill_loads_and_compliance(const Problem& problem, const Solution& x, double residual,
                               CaseResults& results) {
  const auto& t = problem.ws.topology;
  const std::size_t effectors = problem.model.end_effectors.size();
  const Index k = problem.load_columns();
  Result& result = results.front();
  result.report.relative_residual = std::max(result.report.relative_residual, residual);
  const double length = detail::characteristic_length(problem.model);
  for (std::size_t e = 0; e < effectors; ++e) {
    const Mat6 compliance = x.template block<6, 6>(deflection_column(t.effector_ends[e]),
                                                   k + 6 * static_cast<Index>(e));
    auto& r = result.end_effectors[e];
    r.compliance = compliance;
    const detail::CartesianStiffness cartesian =
        detail::cartesian_stiffness(compliance, length, problem.options.warn_condition);
    r.stiffness = cartesian.stiffness;
    if (!r.stiffness) {
      if (problem.scope == detail::ResultScope::sweep_row) continue;  // only a note says so
      r.reduced_stiffness = detail::reduced_stiffness(compliance, length);
      result.report.notes.push_back(
          "end effector '" + r.name +
          "' is held rigidly in some direction (or is so nearly a mechanism that double precision "
          "cannot tell): its "
          "stiffness is unbounded (null)" +
          (r.reduced_stiffness
               ? message("; reduced_stiffness gives it on the ", r.reduced_stiffness->matrix.rows(),
                         " directions it can move in")
               : std::string()));
    } else if (cartesian.spread > problem.options.warn_condition) {
      result.report.warnings.push_back(message(
          "end effector '", r.name, "': its stiffness differs by a factor ", cartesian.spread,
          " between directions, a near-mechanism; its softest direction may "
          "have lost most digits"));
    }
  }
  // Every case shares the compliance and what was said of it; each has its own state.
  for (std::size_t c = 1; c < results.size(); ++c) {
    Result& other = results[c];
    other.system = result.system;
    other.report = result.report;
    for (std::size_t e = 0; e < effectors; ++e) {
      other.end_effectors[e].compliance = result.end_effectors[e].compliance;
      other.end_effectors[e].stiffness = result.end_effectors[e].stiffness;
      other.end_effectors[e].reduced_stiffness = result.end_effectors[e].reduced_stiffness;
    }
  }
  const bool internal_forces =
      problem.scope == detail::ResultScope::everything && detail::loads_along_links(problem.model);
  for (std::size_t c = 0; c < results.size(); ++c) {
    const detail::CaseLoads& loads = problem.cases[c];
    fill_state_results(problem, x.col(static_cast<Index>(c)), loads, results[c]);
    if (internal_forces) detail::add_internal_forces(problem.model, t, loads, results[c]);
    results[c].report.equilibrium_error = equilibrium_error(problem, loads, results[c]);
  }
}

void check_accuracy(const SolveOptions& options, CaseResults& results) {
  for (Result& result : results) check_accuracy(options, result);
}

// Sets `member` of every case's result.
template <class Member, class Value>
void set_all(CaseResults& results, Member member, const Value& value) {
  for (Result& result : results) result.*member = value;
}

void solve_regular(Problem& problem, CaseResults& results) {
  double residual = 0;
  const MatX x = problem.ws.system->solve(load_and_unit_wrench_rhs(problem),
                                          problem.options.refinement_steps, residual);
  fill_loads_and_compliance(problem, x, residual, results);
  check_accuracy(problem.options, results);
}

// The solves that factorise no mixed system, the tree solve (solver/tree_solver.hpp) and the
// frame solve (solver/frame_solver.hpp), checked against the equations block by block. False,
// with the result untouched, where the solve declines or its residual fails the check: the
// factorising solve then decides.
enum class BlockSolve { tree, frame };

bool solve_without_factorising(Problem& problem, BlockSolve kind, CaseResults& results) {
  const auto& t = problem.ws.topology;
  detail::TreeScratch& scratch = problem.ws.tree_scratch;
  // Whatever the outcome, a long model's buffers are not kept in the workspace.
  struct Release {
    detail::TreeScratch& scratch;
    ~Release() { scratch.release_large(); }
  } release{scratch};
  detail::EndWrenches& external = scratch.load_case_wrenches;
  load_and_unit_wrenches(problem, external);
  const char* solver = nullptr;
  double reciprocal_condition = 0;  // of what was factorised: nothing on the tree
  if (kind == BlockSolve::tree) {
    const std::optional<detail::Index> cut_unknowns = detail::tree_solve(
        problem.blocks, t, *problem.ws.tree, external, 1 / problem.options.warn_condition, scratch);
    if (!cut_unknowns) return false;
    solver = *cut_unknowns == 0 ? "tree" : "tree_with_cuts";
  } else {
    const std::optional<detail::FrameSolution> solution =
        detail::frame_solve(problem.blocks, t, *problem.ws.frame, external, scratch.x);
    if (!solution) return false;
    solver = "frame";
    reciprocal_condition = solution->reciprocal_condition;
  }
  const detail::RowMajorMatX& x = scratch.x;
  const detail::BlockCheck check =
      detail::check_block_by_block(problem.blocks, t, x, external, scratch);
  if (!problem.blocks_are_the_reference) {
    if (!problem.ws.block_pattern)
      problem.ws.block_pattern = detail::pattern_fingerprint(problem.reference_blocks());
    if (check.pattern != *problem.ws.block_pattern) detail::throw_topology_changed();
  }
  if (!(check.relative_residual <= problem.options.max_relative_residual)) return false;
  Result& result = results.front();
  result.system = {t.unknowns(), t.unknowns(), check.nonzeros};
  result.report.solver = solver_used_from_string(solver).value_or(SolverUsed::none);
  result.report.reciprocal_condition = reciprocal_condition;
  fill_loads_and_compliance(problem, x, check.relative_residual, results);
  check_accuracy(problem.options, results);
  return true;
}

detail::SparseMatrix bordered(const detail::SparseMatrix& a, const MatX& columns,
                              const MatX& rows) {
  const Index n = a.rows(), k = columns.cols();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(a.nonZeros() + 2 * n * k));
  for (Index j = 0; j < a.outerSize(); ++j)
    for (detail::SparseMatrix::InnerIterator e(a, j); e; ++e)
      entries.emplace_back(static_cast<int>(e.row()), static_cast<int>(j), e.value());
  for (Index c = 0; c < k; ++c) {
    const double column_scale = columns.col(c).cwiseAbs().maxCoeff(),
                 row_scale = rows.col(c).cwiseAbs().maxCoeff();
    for (Index i = 0; i < n; ++i) {
      if (std::abs(columns(i, c)) > detail::kBorderDrop * column_scale)
        entries.emplace_back(static_cast<int>(i), static_cast<int>(n + c), columns(i, c));
      if (std::abs(rows(i, c)) > detail::kBorderDrop * row_scale)
        entries.emplace_back(static_cast<int>(n + c), static_cast<int>(i), rows(i, c));
    }
  }
  detail::SparseMatrix m(n + k, n + k);
  m.setFromTriplets(entries.begin(), entries.end());
  m.makeCompressed();
  return m;
}

// The largest over columns of a 6-row block's weighted size: translations plus rotations times
// a length, or forces plus moments divided by it, so that both halves weigh alike.
double largest_six(const MatX& rows6, double length, bool rotations_times_length) {
  if (rows6.cols() == 0) return 0.0;
  const double w = rotations_times_length ? length : 1.0 / length;
  return (rows6.topRows<3>().colwise().norm() + w * rows6.bottomRows<3>().colwise().norm())
      .maxCoeff();
}

bool moves_any_end_effector(const Problem& problem, const MatX& motions) {
  const double length = detail::characteristic_length(problem.model);
  double largest = 0;
  for (int end = 0; end < problem.ws.topology.end_count(); ++end)
    largest =
        std::max(largest, largest_six(motions.middleRows<6>(deflection_column(end)), length, true));
  for (int end : problem.ws.topology.effector_ends)
    if (largest_six(motions.middleRows<6>(deflection_column(end)), length, true) >
        detail::kNegligibleShare * largest)
      return true;
  return false;
}

// A wrench that a rigid model leaves undetermined (its `variation` across the family of internal
// wrenches, 6×k, is not negligible against `negligible`) may still have some components that do
// not vary: a planar robot's in-plane reactions where only its out-of-plane ones are shared out
// among over-constrained legs. A note names them with their values; the wrench is null.
void note_determined_components(const std::string& whose, const Vec6& wrench, const MatX& variation,
                                double length, double negligible, std::vector<std::string>& notes) {
  static constexpr std::array<const char*, 6> components = {"Fx", "Fy", "Fz", "Mx", "My", "Mz"};
  std::array<bool, 6> fixed{};
  double scale = 0;
  for (int c = 0; c < 6; ++c) {
    const double per_length = c < 3 ? 1.0 : 1.0 / length;
    fixed[static_cast<std::size_t>(c)] =
        variation.row(c).cwiseAbs().maxCoeff() * per_length <= negligible;
    if (fixed[static_cast<std::size_t>(c)])
      scale = std::max(scale, std::abs(wrench(c)) * per_length);
  }
  std::string determined;
  int count = 0;
  for (int c = 0; c < 6; ++c) {
    if (!fixed[static_cast<std::size_t>(c)]) continue;
    const double value =
        std::abs(wrench(c)) * (c < 3 ? 1.0 : 1.0 / length) < detail::kRoundOff * scale ? 0.0
                                                                                       : wrench(c);
    determined += message(count++ ? ", " : "", components[static_cast<std::size_t>(c)], " = ",
                          value, c < 3 ? " N" : " N·m");
  }
  if (count > 0)
    notes.push_back(whose +
                    " is null, as the rigid model does not determine all of it; its determined " +
                    (count == 1 ? "component is " : "components are ") + determined);
}

constexpr const char* kIdleMotionsAccepted =
    "idle motions accepted: the end-effector results do not depend on them; the deflections they "
    "change are null";

void leave_undetermined_null(const Problem& problem, const detail::SingularStructure& structure,
                             Result& result);

// A singular system whose null space leaves every end effector in place: over-constrained rigid
// loops (deflections unique, some wrenches not) and, where accepted, idle motions (some link
// ends' deflections not unique). The system bordered with the dependencies of its equations
// and its null vectors is regular; its solution is one member of the family, and every value
// that varies across the family is reported null.
void solve_singular_but_determined(Problem& problem, const detail::SingularStructure& structure,
                                   CaseResults& results) {
  const Index n = problem.ws.topology.unknowns();
  const MatX& redundancies = structure.redundancies;
  const MatX& idle = structure.motions;
  MatX null_vectors(n, redundancies.cols() + idle.cols());
  null_vectors << redundancies, idle;
  const detail::SparseMatrix extended =
      bordered(problem.ws.matrix, structure.left_null, null_vectors);
  detail::FactorizedSystem system(problem.options.solver);
  if (!system.factorize(extended, problem.options.singular_rcond))
    throw SingularModelError(SingularModelError::Cause::numerical,
                             "the model is singular and could not be solved",
                             structure.descriptions);
  {
    const MatX rhs = load_and_unit_wrench_rhs(problem);
    MatX padded = MatX::Zero(n + null_vectors.cols(), rhs.cols());
    padded.topRows(n) = rhs;
    double bordered_residual = 0;
    const MatX x =
        system.solve(std::move(padded), problem.options.refinement_steps, bordered_residual);
    const MatX solution = x.topRows(n);
    fill_loads_and_compliance(problem, solution,
                              detail::relative_residual(problem.ws.matrix, solution, rhs), results);
  }
  if (results.front().report.relative_residual > detail::kLoadAlongFreeMotion)
    throw SingularModelError(
        SingularModelError::Cause::free_motion,
        "the structure cannot hold its loads or preloads: they act along a free motion",
        structure.descriptions);
  for (Result& result : results) leave_undetermined_null(problem, structure, result);
}

// What varies across the family of solutions of a singular but determined system, null in one
// case's result, and the notes that say so.
void leave_undetermined_null(const Problem& problem, const detail::SingularStructure& structure,
                             Result& result) {
  const MatX& redundancies = structure.redundancies;
  const MatX& idle = structure.motions;
  const double length = detail::characteristic_length(problem.model);
  // Rows of a matrix without columns would be taken from a null pointer.
  if (redundancies.cols() > 0) {
    auto size = [&](const MatX& rows6) { return largest_six(rows6, length, false); };
    double largest = 0;
    for (int end = 0; end < problem.ws.topology.end_count(); ++end)
      largest = std::max(largest, size(redundancies.middleRows<6>(wrench_column(end))));
    auto undetermined = [&](const MatX& rows6) {
      return size(rows6) > detail::kNegligibleShare * largest;
    };
    for (std::size_t l = 0; l < problem.model.links.size(); ++l) {
      const int from = 2 * static_cast<int>(l);
      if (undetermined(redundancies.middleRows<6>(wrench_column(from))))
        result.links[l].from.wrench.reset();
      if (undetermined(redundancies.middleRows<6>(wrench_column(from + 1))))
        result.links[l].to.wrench.reset();
    }
    for (const auto& group : problem.ws.topology.groups) {
      if (group.kind == detail::ConnectionGroup::Kind::joint &&
          undetermined(redundancies.middleRows<6>(wrench_column(group.ends.front())))) {
        auto& joint = result.joints[static_cast<std::size_t>(group.source)];
        if (joint.wrench)
          note_determined_components(
              "the wrench of joint '" +
                  problem.model.joints[static_cast<std::size_t>(group.source)].name + "'",
              *joint.wrench, redundancies.middleRows<6>(wrench_column(group.ends.front())), length,
              detail::kNegligibleShare * largest, result.report.notes);
        joint.wrench.reset();
        joint.effort.reset();
      } else if (group.kind == detail::ConnectionGroup::Kind::support) {
        MatX sum = MatX::Zero(6, redundancies.cols());
        for (int end : group.ends) sum += redundancies.middleRows<6>(wrench_column(end));
        auto& support = result.supports[static_cast<std::size_t>(group.source)];
        if (!undetermined(sum)) continue;
        if (support.reaction)
          note_determined_components(
              "the reaction of support '" +
                  problem.model.supports[static_cast<std::size_t>(group.source)].name + "'",
              *support.reaction, sum, length, detail::kNegligibleShare * largest,
              result.report.notes);
        support.reaction.reset();
      }
    }
  }
  if (idle.cols() > 0) {
    double largest_motion = 0;
    for (int end = 0; end < problem.ws.topology.end_count(); ++end)
      largest_motion = std::max(
          largest_motion, largest_six(idle.middleRows<6>(deflection_column(end)), length, true));
    std::vector<bool> moving(static_cast<std::size_t>(problem.ws.topology.end_count()));
    for (int end = 0; end < problem.ws.topology.end_count(); ++end)
      moving[static_cast<std::size_t>(end)] =
          largest_six(idle.middleRows<6>(deflection_column(end)), length, true) >
          detail::kNegligibleShare * largest_motion;
    for (std::size_t l = 0; l < problem.model.links.size(); ++l) {
      if (moving[2 * l]) result.links[l].from.deflection.reset();
      if (moving[2 * l + 1]) result.links[l].to.deflection.reset();
    }
    for (const auto& group : problem.ws.topology.groups)
      if (group.kind == detail::ConnectionGroup::Kind::joint)
        for (int end : group.ends)
          if (moving[static_cast<std::size_t>(end)])
            result.joints[static_cast<std::size_t>(group.source)].relative_deflection.reset();
    result.report.notes.push_back(kIdleMotionsAccepted);
  }
  for (std::string d : structure.descriptions) {
    for (const auto& [hint, accepted] :
         {std::pair{detail::kAcceptIdleMotionHint, detail::kAcceptedIdleMotionTag},
          std::pair{detail::kAcceptIdleMotionsHint, detail::kAcceptedIdleMotionsTag}})
      if (const auto at = d.find(hint); at != std::string::npos)
        d.replace(at, hint.size(), accepted);
    result.report.notes.push_back(std::move(d));
  }
  check_accuracy(problem.options, result);
}

// Eq. (21) without an inverse: Δt_e becomes prescribed and W_ext,e unknown. Regular where
// prescribing Δt_e removes every free motion.
std::optional<Mat6> prescribed_deflection_stiffness(const Problem& problem, int end,
                                                    double& residual, double& rcond) {
  const Index n = problem.ws.topology.unknowns();
  MatX columns = -problem.unit_wrench_rhs(end);
  MatX rows = MatX::Zero(n, 6);
  rows.middleRows<6>(deflection_column(end)).setIdentity();
  const detail::SparseMatrix augmented = bordered(problem.ws.matrix, columns, rows);
  detail::FactorizedSystem system(problem.options.solver);
  MatX rhs = MatX::Zero(n + 6, 6);
  rhs.bottomRows<6>().setIdentity();
  if (system.factorize(augmented, problem.options.singular_rcond)) {
    rcond = system.reciprocal_condition();
    const MatX x = system.solve(rhs, problem.options.refinement_steps, residual);
    return Mat6(x.bottomRows<6>());
  }
  // Still singular: acceptable only where what remains are over-constrained loops, whose
  // null vectors change no deflection and not the end effector's wrench. Bordering with them
  // picks one member of the family of internal wrenches; the stiffness is the same for all.
  const auto spaces = detail::null_spaces(augmented);
  if (!spaces || spaces->right_equilibrated.cols() == 0) return std::nullopt;
  const MatX& null_basis = spaces->right_equilibrated;
  for (int e = 0; e < problem.ws.topology.end_count(); ++e)
    if (null_basis.middleRows<6>(deflection_column(e)).cwiseAbs().maxCoeff() >
        detail::kNegligibleNullEntry)
      return std::nullopt;
  if (null_basis.bottomRows<6>().cwiseAbs().maxCoeff() > detail::kNegligibleNullEntry)
    return std::nullopt;
  const detail::SparseMatrix regular = bordered(augmented, spaces->left, spaces->right());
  detail::FactorizedSystem bordered_system(problem.options.solver);
  if (!bordered_system.factorize(regular, problem.options.singular_rcond)) return std::nullopt;
  rcond = bordered_system.reciprocal_condition();
  MatX padded = MatX::Zero(regular.rows(), 6);
  padded.topRows(n + 6) = rhs;
  const MatX x =
      bordered_system.solve(std::move(padded), problem.options.refinement_steps, residual);
  return Mat6(x.middleRows<6>(n));
}

// "the model is a mechanism with 3 free motions", the count where the analysis found it.
std::string mechanism(const detail::SingularStructure& structure) {
  const Index count = structure.motions.cols();
  if (!structure.analysed || count == 0) return "the model is a mechanism";
  return message("the model is a mechanism with ", count,
                 count == 1 ? " free motion" : " free motions");
}

void solve_free_structure(Problem& problem, const detail::SingularStructure& structure,
                          CaseResults& results) {
  Result& result = results.front();
  const std::vector<std::string>& details = structure.descriptions;
  const bool one = structure.motions.cols() == 1;
  if (problem.loaded)
    throw SingularModelError(SingularModelError::Cause::free_motion,
                             mechanism(structure) +
                                 " and carries loads or preloads, which a mechanism cannot hold "
                                 "(only an unloaded one is solved)",
                             details);
  bool any = false;
  for (std::size_t e = 0; e < problem.model.end_effectors.size(); ++e) {
    double residual = 0, rcond = 0;
    auto stiffness = prescribed_deflection_stiffness(problem, problem.ws.topology.effector_ends[e],
                                                     residual, rcond);
    if (!stiffness) continue;
    any = true;
    result.end_effectors[e].stiffness = stiffness;
    result.report.relative_residual = std::max(result.report.relative_residual, residual);
    result.report.reciprocal_condition = std::max(result.report.reciprocal_condition, rcond);
  }
  if (!any)
    throw SingularModelError(SingularModelError::Cause::free_motion,
                             mechanism(structure) + (one ? ", and no end effector stops it"
                                                         : ", and no end effector stops them"),
                             details);
  result.report.notes.push_back(
      "the structure can move freely; only the stiffness of the end effectors that stop every free "
      "motion "
      "is reported, everything else is null");
  if (problem.model.supports.empty())
    result.report.warnings.push_back(
        "the model has no support: nothing holds it, so the stiffness of its end effectors "
        "is zero (it measures only what holds the end effector against the rest of the "
        "model); add a support under `supports:`");
  for (const auto& d : details) result.report.notes.push_back(d);
  check_accuracy(problem.options, result);
  for (std::size_t c = 1; c < results.size(); ++c) {
    results[c].report = result.report;
    for (std::size_t e = 0; e < result.end_effectors.size(); ++e)
      results[c].end_effectors[e].stiffness = result.end_effectors[e].stiffness;
  }
}

}  // namespace

SystemSize check(const Model& model) {
  Workspace workspace(model);
  auto& ws = detail::WorkspaceAccess::impl(workspace);
  detail::Assembler& assembler = ws.pattern(ws.recorded_blocks);
  assembler.fill(ws.recorded_blocks, ws.matrix);
  SystemSize size = assembler.size();
  size.nonzeros = count_nonzero_values(ws.matrix);
  return size;
}

namespace {

// What holding the rods' spins left out of a result: the spin moves the rods' ends, so their
// deflections and their ball joints' relative deflections are not determined, as an accepted
// idle motion's are (solve_singular_but_determined); a support reports no relative deflection.
void report_held_spins(const Model& model, const detail::Topology& topology,
                       const std::vector<detail::SpinLock>& locks, Result& result) {
  std::string rods;
  for (const detail::SpinLock& lock : locks) {
    auto& link = result.links[static_cast<std::size_t>(lock.rod)];
    link.from.deflection.reset();
    link.to.deflection.reset();
    for (int g : {lock.group, lock.other_group}) {
      const detail::ConnectionGroup& group = topology.groups[static_cast<std::size_t>(g)];
      if (group.kind == detail::ConnectionGroup::Kind::joint)
        result.joints[static_cast<std::size_t>(group.source)].relative_deflection.reset();
    }
    rods +=
        (rods.empty() ? "'" : ", '") + model.links[static_cast<std::size_t>(lock.rod)].name + "'";
  }
  // Once, where idle motions other than the spins were accepted too.
  if (std::find(result.report.notes.begin(), result.report.notes.end(), kIdleMotionsAccepted) ==
      result.report.notes.end())
    result.report.notes.push_back(kIdleMotionsAccepted);
  const bool one = locks.size() == 1;
  result.report.notes.push_back(
      message(one ? "link " : "links ", rods, one ? " spins" : " spin",
              " freely about the line through the ball joints at ", one ? "its" : "their",
              one ? " ends (an idle motion)" : " ends (an idle motion each)"));
}

// The solve with one set of blocks: the model's own, or those with the rods' spins held.
struct CaseSolve {
  CaseResults results;
  std::vector<bool> with_state;          // per result: a load case (else the self-weight alone)
  std::vector<detail::CaseLoads> cases;  // case_loads(model, topology), computed once
};

CaseSolve solve_in(Workspace::Impl& ws, const Model& model, const SolveOptions& options,
                   detail::ResultScope scope, bool topology_known);

CaseSolve solve_validated(Workspace& workspace, const Model& model, const SolveOptions& options,
                          detail::ResultScope scope, bool topology_known) {
  Workspace::Impl& ws = detail::WorkspaceAccess::impl(workspace);
  const bool accept_idle = options.accept_idle_motions || model.options.accept_idle_motions;
  if (accept_idle && options.solver == SolverKind::automatic && ws.spin_locked) {
    CaseSolve solved = solve_in(*ws.spin_locked, model, options, scope, topology_known);
    for (Result& result : solved.results)
      report_held_spins(model, ws.topology, ws.spin_locked->spin_locks, result);
    return solved;
  }
  return solve_in(ws, model, options, scope, topology_known);
}

CaseSolve solve_in(Workspace::Impl& ws, const Model& model, const SolveOptions& options,
                   detail::ResultScope scope, bool topology_known) {
  CaseSolve solved;
  Problem problem(model, ws, options, scope, topology_known, solved.cases);
  CaseResults& results = solved.results;
  results.reserve(problem.cases.size());
  results.push_back(
      empty_result(model, ws, scope));  // a large model's result is copied only per case
  while (results.size() < problem.cases.size()) results.push_back(results.front());
  for (std::size_t c = 0; c < problem.cases.size(); ++c) {
    results[c].load_case = problem.cases[c].name;
    solved.with_state.push_back(problem.cases[c].with_state);
  }
  if (options.solver == SolverKind::automatic && ws.tree && detail::passes_tree(problem.blocks) &&
      solve_without_factorising(problem, BlockSolve::tree, results))
    return solved;
  if (options.solver == SolverKind::automatic && ws.frame &&
      solve_without_factorising(problem, BlockSolve::frame, results))
    return solved;
  detail::Assembler& assembler = ws.pattern(problem.reference_blocks());
  if (!ws.system || ws.solver_kind != options.solver) {
    auto system = std::make_unique<detail::FactorizedSystem>(options.solver);
    if (!topology_known) {
      // The reference first; whether it is regular does not matter here. Installed only once
      // factorised, so that a throw leaves the next solve to try the reference again.
      assembler.fill(ws.recorded_blocks, ws.matrix);
      system->factorize(ws.matrix, options.singular_rcond);
    }
    ws.system = std::move(system);
    ws.solver_kind = options.solver;
  }
  assembler.fill(problem.blocks, ws.matrix);
  SystemSize size = assembler.size();
  size.nonzeros = count_nonzero_values(ws.matrix);
  const bool regular = ws.system->factorize(ws.matrix, options.singular_rcond);
  for (Result& result : results) {
    result.system = size;
    result.report.solver = solver_used_from_string(ws.system->solver_name())
                               .value_or(SolverUsed::none);  // `auto` has chosen by now
    result.report.reciprocal_condition = ws.system->reciprocal_condition();
  }
  if (regular) {
    solve_regular(problem, results);
    return solved;
  }
  const auto structure = detail::analyse_singular_structure(model, ws.topology, ws.matrix);
  const bool accept_idle = options.accept_idle_motions || model.options.accept_idle_motions;
  const bool determined = structure.motions.cols() == 0 ||
                          (accept_idle && !moves_any_end_effector(problem, structure.motions));
  if (structure.analysed && structure.motions.cols() + structure.redundancies.cols() > 0 &&
      determined)
    solve_singular_but_determined(problem, structure, results);
  else
    solve_free_structure(problem, structure, results);
  return solved;
}

// What every solve adds to its result, however it was solved.
void finish_result(const Model& model, const detail::ModelIndex& index, const SolveOptions& options,
                   detail::ResultScope scope, Result& result) {
  result.model_size = detail::characteristic_length(model);
  if (scope == detail::ResultScope::everything) result.parameters = model.parameters;
  detail::add_plausibility_warnings(model, index, result);
  if (!options.direction) return;
  for (EndEffectorResult& e : result.end_effectors)
    if (e.compliance) e.along_direction = directional_stiffness(*e.compliance, *options.direction);
}

// What the reader noticed in the model (Model::warnings) comes first among the warnings.
void add_model_warnings(const Model& model, Result& result) {
  std::vector<std::string> warnings;
  for (const Diagnostic& w : model.warnings) warnings.push_back(w.to_string());
  result.report.warnings.insert(result.report.warnings.begin(), warnings.begin(), warnings.end());
}

// Each result of an end effector with axes of its own, turned into them too.
void add_results_in_own_axes(const Model& model, Result& result) {
  for (std::size_t e = 0; e < model.end_effectors.size(); ++e) {
    if (!model.end_effectors[e].axes) continue;
    EndEffectorResult& r = result.end_effectors[e];
    EndEffectorResult::InAxes in{*model.end_effectors[e].axes, {}, {}, {}, {}};
    Mat6 turn = Mat6::Zero();  // own-axes components into world components
    turn.topLeftCorner<3, 3>() = in.axes;
    turn.bottomRightCorner<3, 3>() = in.axes;
    if (r.compliance) in.compliance = turn.transpose() * *r.compliance * turn;
    if (r.stiffness) in.stiffness = turn.transpose() * *r.stiffness * turn;
    if (r.deflection) in.deflection = turn.transpose() * *r.deflection;
    if (r.deflection_gravity) in.deflection_gravity = turn.transpose() * *r.deflection_gravity;
    r.in_own_axes = in;
  }
}

void add_gravity_deflections(const Result& weight, Result& result) {
  for (std::size_t e = 0; e < result.end_effectors.size(); ++e)
    result.end_effectors[e].deflection_gravity = weight.end_effectors[e].deflection;
}

// In the loaded mode (SolveOptions::mode, else the model's own), the loaded result in place of
// the linear one, which it keeps as Result::linear (docs/theory.md §15).
Result in_analysis_mode(Workspace::Impl& ws, const Model& model, const SolveOptions& options,
                        const std::vector<detail::CaseLoads>& cases, Result result) {
  if (options.mode.value_or(model.options.mode) != AnalysisMode::loaded) return result;
  const int load_steps = model.options.load_steps.value_or(detail::kDefaultLoadSteps);
  // The linear results of a case, without the other cases, become its loaded result's `linear`.
  auto loaded_case = [&](Result linear, const detail::CaseLoads& loads) {
    linear.load_cases.clear();
    if (!ws.loaded_tangent || ws.loaded_tangent->kind() != options.solver)
      ws.loaded_tangent = std::make_unique<detail::LoadedTangent>(options.solver);
    Result loaded =
        detail::loaded_result(model, ws.topology, options, linear, loads.applied_at_ends(),
                              load_steps, *ws.loaded_tangent, loads.link_loads);
    detail::add_loaded_internal_forces(model, ws.topology, loads, loaded);
    add_results_in_own_axes(model, loaded);
    if (options.direction)
      for (EndEffectorResult& e : loaded.end_effectors)
        if (e.compliance)
          e.along_direction = directional_stiffness(*e.compliance, *options.direction);
    return loaded;
  };
  const bool unnamed = detail::has_unnamed_case(model);
  std::vector<Result> named;
  named.reserve(result.load_cases.size());
  for (std::size_t c = 0; c < result.load_cases.size(); ++c)
    named.push_back(loaded_case(result.load_cases[c], cases[c + (unnamed ? 1 : 0)]));
  Result top = unnamed ? loaded_case(result, cases.front()) : named.front();
  top.load_cases = std::move(named);
  return top;
}

// A model of issue 22's loads (load cases, loads along links, gravity, settlements) or of the
// loaded mode gets its critical load factors without asking: its result file's contract has
// them (model-format.md). Others only where asked, so that their results stay as they were and
// their solves pay nothing for it.
bool always_finds_critical_load(const Model& model, const SolveOptions& options) {
  return !model.load_cases.empty() || !model.link_loads.empty() || model.gravity ||
         options.mode.value_or(model.options.mode) == AnalysisMode::loaded ||
         std::any_of(model.supports.begin(), model.supports.end(),
                     [](const Support& s) { return s.displacement.has_value(); });
}

// SolveOptions::critical_load where set, else the result file's contract.
bool finds_critical_load(const Model& model, const SolveOptions& options) {
  return options.critical_load.value_or(always_finds_critical_load(model, options));
}

// The critical load factors of the result's load cases (analysis/critical_load.hpp), where
// asked, with the blocks the solve used (the rods' spins held where it held them): the very
// blocks, where the workspace kept them (Problem's destructor), and its tree order.
void add_critical_load(Workspace& workspace, const Model& model, const SolveOptions& options,
                       const std::vector<detail::CaseLoads>& cases, Result& result) {
  Workspace::Impl& ws = detail::WorkspaceAccess::impl(workspace);
  if (ws.skip_critical_loads) return;
  if (!finds_critical_load(model, options)) return;
  const bool accept_idle = options.accept_idle_motions || model.options.accept_idle_motions;
  Workspace::Impl& used = accept_idle && options.solver == SolverKind::automatic && ws.spin_locked
                              ? *ws.spin_locked
                              : ws;
  detail::CriticalLoadReuse reuse;
  if (used.pose_blocks.size() ==
      static_cast<std::size_t>(used.topology.link_count) + used.topology.groups.size())
    reuse.blocks = &used.pose_blocks;
  if (used.tree) reuse.tree = &*used.tree;
  reuse.scratch = &used.critical_load_scratch;
  if (used.tree && result.report.solver == SolverUsed::tree_with_cuts)
    reuse.cut_system = &used.tree_scratch;
  detail::add_critical_loads(model, used.topology, used.spin_locks, options, cases, result, reuse);
}

// The results of the solved cases as a Result: the robot's self-weight column gives the unnamed
// case's deflection_gravity; every case gets what a result reports beside (results in own axes,
// the model's warnings, plausibility); the top level is the unnamed case, or a copy of the first
// named case where there is no unnamed one, and holds every named case's results.
Result results_of_cases(const Model& model, const detail::ModelIndex& index,
                        const SolveOptions& options, detail::ResultScope scope, CaseSolve solved) {
  CaseResults& results = solved.results;
  if (!solved.with_state.back()) {
    add_gravity_deflections(results.back(), results.front());
    results.pop_back();
  }
  for (Result& result : results) {
    if (scope == detail::ResultScope::everything) add_results_in_own_axes(model, result);
    add_model_warnings(model, result);
    finish_result(model, index, options, scope, result);
  }
  const bool unnamed = detail::has_unnamed_case(model);
  Result top = unnamed ? std::move(results.front()) : results.front();
  top.load_cases.reserve(results.size() - (unnamed ? 1 : 0));
  for (std::size_t c = unnamed ? 1 : 0; c < results.size(); ++c)
    top.load_cases.push_back(std::move(results[c]));
  return top;
}

// The solve of a checked model on its workspace: every load case's results from one
// factorisation (the robot's self-weight alone among them), and what every result reports
// beside.
Result solve_checked(Workspace& workspace, const Model& model, const detail::ModelIndex& index,
                     const SolveOptions& options, bool topology_known = false) {
  CaseSolve solved =
      solve_validated(workspace, model, options, detail::ResultScope::everything, topology_known);
  const std::vector<detail::CaseLoads> cases = std::move(solved.cases);
  Result result =
      results_of_cases(model, index, options, detail::ResultScope::everything, std::move(solved));
  add_critical_load(workspace, model, options, cases, result);
  return in_analysis_mode(detail::WorkspaceAccess::impl(workspace), model, options, cases,
                          std::move(result));
}

}  // namespace

void detail::skip_critical_loads(Workspace& workspace) {
  WorkspaceAccess::impl(workspace).skip_critical_loads = true;
}

Result solve(const Model& model, const SolveOptions& options) {
  options.validate();
  const detail::ModelIndex index(model);
  Workspace workspace = detail::WorkspaceAccess::of(model, index);  // validates the model
  return solve_checked(workspace, model, index, options, true);
}

namespace {
// The member of a structure's workspace at `values`, its values checked.
const Model& posed_member(Workspace::Impl& ws, std::span<const double> values) {
  if (!ws.structure)
    throw UsageError(
        "solving values needs the workspace of their structure: build it as Workspace(structure)");
  const Structure& structure = *ws.structure;
  structure.write_values(values, ws.member);
  auto defects = detail::find_value_defects(ws.member, structure.impl().index);
  if (!defects.empty()) throw InputError(std::move(defects));
  return ws.member;
}
}  // namespace

Result solve(Workspace& workspace, std::span<const double> values, const SolveOptions& options) {
  options.validate();
  Workspace::Impl& ws = detail::WorkspaceAccess::impl(workspace);
  const Model& model = posed_member(ws, values);
  return solve_checked(workspace, model, ws.structure->impl().index, options);
}

Result detail::solve_sweep_row(Workspace& workspace, std::span<const double> values,
                               const SolveOptions& options) {
  Workspace::Impl& ws = detail::WorkspaceAccess::impl(workspace);
  const Model& model = posed_member(ws, values);
  const detail::ModelIndex& index = ws.structure->impl().index;
  // The whole solve where the model's results have more than a sweep row's (the loaded mode,
  // issue 22's loads) or the factor is asked for; the workspace skips the factor itself.
  if (options.critical_load == true || always_finds_critical_load(model, options))
    return solve_checked(workspace, model, index, options);
  CaseSolve solved = solve_validated(workspace, model, options, ResultScope::sweep_row, false);
  return results_of_cases(model, index, options, ResultScope::sweep_row, std::move(solved));
}

Result solve(const Structure& structure, Workspace& workspace, std::span<const double> values,
             const SolveOptions& options) {
  const auto& own_structure = detail::WorkspaceAccess::impl(workspace).structure;
  if (!own_structure || !(*own_structure == structure))
    throw UsageError(
        "the workspace was built for another structure; build it as Workspace(structure)");
  return solve(workspace, values, options);
}

Result solve(Workspace& workspace, const Model& model, const SolveOptions& options) {
  options.validate();
  const detail::ModelIndex index(model);
  detail::validate(model, index);
  if (!(detail::build_topology(model, index) == detail::WorkspaceAccess::impl(workspace).topology))
    detail::throw_topology_changed();
  return solve_checked(workspace, model, index, options);
}

}  // namespace stiffmsa

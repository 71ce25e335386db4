// stiffmsa benchmarks (Google Benchmark). Names are <model>/<what>[/<solver>][/<size>]:
//
//   <robot>/public_solve/S        stiffmsa::solve(Workspace&, pose): one pose, everything the
//                                 public API does (the pattern analysis is reused)
//   <robot>/public_solve_refine0/S  the same with SolveOptions::refinement_steps = 0
//   <robot>/stage:validate        stiffmsa::validate (redone by every public solve)
//   <robot>/stage:topology        detail::build_topology (redone by every public solve)
//   <robot>/stage:make_blocks     detail::make_blocks: element blocks of the pose
//   <robot>/stage:fill            Assembler::fill: values into the recorded pattern
//   <robot>/stage:factorize/S     FactorizedSystem::factorize, numeric only (pattern analysed
//                                 before the timing): equilibration + LU + condition estimate
//   <robot>/stage:solve/S         FactorizedSystem::solve of the 1 + 6 right-hand sides with
//                                 the default 2 refinement steps
//   <robot>/part:...              pieces of those two stages, to find where the time goes
//   <robot>/pipeline/S            the internal stages back to back, per pose: make_blocks,
//                                 fill, right-hand sides, factorize, solve, K = C⁻¹
//   <robot>/pipeline/tree         robots `auto` solves on the tree (the serial ones; the
//                                 tripteron with cuts): make_blocks, the tree solve, its
//                                 block-by-block check, K = C⁻¹ (what `auto` does)
//   <robot>/stage:tree_solve      detail::tree_solve of the 1 + 6 load cases
//   <robot>/stage:tree_check      detail::check_block_by_block: residual of every block
//   <robot>/dense_lu              the same pipeline with Eigen::PartialPivLU on the assembled
//                                 system as a dense matrix: the naive baseline
//   urdf_6axis/pose_from_joint_angles  a URDF six-axis robot (examples/robots/six-axis.urdf, its
//                                 upper arm and forearm flexible as in the 6-axis example)
//                                 posed from six joint angles: the family's builder (forward
//                                 kinematics, numbers written into the member) and
//                                 stiffmsa::solve(Workspace&, member), per pose
//   urdf_6axis/build              the builder alone
//   6axis/vjm_floor               closed-form VJM compliance C = Σ J_i·k_i⁻¹·J_iᵀ and K = C⁻¹
//   chain/solve/S/N               stiffmsa::solve(model) from scratch, N beam links
//   chain/resolve/S/N             stiffmsa::solve(Workspace&, model), workspace reused (N ≤ 10 000)
//   frame/solve/S, frame/resolve/S  the same for a space frame of 960 beams
//   frame/dense_ldlt_of_K         the condensed stiffness K of the same frame (6 unknowns per
//                                 free node) stored dense and LDLᵀ-factorised entry by entry
//                                 (Eigen's LDLT), then solved for the loads: the dense method
//                                 the issue supposed of Frame3DD, which in fact skips the zeros
//                                 ahead of each column's first entry (a profile LDLᵀ) and is
//                                 measured itself by bench/frame3dd_compare.py; counter u_diff =
//                                 largest node deflection difference from the library's,
//                                 relative to the largest
//   <model>/klu_fill/O/tol:T      KLU's bare numeric factorisation of the equilibrated matrix
//                                 with ordering O (amd: the library's, colamd) and pivot
//                                 tolerance T: 1 (the library's) or 0.001 (KLU's default);
//                                 counters: entries of L + U, and the error of x for A·x = A·1
//
// Every robot benchmark walks through 16 poses of the example (bench_models.hpp), so each
// iteration is one pose. Counters: allocs = heap allocations per iteration; c_diff,
// err_vs_sparse, msa_vs_vjm, tip_err = scaled entry differences of 6×6 compliances (see
// scaled_difference) against the default solver (auto since the tuning, sparse_lu before), the
// public solve, the closed-form VJM and the closed-form cantilever; residual =
// SolveReport::relative_residual.
#include <benchmark/benchmark.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <map>
#include <memory>

#include "alloc_counter.hpp"
#include "analysis/cartesian.hpp"
#include "assembly/assembler.hpp"
#include "assembly/topology.hpp"
#include "bench_models.hpp"
#include "solver/frame_solver.hpp"
#include "solver/sparse_solver.hpp"
#include "solver/tree_solver.hpp"
#include "stiffmsa/config.hpp"
#if STIFFMSA_HAVE_SUITESPARSE
#include <klu.h>
#endif

namespace {

using namespace stiffmsa;
using detail::Index;
using detail::SparseMatrix;

constexpr int kPoses = 16;
constexpr double kSingularRcond = SolveOptions{}.singular_rcond;
constexpr int kRefinementSteps = SolveOptions{}.refinement_steps;

std::vector<SolverKind> available_solvers() {
  std::vector<SolverKind> kinds;
  for (SolverKind k :
       {SolverKind::automatic, SolverKind::sparse_lu, SolverKind::umfpack, SolverKind::klu})
    if (solver_available(k)) kinds.push_back(k);
  return kinds;
}

SolveOptions options_for(SolverKind kind, int refinement_steps = kRefinementSteps) {
  SolveOptions options;
  options.solver = kind;
  options.refinement_steps = refinement_steps;
  return options;
}

// Heap allocations per iteration, from the counts before and after the timing loop.
void count_allocations(benchmark::State& state, std::uint64_t before) {
  state.counters["allocs"] = benchmark::Counter(
      static_cast<double>(bench::allocation_count() - before), benchmark::Counter::kAvgIterations);
}

// ---- one robot, prepared once --------------------------------------------------------------

// Right-hand sides as the analysis builds them: the loads (and preloads), then six unit
// wrenches at every end effector.
MatX right_hand_sides(const Model& model, const detail::Topology& topology,
                      const detail::Blocks& blocks, const detail::Assembler& assembler) {
  std::vector<std::pair<int, Vec6>> loads;
  for (std::size_t i = 0; i < model.loads.size(); ++i)
    loads.emplace_back(topology.load_ends[i], model.loads[i].wrench);
  const Index n = topology.unknowns();
  MatX b = MatX::Zero(n, 1 + 6 * static_cast<Index>(topology.effector_ends.size()));
  b.col(0) = assembler.right_hand_side(blocks, topology, loads, true);
  for (std::size_t e = 0; e < topology.effector_ends.size(); ++e)
    for (int c = 0; c < 6; ++c) {
      VecX column = VecX::Zero(n);
      assembler.add_wrench(blocks, topology, topology.effector_ends[e], Vec6::Unit(c), column);
      b.col(1 + 6 * static_cast<Index>(e) + c) = column;
    }
  return b;
}

// Compliance and stiffness of the first end effector from the solutions.
struct Cartesian {
  Mat6 compliance;
  std::optional<Mat6> stiffness;
};
Cartesian cartesian(const MatX& x, const detail::Topology& topology, double length) {
  const Mat6 c = x.block<6, 6>(detail::deflection_column(topology.effector_ends.front()), 1);
  return {c, detail::cartesian_stiffness(c, length, SolveOptions{}.warn_condition).stiffness};
}

struct Robot {
  std::string name;
  std::vector<Model> poses;
  detail::Topology topology;
  std::unique_ptr<detail::Assembler> assembler;
  std::vector<detail::Blocks> blocks;     // per pose
  std::vector<SparseMatrix> matrices;     // per pose, assembled
  std::vector<MatX> rhs;                  // per pose
  std::vector<Mat6> compliance;           // per pose, from the public solve: the reference
  double length = 1;                      // detail::characteristic_length
  std::optional<detail::TreeOrder> tree;  // where `auto` takes the tree solve

  Robot(std::string robot_name, std::vector<Model> robot_poses)
      : name(std::move(robot_name)), poses(std::move(robot_poses)) {
    topology = detail::build_topology(poses.front());
    assembler = std::make_unique<detail::Assembler>(detail::make_blocks(poses.front(), topology),
                                                    topology.unknowns());
    length = detail::characteristic_length(poses.front());
    Workspace workspace(poses.front());
    for (const Model& pose : poses) {
      blocks.push_back(detail::make_blocks(pose, topology));
      matrices.emplace_back();
      assembler->fill(blocks.back(), matrices.back());
      rhs.push_back(right_hand_sides(pose, topology, blocks.back(), *assembler));
      const Result result = solve(workspace, pose);
      if (!result.report.warnings.empty() || !result.end_effectors.front().stiffness)
        throw std::runtime_error("bench: a pose of " + name + " is not a healthy regular solve");
      compliance.push_back(*result.end_effectors.front().compliance);
    }
    // The robots `auto` solves on the tree, with or without cuts (not the Gough–Stewart platform:
    // more cut unknowns than the cut solve takes).
    detail::TreeScratch scratch;
    if (auto order = detail::tree_order(topology);
        order && detail::passes_tree(blocks.front()) &&
        detail::tree_solve(blocks.front(), topology, *order,
                           detail::load_cases(poses.front(), topology),
                           1 / SolveOptions{}.warn_condition, scratch))
      tree = std::move(order);
  }
  std::size_t pose_count() const { return poses.size(); }
};

// ---- the public API ----------------------------------------------------------------------

void public_solve(benchmark::State& state, const Robot& robot, SolverKind kind,
                  int refinement_steps) {
  Workspace workspace(robot.poses.front());
  const SolveOptions options = options_for(kind, refinement_steps);
  // Accuracy, outside the timing: every pose against the default solver's compliance, and the
  // largest relative residual.
  double difference = 0, residual = 0;
  for (std::size_t p = 0; p < robot.pose_count(); ++p) {
    const Result result = solve(workspace, robot.poses[p], options);
    difference = std::max(
        difference,
        bench::scaled_difference(*result.end_effectors.front().compliance, robot.compliance[p]));
    residual = std::max(residual, result.report.relative_residual);
  }
  std::size_t p = 0;
  const auto before = bench::allocation_count();
  for (auto _ : state) {
    Result result = solve(workspace, robot.poses[p], options);
    benchmark::DoNotOptimize(result);
    p = (p + 1) % robot.pose_count();
  }
  count_allocations(state, before);
  state.counters["unknowns"] = static_cast<double>(robot.topology.unknowns());
  state.counters["nnz"] = static_cast<double>(robot.matrices.front().nonZeros());
  state.counters["c_diff"] = difference;
  state.counters["residual"] = residual;
}

// ---- robots from URDF files, posed in joint space -----------------------------------------

// The URDF six-axis robot with every joint a parameter; read as if it stood beside the URDF.
constexpr const char* kUrdfJointSpace = R"(format: stiffmsa/1
parameters: {q1: 0, q2: 0.3, q3: 0.4, q4: 0, q5: 0.9, q6: 0}
materials:
  steel: {E: 2.1e11, nu: 0.3}
  aluminium: {E: 7.0e10, nu: 0.33}
robot:
  urdf: six-axis.urdf
  positions: {joint_1: q1, joint_2: q2, joint_3: q3, joint_4: q4, joint_5: q5, joint_6: q6}
  joints:
    joint_1: {stiffness: 2.0e6}
    joint_2: {stiffness: 3.5e6}
    joint_3: {stiffness: 1.6e6}
    joint_4: {stiffness: 4.0e5}
    joint_5: {stiffness: 3.0e5}
    joint_6: {stiffness: 1.5e5}
  links:
    link_2: {material: steel, section: {shape: rect_tube, b: 0.12, h: 0.18, t: 0.008}}
    link_4: {material: aluminium, section: {shape: tube, D: 0.13, t: 0.008}}
end_effectors:
  tcp: {frame: tool0, offset: [0, 0, 0.15]}
loads:
  - {frame: tool0, offset: [0, 0, 0.15], wrench: [300, -200, -600, 0, 0, 10]}
)";

// 16 poses about the file's defaults, each joint turned as the 6-axis benchmark turns it.
std::vector<std::vector<double>> urdf_joint_poses(const ModelFamily& family) {
  const double amplitude[] = {0.3, 0.2, 0.2, 0.3, 0.2, 0.3};
  std::vector<std::vector<double>> poses;
  for (int p = 0; p < kPoses; ++p) {
    std::vector<double> q = family.default_values();
    for (std::size_t k = 0; k < q.size(); ++k)
      q[k] += amplitude[k] *
              std::sin(2 * 3.14159265358979323846 * p / kPoses + 1.3 * static_cast<double>(k));
    poses.push_back(std::move(q));
  }
  return poses;
}

void urdf_pose(benchmark::State& state, bool solve_too) {
  const ModelFamily family = parse_model_family(
      kUrdfJointSpace, std::string(STIFFMSA_EXAMPLES_DIR) + "/robots/joint-space.yaml");
  const auto poses = urdf_joint_poses(family);
  const Structure structure = family.structure();
  ModelFamily::ValueWriter write = family.make_writer(structure);
  std::vector<double> values(structure.value_count());
  std::vector<Diagnostic> warnings;
  Workspace workspace(structure);
  std::size_t p = 0;
  for (auto _ : state) {
    write(poses[p], values, warnings);
    if (solve_too) {
      Result result = solve(workspace, values);
      benchmark::DoNotOptimize(result);
    }
    benchmark::DoNotOptimize(values);
    p = (p + 1) % poses.size();
  }
  state.counters["unknowns"] = static_cast<double>(workspace.size().unknowns);
}

// ---- the internal stages -------------------------------------------------------------------

void stage_topology(benchmark::State& state, const Robot& robot) {
  std::size_t p = 0;
  const auto before = bench::allocation_count();
  for (auto _ : state) {
    detail::Topology topology = detail::build_topology(robot.poses[p]);
    benchmark::DoNotOptimize(topology);
    p = (p + 1) % robot.pose_count();
  }
  count_allocations(state, before);
}

void stage_validate(benchmark::State& state, const Robot& robot) {
  std::size_t p = 0;
  const auto before = bench::allocation_count();
  for (auto _ : state) {
    validate(robot.poses[p]);
    p = (p + 1) % robot.pose_count();
  }
  count_allocations(state, before);
}

void stage_make_blocks(benchmark::State& state, const Robot& robot) {
  std::size_t p = 0;
  const auto before = bench::allocation_count();
  for (auto _ : state) {
    detail::Blocks blocks = detail::make_blocks(robot.poses[p], robot.topology);
    benchmark::DoNotOptimize(blocks);
    p = (p + 1) % robot.pose_count();
  }
  count_allocations(state, before);
}

void stage_fill(benchmark::State& state, const Robot& robot) {
  SparseMatrix matrix;
  robot.assembler->fill(robot.blocks.front(), matrix);
  std::size_t p = 0;
  const auto before = bench::allocation_count();
  for (auto _ : state) {
    robot.assembler->fill(robot.blocks[p], matrix);
    benchmark::DoNotOptimize(matrix.valuePtr());
    p = (p + 1) % robot.pose_count();
  }
  count_allocations(state, before);
}

void stage_factorize(benchmark::State& state, const Robot& robot, SolverKind kind) {
  detail::FactorizedSystem system(kind);
  system.factorize(robot.matrices.front(), kSingularRcond);  // analyses the pattern
  std::size_t p = 0;
  const auto before = bench::allocation_count();
  for (auto _ : state) {
    benchmark::DoNotOptimize(system.factorize(robot.matrices[p], kSingularRcond));
    p = (p + 1) % robot.pose_count();
  }
  count_allocations(state, before);
}

void stage_solve(benchmark::State& state, const Robot& robot, SolverKind kind,
                 int refinement_steps) {
  detail::FactorizedSystem system(kind);
  system.factorize(robot.matrices.front(), kSingularRcond);
  double residual = 0;
  const auto before = bench::allocation_count();
  for (auto _ : state) {
    MatX x = system.solve(robot.rhs.front(), refinement_steps, residual);
    benchmark::DoNotOptimize(x.data());
  }
  count_allocations(state, before);
  state.counters["residual"] = residual;
}

// The equilibrated matrix of every pose, as FactorizedSystem::factorize makes it.
std::vector<SparseMatrix> scaled_matrices(const Robot& robot) {
  std::vector<SparseMatrix> scaled;
  for (const SparseMatrix& a : robot.matrices) {
    const detail::Equilibration s = detail::equilibrate(a);
    scaled.push_back(s.row.asDiagonal() * a * s.column.asDiagonal());
  }
  return scaled;
}

void part_equilibrate(benchmark::State& state, const Robot& robot) {
  std::size_t p = 0;
  for (auto _ : state) {
    detail::Equilibration s = detail::equilibrate(robot.matrices[p]);
    benchmark::DoNotOptimize(s.row.data());
    p = (p + 1) % robot.pose_count();
  }
}

// The bare numeric factorisation of the backend on the equilibrated matrix.
void part_lu_numeric(benchmark::State& state, const Robot& robot, SolverKind kind) {
  const auto scaled = scaled_matrices(robot);
  auto lu = detail::make_linear_solver(kind);
  lu->analyze(scaled.front());
  std::size_t p = 0;
  const auto before = bench::allocation_count();
  for (auto _ : state) {
    benchmark::DoNotOptimize(lu->factorize(scaled[p]));
    p = (p + 1) % robot.pose_count();
  }
  count_allocations(state, before);
}

// The bare triangular solves of the backend for the 1 + 6 right-hand sides.
void part_lu_solve(benchmark::State& state, const Robot& robot, SolverKind kind) {
  const auto scaled = scaled_matrices(robot);
  auto lu = detail::make_linear_solver(kind);
  lu->analyze(scaled.front());
  lu->factorize(scaled.front());
  for (auto _ : state) {
    MatX x = robot.rhs.front();
    lu->solve(x);
    benchmark::DoNotOptimize(x.data());
  }
}

#if STIFFMSA_HAVE_SUITESPARSE
// KLU's numeric refactorisation with the pivot order of the first pose, against klu_factor.
void part_klu_refactor(benchmark::State& state, const Robot& robot, bool refactor) {
  auto scaled = scaled_matrices(robot);
  klu_common common;
  klu_defaults(&common);
  common.tol = 1.0;
  const int n = static_cast<int>(scaled.front().rows());
  klu_symbolic* symbolic =
      klu_analyze(n, scaled.front().outerIndexPtr(), scaled.front().innerIndexPtr(), &common);
  klu_numeric* numeric = klu_factor(scaled.front().outerIndexPtr(), scaled.front().innerIndexPtr(),
                                    scaled.front().valuePtr(), symbolic, &common);
  std::size_t p = 0;
  for (auto _ : state) {
    auto& a = scaled[p];
    if (refactor) {
      klu_refactor(a.outerIndexPtr(), a.innerIndexPtr(), a.valuePtr(), symbolic, numeric, &common);
    } else {
      klu_free_numeric(&numeric, &common);
      numeric = klu_factor(a.outerIndexPtr(), a.innerIndexPtr(), a.valuePtr(), symbolic, &common);
    }
    p = (p + 1) % robot.pose_count();
  }
  klu_free_numeric(&numeric, &common);
  klu_free_symbolic(&symbolic, &common);
}
#endif

void part_condition_estimate(benchmark::State& state, const Robot& robot, SolverKind kind) {
  const auto scaled = scaled_matrices(robot);
  auto lu = detail::make_linear_solver(kind);
  lu->analyze(scaled.front());
  lu->factorize(scaled.front());
  const auto before = bench::allocation_count();
  // The library's own estimator on the bare factorisation: its share of factorize() alone.
  for (auto _ : state)
    benchmark::DoNotOptimize(detail::estimate_inverse_norm1(*lu, scaled.front().rows()));
  count_allocations(state, before);
}

// ---- per-pose pipelines: sparse (the library's stages) and dense (the naive baseline) -------

Cartesian sparse_pose(const Robot& robot, const Model& pose, SparseMatrix& matrix,
                      detail::FactorizedSystem& system) {
  const detail::Blocks blocks = detail::make_blocks(pose, robot.topology);
  robot.assembler->fill(blocks, matrix);
  const MatX b = right_hand_sides(pose, robot.topology, blocks, *robot.assembler);
  if (!system.factorize(matrix, kSingularRcond)) throw std::runtime_error("bench: singular pose");
  double residual = 0;
  return cartesian(system.solve(b, kRefinementSteps, residual), robot.topology, robot.length);
}

Cartesian dense_pose(const Robot& robot, const Model& pose, SparseMatrix& matrix) {
  const detail::Blocks blocks = detail::make_blocks(pose, robot.topology);
  robot.assembler->fill(blocks, matrix);
  const MatX b = right_hand_sides(pose, robot.topology, blocks, *robot.assembler);
  const Eigen::PartialPivLU<MatX> lu{MatX(matrix)};
  return cartesian(lu.solve(b), robot.topology, robot.length);
}

void pipeline(benchmark::State& state, const Robot& robot, SolverKind kind) {
  SparseMatrix matrix;
  detail::FactorizedSystem system(kind);
  sparse_pose(robot, robot.poses.front(), matrix, system);  // the pattern analysis
  std::size_t p = 0;
  const auto before = bench::allocation_count();
  for (auto _ : state) {
    Cartesian c = sparse_pose(robot, robot.poses[p], matrix, system);
    benchmark::DoNotOptimize(c);
    p = (p + 1) % robot.pose_count();
  }
  count_allocations(state, before);
}

// ---- the tree solve (serial robots; the tripteron with cuts)
// ----------------------------------------------------------

// Into scratch.x, as the public solve does with its workspace's scratch.
void solve_tree(const Robot& robot, const detail::TreeOrder& order, const detail::Blocks& blocks,
                const detail::EndWrenches& external, detail::TreeScratch& scratch) {
  if (!detail::tree_solve(blocks, robot.topology, order, external,
                          1 / SolveOptions{}.warn_condition, scratch))
    throw std::runtime_error("bench: the tree solve declined a pose");
}

Cartesian tree_pose(const Robot& robot, const detail::TreeOrder& order, const Model& pose,
                    detail::TreeScratch& scratch) {
  const detail::Blocks blocks = detail::make_blocks(pose, robot.topology);
  const detail::EndWrenches external = detail::load_cases(pose, robot.topology);
  solve_tree(robot, order, blocks, external, scratch);
  if (!(detail::check_block_by_block(blocks, robot.topology, scratch.x, external, scratch)
            .relative_residual < 1e-14))
    throw std::runtime_error("bench: a tree solve failed its check");
  const Mat6 c =
      scratch.x.block<6, 6>(detail::deflection_column(robot.topology.effector_ends.front()), 1);
  return {c, detail::cartesian_stiffness(c, robot.length, SolveOptions{}.warn_condition).stiffness};
}

void tree_pipeline(benchmark::State& state, const Robot& robot, const detail::TreeOrder& order) {
  detail::TreeScratch scratch;
  double error = 0;  // against the public solve, over every pose
  for (std::size_t p = 0; p < robot.pose_count(); ++p)
    error = std::max(
        error, bench::scaled_difference(tree_pose(robot, order, robot.poses[p], scratch).compliance,
                                        robot.compliance[p]));
  std::size_t p = 0;
  const auto before = bench::allocation_count();
  for (auto _ : state) {
    Cartesian c = tree_pose(robot, order, robot.poses[p], scratch);
    benchmark::DoNotOptimize(c);
    p = (p + 1) % robot.pose_count();
  }
  count_allocations(state, before);
  state.counters["c_diff"] = error;
}

void stage_tree_solve(benchmark::State& state, const Robot& robot, const detail::TreeOrder& order) {
  std::vector<detail::EndWrenches> loads;
  for (const Model& pose : robot.poses) loads.push_back(detail::load_cases(pose, robot.topology));
  detail::TreeScratch scratch;
  std::size_t p = 0;
  for (auto _ : state) {
    solve_tree(robot, order, robot.blocks[p], loads[p], scratch);
    benchmark::DoNotOptimize(scratch.x.data());
    p = (p + 1) % robot.pose_count();
  }
}

void stage_tree_check(benchmark::State& state, const Robot& robot, const detail::TreeOrder& order) {
  std::vector<detail::EndWrenches> loads;
  std::vector<detail::RowMajorMatX> solutions;
  detail::TreeScratch scratch;
  for (std::size_t p = 0; p < robot.pose_count(); ++p) {
    loads.push_back(detail::load_cases(robot.poses[p], robot.topology));
    solve_tree(robot, order, robot.blocks[p], loads.back(), scratch);
    solutions.push_back(scratch.x);
  }
  std::size_t p = 0;
  for (auto _ : state) {
    detail::BlockCheck check = detail::check_block_by_block(robot.blocks[p], robot.topology,
                                                            solutions[p], loads[p], scratch);
    benchmark::DoNotOptimize(check);
    p = (p + 1) % robot.pose_count();
  }
}

void dense_lu(benchmark::State& state, const Robot& robot) {
  SparseMatrix matrix;
  double error = 0;  // against the public solve, over every pose
  for (std::size_t p = 0; p < robot.pose_count(); ++p)
    error = std::max(error,
                     bench::scaled_difference(dense_pose(robot, robot.poses[p], matrix).compliance,
                                              robot.compliance[p]));
  std::size_t p = 0;
  for (auto _ : state) {
    Cartesian c = dense_pose(robot, robot.poses[p], matrix);
    benchmark::DoNotOptimize(c);
    p = (p + 1) % robot.pose_count();
  }
  state.counters["err_vs_sparse"] = error;
}

// ---- the closed-form floor -------------------------------------------------------------------

void vjm_floor(benchmark::State& state, const Robot& rigid) {
  std::vector<bench::VirtualJointModel> vjm;
  double error = 0;  // the MSA of the same rigid-link robot against the closed form
  for (std::size_t p = 0; p < rigid.pose_count(); ++p) {
    vjm.push_back(bench::virtual_joint_model(rigid.poses[p]));
    error = std::max(
        error, bench::scaled_difference(rigid.compliance[p], bench::vjm_compliance(vjm.back())));
  }
  std::size_t p = 0;
  for (auto _ : state) {
    const Mat6 compliance = bench::vjm_compliance(vjm[p]);
    Mat6 stiffness = compliance.llt().solve(Mat6::Identity());
    benchmark::DoNotOptimize(stiffness);
    p = (p + 1) % vjm.size();
  }
  state.counters["msa_vs_vjm"] = error;
}

// ---- the chain and the frame ------------------------------------------------------------------

const Model& chain_model(int links) {
  static std::map<int, Model> cache;
  auto it = cache.find(links);
  if (it == cache.end()) it = cache.emplace(links, bench::cantilever_chain(links)).first;
  return it->second;
}

void report_tip_accuracy(benchmark::State& state, const Result& result) {
  const Mat6 expected = bench::cantilever_tip_compliance();
  const Mat6& c = *result.end_effectors.front().compliance;
  state.counters["tip_err"] = bench::scaled_difference(c, expected);
  state.counters["Cyy_err"] = std::abs(c(1, 1) / expected(1, 1) - 1);
  state.counters["unknowns"] = static_cast<double>(result.system.unknowns);
}

void chain_solve(benchmark::State& state, SolverKind kind) {
  const Model& model = chain_model(static_cast<int>(state.range(0)));
  Result result;
  for (auto _ : state) {
    result = solve(model, options_for(kind));
    benchmark::DoNotOptimize(result);
  }
  report_tip_accuracy(state, result);
}

void chain_resolve(benchmark::State& state, SolverKind kind) {
  const Model& model = chain_model(static_cast<int>(state.range(0)));
  Workspace workspace(model);
  Result result = solve(workspace, model, options_for(kind));
  for (auto _ : state) {
    result = solve(workspace, model, options_for(kind));
    benchmark::DoNotOptimize(result);
  }
  report_tip_accuracy(state, result);
}

const Model& frame_model() {
  static const Model frame = bench::space_frame(5, 5, 10);
  return frame;
}

// The example files as they are (the file's own pose).
const Model& industrial_home() {
  static const Model model = bench::load_example("industrial-6axis.yaml");
  return model;
}
const Model& tripteron_home() {
  static const Model model = bench::load_example("tripteron.yaml");
  return model;
}

void frame_solve(benchmark::State& state, SolverKind kind) {
  Result result;
  for (auto _ : state) {
    result = solve(frame_model(), options_for(kind));
    benchmark::DoNotOptimize(result);
  }
  state.counters["links"] = static_cast<double>(frame_model().links.size());
  state.counters["unknowns"] = static_cast<double>(result.system.unknowns);
  state.counters["residual"] = result.report.relative_residual;
}

// The stiffness matrix of the nodes' 6 displacements stored dense and factorised whole (LDLᵀ),
// as a frame program without sparsity would; the same K as the frame solve's, from the element
// blocks and its plan. (Frame3DD stores K dense too, but skips each column's leading zeros.)
void frame_dense_ldlt(benchmark::State& state) {
  const Model& model = frame_model();
  const detail::Topology topology = detail::build_topology(model);
  const detail::Blocks blocks = detail::make_blocks(model, topology);
  const detail::FramePlan plan = *detail::frame_plan(topology, blocks);
  const Index n = 6 * static_cast<Index>(plan.nodes);
  const detail::EndWrenches external = detail::load_cases(model, topology);
  MatX f = MatX::Zero(n, 1);
  for (int end = 0; end < topology.end_count(); ++end) {
    const int node = plan.node_of_end[static_cast<std::size_t>(end)];
    if (node >= 0 && external.any_at(end))
      f.middleRows<6>(6 * node) += external.at(end).col(detail::kLoadCase);
  }
  MatX u;
  for (auto _ : state) {
    MatX k = MatX::Zero(n, n);
    for (int l = 0; l < topology.link_count; ++l) {
      const Mat12 k12 = *detail::end_stiffness(*blocks[static_cast<std::size_t>(l)]);
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
          const int row = plan.node_of_end[static_cast<std::size_t>(2 * l + a)];
          const int column = plan.node_of_end[static_cast<std::size_t>(2 * l + b)];
          if (row >= 0 && column >= 0)
            k.block<6, 6>(6 * row, 6 * column) += k12.block<6, 6>(6 * a, 6 * b);
        }
    }
    u = k.ldlt().solve(f);
    benchmark::DoNotOptimize(u);
  }
  // The same displacements as the library's frame solve.
  const Result result = solve(model);
  double largest = 0, difference = 0;
  for (int end = 0; end < topology.end_count(); ++end) {
    const int node = plan.node_of_end[static_cast<std::size_t>(end)];
    if (node < 0) continue;
    const auto& link = result.links[static_cast<std::size_t>(end / 2)];
    const Vec6 deflection = *(end % 2 == 0 ? link.from : link.to).deflection;
    largest = std::max(largest, deflection.cwiseAbs().maxCoeff());
    difference =
        std::max(difference, (deflection - u.middleRows<6>(6 * node)).cwiseAbs().maxCoeff());
  }
  state.counters["unknowns"] = static_cast<double>(n);
  state.counters["u_diff"] = difference / largest;
}

void frame_resolve(benchmark::State& state, SolverKind kind) {
  Workspace workspace(frame_model());
  Result result = solve(workspace, frame_model(), options_for(kind));
  for (auto _ : state) {
    result = solve(workspace, frame_model(), options_for(kind));
    benchmark::DoNotOptimize(result);
  }
  state.counters["links"] = static_cast<double>(frame_model().links.size());
}

// ---- KLU's fill against its pivot tolerance ------------------------------------------------

// The equilibrated system matrix of a model, as FactorizedSystem factorises it.
SparseMatrix equilibrated_matrix(const Model& model) {
  const detail::Topology topology = detail::build_topology(model);
  const detail::Blocks blocks = detail::make_blocks(model, topology);
  const detail::Assembler assembler(blocks, topology.unknowns());
  SparseMatrix a;
  assembler.fill(blocks, a);
  const detail::Equilibration s = detail::equilibrate(a);
  return s.row.asDiagonal() * a * s.column.asDiagonal();
}

#if STIFFMSA_HAVE_SUITESPARSE
// Pivot tolerance 1 is full partial pivoting: KLU then leaves the fill-reducing order where a
// larger entry sits off the diagonal, and the factors can grow far beyond it. Ordering 0 is
// AMD on the pattern of A + Aᵀ (KLU's default, the library's), 1 is COLAMD on A.
void klu_fill(benchmark::State& state, const Model& (*model)(), double tolerance, int ordering) {
  // Built on first use, so that a filtered run does not assemble the large models.
  static std::map<const Model*, SparseMatrix> matrices;
  auto it = matrices.find(&model());
  if (it == matrices.end()) it = matrices.emplace(&model(), equilibrated_matrix(model())).first;
  const SparseMatrix& a = it->second;
  klu_common common;
  klu_defaults(&common);
  common.tol = tolerance;
  common.ordering = ordering;
  const int n = static_cast<int>(a.rows());
  int* ap = const_cast<int*>(a.outerIndexPtr());
  int* ai = const_cast<int*>(a.innerIndexPtr());
  double* ax = const_cast<double*>(a.valuePtr());
  klu_symbolic* symbolic = klu_analyze(n, ap, ai, &common);
  // KLU's own prediction (its ordering, no pivoting), which the solver choice reads.
  state.counters["nnz_LU_predicted"] = symbolic->lnz + symbolic->unz;
  double factor_entries = 0, error = 0;
  for (auto _ : state) {
    klu_numeric* numeric = klu_factor(ap, ai, ax, symbolic, &common);
    state.PauseTiming();
    factor_entries = numeric->lnz + numeric->unz;
    VecX x = a * VecX::Ones(n);
    klu_solve(symbolic, numeric, n, 1, x.data(), &common);
    error = (x.array() - 1.0).abs().maxCoeff();
    klu_free_numeric(&numeric, &common);
    state.ResumeTiming();
  }
  klu_free_symbolic(&symbolic, &common);
  state.counters["nnz_A"] = static_cast<double>(a.nonZeros());
  state.counters["nnz_LU"] = factor_entries;
  state.counters["x_err"] = error;
}
#endif

// ---- registration --------------------------------------------------------------------------

template <class F, class... Args>
benchmark::internal::Benchmark* add(const std::string& name, F function, Args&&... args) {
  return benchmark::RegisterBenchmark(name.c_str(), function, std::forward<Args>(args)...)
      ->Unit(benchmark::kMicrosecond);
}

void register_robot(const Robot& robot) {
  const std::string& r = robot.name;
  for (SolverKind kind : available_solvers()) {
    const std::string s = std::string("/") + to_string(kind);
    add(r + "/public_solve" + s, public_solve, std::cref(robot), kind, kRefinementSteps);
    add(r + "/public_solve_refine0" + s, public_solve, std::cref(robot), kind, 0);
    add(r + "/stage:factorize" + s, stage_factorize, std::cref(robot), kind);
    add(r + "/stage:solve" + s, stage_solve, std::cref(robot), kind, kRefinementSteps);
    add(r + "/part:lu_numeric" + s, part_lu_numeric, std::cref(robot), kind);
    add(r + "/part:condition_estimate" + s, part_condition_estimate, std::cref(robot), kind);
    add(r + "/part:lu_solve" + s, part_lu_solve, std::cref(robot), kind);
    add(r + "/part:solve_refine0" + s, stage_solve, std::cref(robot), kind, 0);
    add(r + "/pipeline" + s, pipeline, std::cref(robot), kind);
  }
  add(r + "/stage:validate", stage_validate, std::cref(robot));
  add(r + "/stage:topology", stage_topology, std::cref(robot));
  add(r + "/stage:make_blocks", stage_make_blocks, std::cref(robot));
  add(r + "/stage:fill", stage_fill, std::cref(robot));
  add(r + "/part:equilibrate", part_equilibrate, std::cref(robot));
#if STIFFMSA_HAVE_SUITESPARSE
  add(r + "/part:klu_factor", part_klu_refactor, std::cref(robot), false);
  add(r + "/part:klu_refactor", part_klu_refactor, std::cref(robot), true);
#endif
  add(r + "/dense_lu", dense_lu, std::cref(robot));
  if (robot.tree) {
    add(r + "/pipeline/tree", tree_pipeline, std::cref(robot), std::cref(*robot.tree));
    add(r + "/stage:tree_solve", stage_tree_solve, std::cref(robot), std::cref(*robot.tree));
    add(r + "/stage:tree_check", stage_tree_check, std::cref(robot), std::cref(*robot.tree));
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;

  const Model industrial = bench::load_example("industrial-6axis.yaml");
  const auto industrial_poses = bench::industrial_poses(industrial, kPoses);
  std::vector<Model> rigid_poses;
  for (const Model& pose : industrial_poses) rigid_poses.push_back(bench::with_rigid_links(pose));
  // Kept alive until the benchmarks have run: they refer to these.
  const std::vector<std::unique_ptr<Robot>> robots = [&] {
    std::vector<std::unique_ptr<Robot>> list;
    list.push_back(std::make_unique<Robot>("6axis", industrial_poses));
    list.push_back(std::make_unique<Robot>("6axis_rigid", rigid_poses));
    list.push_back(std::make_unique<Robot>(
        "gough_stewart",
        bench::gough_stewart_poses(bench::load_example("gough-stewart-6ups.yaml"), kPoses)));
    list.push_back(std::make_unique<Robot>(
        "tripteron", bench::tripteron_poses(bench::load_example("tripteron.yaml"), kPoses)));
    return list;
  }();

  for (const auto& robot : robots) {
    register_robot(*robot);
    benchmark::AddCustomContext(
        robot->name, std::to_string(robot->topology.unknowns()) + " unknowns, " +
                         std::to_string(robot->matrices.front().nonZeros()) + " stored entries");
  }
  add("urdf_6axis/pose_from_joint_angles", urdf_pose, true);
  add("urdf_6axis/build", urdf_pose, false);
  add("6axis/vjm_floor", vjm_floor, std::cref(*robots[1]))->Unit(benchmark::kNanosecond);
  for (SolverKind kind : available_solvers()) {
    const std::string s = std::string("/") + to_string(kind);
    // N = 10, 100, ..., 100 000 from scratch; the repeated solve up to 10 000 (stiffmsa_chain
    // times it at 100 000, with the memory).
    add("chain/solve" + s, chain_solve, kind)
        ->Unit(benchmark::kMillisecond)
        ->ArgName("N")
        ->RangeMultiplier(10)
        ->Range(10, 100000);
    add("chain/resolve" + s, chain_resolve, kind)
        ->Unit(benchmark::kMillisecond)
        ->ArgName("N")
        ->RangeMultiplier(10)
        ->Range(10, 10000);
    add("frame/solve" + s, frame_solve, kind)->Unit(benchmark::kMillisecond);
    add("frame/resolve" + s, frame_resolve, kind)->Unit(benchmark::kMillisecond);
  }
  add("frame/dense_ldlt_of_K", frame_dense_ldlt)->Unit(benchmark::kMillisecond);
#if STIFFMSA_HAVE_SUITESPARSE
  const std::pair<const char*, const Model& (*)()> klu_cases[] = {
      {"6axis", industrial_home},
      {"tripteron", tripteron_home},
      {"chain_10000", []() -> const Model& { return chain_model(10000); }},
      {"frame", frame_model}};
  for (const auto& [name, model] : klu_cases)
    for (const char* ordering : {"amd", "colamd"})
      for (const char* tolerance : {"1", "0.001"})
        add(std::string(name) + "/klu_fill/" + ordering + "/tol:" + tolerance, klu_fill, model,
            std::stod(tolerance), std::string(ordering) == "amd" ? 0 : 1)
            ->Unit(benchmark::kMillisecond);
#endif
  benchmark::AddCustomContext("compiler", "g++ " __VERSION__);
  benchmark::AddCustomContext("eigen", std::to_string(EIGEN_WORLD_VERSION) + "." +
                                           std::to_string(EIGEN_MAJOR_VERSION) + "." +
                                           std::to_string(EIGEN_MINOR_VERSION));
  benchmark::AddCustomContext("suitesparse", STIFFMSA_HAVE_SUITESPARSE ? "UMFPACK, KLU" : "no");

  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

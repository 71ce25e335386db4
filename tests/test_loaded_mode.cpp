// The loaded mode (docs/theory.md §15) against independent computations: the elastica of a
// cantilever under a tip force, the exact equilibrium and loaded stiffness of a planar 2R arm
// with joint springs, the linear results under tiny loads, and the critical point of a column.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include "command_line.hpp"
#include "stiffmsa/analysis.hpp"
#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/model.hpp"
#include "stiffmsa/parametric.hpp"

namespace stiffmsa {
namespace {

SolveOptions loaded_options() {
  SolveOptions options;
  options.mode = AnalysisMode::loaded;
  return options;
}

// ---- the elastica -----------------------------------------------------------------------

// A cantilever of unit length along x, clamped at s = 0, a dead tip force −P·y. With θ(s) the
// angle of its tangent and α = P·L²/(E·I): θ'' = α·cos θ, θ(0) = 0, θ'(1) = 0 (no moment at the
// tip), x' = cos θ, y' = sin θ. Shooting on θ'(0) with classical Runge–Kutta in fine steps.
struct ElasticaTip {
  double x = 0, y = 0, angle = 0;
};

struct ElasticaState {
  double theta, kappa, x, y;
};

ElasticaState integrate(double alpha, double start_curvature, int steps) {
  auto rate = [&](const ElasticaState& s) {
    return ElasticaState{s.kappa, alpha * std::cos(s.theta), std::cos(s.theta), std::sin(s.theta)};
  };
  auto plus = [](const ElasticaState& a, const ElasticaState& b, double h) {
    return ElasticaState{a.theta + h * b.theta, a.kappa + h * b.kappa, a.x + h * b.x,
                         a.y + h * b.y};
  };
  ElasticaState s{0, start_curvature, 0, 0};
  const double h = 1.0 / steps;
  for (int i = 0; i < steps; ++i) {
    const ElasticaState k1 = rate(s), k2 = rate(plus(s, k1, h / 2)), k3 = rate(plus(s, k2, h / 2)),
                        k4 = rate(plus(s, k3, h));
    s.theta += h / 6 * (k1.theta + 2 * k2.theta + 2 * k3.theta + k4.theta);
    s.kappa += h / 6 * (k1.kappa + 2 * k2.kappa + 2 * k3.kappa + k4.kappa);
    s.x += h / 6 * (k1.x + 2 * k2.x + 2 * k3.x + k4.x);
    s.y += h / 6 * (k1.y + 2 * k2.y + 2 * k3.y + k4.y);
  }
  return s;
}

ElasticaTip elastica(double alpha) {
  // θ'(0) = −α·x_tip lies in [−α, 0]; θ'(1) grows with θ'(0): bisection.
  constexpr int kSteps = 4000;  // RK4 error ~h⁴: below 1e-13 here
  double low = -alpha, high = 0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (low + high);
    (integrate(alpha, mid, kSteps).kappa > 0 ? high : low) = mid;
  }
  const ElasticaState s = integrate(alpha, 0.5 * (low + high), kSteps);
  return {s.x, s.y, s.theta};
}

TEST(Elastica, ReferenceMatchesTheSmallLoadLimitAndIsConverged) {
  // Small α: y = −α/3 (the linear cantilever), x ≈ 1.
  const ElasticaTip small = elastica(1e-4);
  EXPECT_NEAR(small.y, -1e-4 / 3, 1e-11);
  // The integration is converged: twice the steps move the tip by nothing that counts.
  const ElasticaState coarse = integrate(10.0, -3.0, 4000), fine = integrate(10.0, -3.0, 8000);
  EXPECT_NEAR(coarse.y, fine.y, 1e-12);
  EXPECT_NEAR(coarse.theta, fine.theta, 1e-12);
}

// The same cantilever as n beams, nearly inextensible (A large against I/L²) unless `area` says
// otherwise.
Model cantilever(int n, double force, double area = 1e3) {
  Model m;
  m.name = "elastica";
  const Material material{1e9, 0.3, std::nullopt, std::nullopt};
  const Section section = Section::generic(area, 1e-6, 1e-6, 2e-6);  // EI = 1000
  for (int i = 0; i <= n; ++i) m.add_point("p" + std::to_string(i), Vec3(double(i) / n, 0, 0));
  for (int i = 0; i < n; ++i)
    m.add_beam("b" + std::to_string(i), "p" + std::to_string(i), "p" + std::to_string(i + 1),
               material, section);
  m.add_support("clamp", "p0", {}, Connection::rigid());
  Vec6 w = Vec6::Zero();
  w[1] = -force;
  m.add_load("p" + std::to_string(n), std::nullopt, w);
  m.add_end_effector("tip", "p" + std::to_string(n));
  return m;
}

double tip_error(int n, double alpha) {
  const double ei = 1e9 * 1e-6;
  const Result r = solve(cantilever(n, alpha * ei), loaded_options());
  const ElasticaTip exact = elastica(alpha);
  const Vec6 d = *r.end_effector("tip").deflection;
  // The axial strain P·sin θ/(E·A) stretches the beam by at most P/(E·A) = α·1e-15: nothing.
  return std::max(
      {std::abs(d[0] - (exact.x - 1)), std::abs(d[1] - exact.y), std::abs(d[5] - exact.angle)});
}

TEST(LoadedMode, CantileverConvergesToTheElasticaFromPL2EI01To10) {
  // Measured: at 64 elements the tip is within 5e-9 of the elastica for α = 10 (3e-12 for
  // α = 0.1, the rounding floor), and each halving of the elements divides the error by ~16.
  for (const double alpha : {0.1, 1.0, 3.0, 10.0}) {
    SCOPED_TRACE("alpha " + std::to_string(alpha));
    const double coarse = tip_error(8, alpha), fine = tip_error(16, alpha),
                 finer = tip_error(32, alpha), finest = tip_error(64, alpha);
    std::printf("alpha %g: tip errors at 8, 16, 32, 64 elements %.3e %.3e %.3e %.3e\n", alpha,
                coarse, fine, finer, finest);
    if (alpha >= 1) {
      EXPECT_GT(coarse / fine, 8.0);
      EXPECT_GT(fine / finer, 8.0);
    }
    EXPECT_LT(finer, 1e-6);
    EXPECT_LT(finest, 1e-8);
  }
}

// The block LU's elimination order comes from a search whose cost grows as the square of the
// link ends (theory §15.10): a model of more than kBlockLuMostGroups link ends takes the sparse
// path. Below it, the block LU and a sparse LU find the same equilibrium and tangent. (With the
// elastica's near-inextensible section, EA/EI = 1e12, the tangent's condition leaves the
// compliance only ~6 digits whichever LU solves it: an axial stiffness of a real beam here.)
TEST(LoadedMode, LongModelsTakeTheSparsePathAndBothPathsAgree) {
  const double force = 3.0 * 1e3;                    // PL²/EI = 3
  const Model within = cantilever(60, force, 1e-2);  // 120 link ends
  const Result by_block_lu = solve(within, loaded_options());
  EXPECT_EQ(by_block_lu.report.solver, SolverUsed::block_lu);
  SolveOptions sparse = loaded_options();
  sparse.solver = SolverKind::sparse_lu;
  const Result by_sparse_lu = solve(within, sparse);
  EXPECT_EQ(by_sparse_lu.report.solver, SolverUsed::sparse_lu);
  const Vec6 a = *by_block_lu.end_effector("tip").deflection;
  const Vec6 b = *by_sparse_lu.end_effector("tip").deflection;
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-10 * b.cwiseAbs().maxCoeff());
  const Mat6 ca = *by_block_lu.end_effector("tip").compliance;
  const Mat6 cb = *by_sparse_lu.end_effector("tip").compliance;
  EXPECT_LT((ca - cb).norm(), 1e-9 * cb.norm());

  const Result beyond = solve(cantilever(70, force, 1e-2), loaded_options());  // 140 link ends
  EXPECT_NE(beyond.report.solver, SolverUsed::block_lu);
  EXPECT_LT(beyond.report.relative_residual, 1e-10);
}

// ---- a planar 2R arm with joint springs --------------------------------------------------

struct Arm {
  double l1 = 1.0, l2 = 0.8;
  double a1 = 0.5, a2 = 1.3;  // unloaded link angles from x
  double k1 = 2e3, k2 = 1e3;  // N·m/rad
  Vec3 force{300, -500, 0};   // N at the tip, dead

  Vec3 u(double a) const { return {std::cos(a), std::sin(a), 0}; }
  Vec3 across(double a) const { return {-std::sin(a), std::cos(a), 0}; }
  // Link angles at joint deflections q (q2 relative).
  double b1(const Eigen::Vector2d& q) const { return a1 + q[0]; }
  double b2(const Eigen::Vector2d& q) const { return a2 + q[0] + q[1]; }
  Eigen::Matrix2d jacobian(const Eigen::Vector2d& q) const {
    const Vec3 c1 = l1 * across(b1(q)) + l2 * across(b2(q)), c2 = l2 * across(b2(q));
    Eigen::Matrix2d j;
    j << c1.x(), c2.x(), c1.y(), c2.y();
    return j;
  }
  // Jᵀ·F and its derivative H = ∂(JᵀF)/∂q.
  Eigen::Vector2d generalised(const Eigen::Vector2d& q) const {
    return jacobian(q).transpose() * force.head<2>();
  }
  Eigen::Matrix2d h(const Eigen::Vector2d& q) const {
    const double f1 = force.dot(-l1 * u(b1(q)) - l2 * u(b2(q))), f2 = force.dot(-l2 * u(b2(q)));
    Eigen::Matrix2d m;
    m << f1, f2, f2, f2;
    return m;
  }
  // K_θ·q = Jᵀ(q)·F by Newton's method.
  Eigen::Vector2d equilibrium() const {
    Eigen::Vector2d q = Eigen::Vector2d::Zero();
    const Eigen::Matrix2d k = Eigen::Vector2d(k1, k2).asDiagonal();
    for (int i = 0; i < 50; ++i) q -= (k - h(q)).lu().solve(k * q - generalised(q));
    return q;
  }

  Model model() const {
    Model m;
    m.name = "arm";
    m.add_point("O", Vec3::Zero());
    m.add_point("elbow", l1 * u(a1));
    m.add_point("tip", l1 * u(a1) + l2 * u(a2));
    m.add_rigid_link("upper", "O", "elbow");
    m.add_rigid_link("forearm", "elbow", "tip");
    m.add_support("base", "O", {}, Connection::elastic(Kinematics::revolute(Vec3::UnitZ()), k1));
    m.add_joint("elbow_joint", "elbow", {"upper", "forearm"},
                Connection::elastic(Kinematics::revolute(Vec3::UnitZ()), k2));
    Vec6 w = Vec6::Zero();
    w.head<3>() = force;
    m.add_load("tip", std::nullopt, w);
    m.add_end_effector("tool", "tip");
    return m;
  }
};

TEST(LoadedMode, PlanarArmWithJointSpringsReachesItsExactEquilibrium) {
  const Arm arm;
  const Eigen::Vector2d q = arm.equilibrium();
  ASSERT_GT(std::abs(q[0]), 0.1);  // a large deflection: the test means something
  const Result r = solve(arm.model(), loaded_options());
  const Vec3 tip = arm.l1 * arm.u(arm.b1(q)) + arm.l2 * arm.u(arm.b2(q));
  const Vec3 unloaded = arm.l1 * arm.u(arm.a1) + arm.l2 * arm.u(arm.a2);
  const Vec6 d = *r.end_effector("tool").deflection;
  EXPECT_NEAR(d[0], tip.x() - unloaded.x(), 1e-12);
  EXPECT_NEAR(d[1], tip.y() - unloaded.y(), 1e-12);
  EXPECT_NEAR(d[5], q[0] + q[1], 1e-12);
  // The joint's relative deflection is its finite angle; its spring's moment k2·q2.
  EXPECT_NEAR((*r.joint("elbow_joint").relative_deflection)[0][0], q[1], 1e-12);
  EXPECT_NEAR((*r.joint("elbow_joint").wrench)[5], arm.k2 * q[1], 1e-8);
  EXPECT_EQ(r.analysis.mode, AnalysisMode::loaded);
  EXPECT_GE(r.analysis.load_steps, 1);
  EXPECT_GE(r.analysis.iterations, 2);
  ASSERT_TRUE(r.linear);
  EXPECT_EQ(r.linear->analysis.mode, AnalysisMode::linear);
}

TEST(LoadedMode, PlanarArmLoadedStiffnessIsJacobianTransformOfKThetaMinusH) {
  const Arm arm;
  const Eigen::Vector2d q = arm.equilibrium();
  const Eigen::Matrix2d k = Eigen::Vector2d(arm.k1, arm.k2).asDiagonal();
  const Eigen::Matrix2d j = arm.jacobian(q);
  const Eigen::Matrix2d expected = j.transpose().inverse() * (k - arm.h(q)) * j.inverse();
  const Result r = solve(arm.model(), loaded_options());
  const Mat6 c = *r.end_effector("tool").compliance;
  const Eigen::Matrix2d stiffness = c.topLeftCorner<2, 2>().inverse();
  EXPECT_LT((stiffness - expected).norm(), 1e-9 * expected.norm()) << "loaded\n"
                                                                   << stiffness << "\nexpected\n"
                                                                   << expected;
  // And it differs from the linear stiffness at the unloaded pose by far more.
  const Mat6 linear = *r.linear->end_effector("tool").compliance;
  EXPECT_GT((linear.topLeftCorner<2, 2>().inverse() - expected).norm(), 1e-2 * expected.norm());
}

// ---- tiny loads give the linear answers --------------------------------------------------

Model scaled_loads(Model m, double factor) {
  for (Load& l : m.loads) l.wrench *= factor;
  return m;
}

// The loaded mode at loads of `factor` times the file's: its compliance within
// `compliance_tolerance` of the linear one, its deflections and reactions within
// `state_tolerance` (relative). The loaded mode holds positions and rotation matrices, whose
// rounding (1e-16 of the model size) limits how closely a tiny deflection is resolved.
void expect_linear_answers(const std::string& file, double factor, double compliance_tolerance,
                           double state_tolerance) {
  SCOPED_TRACE(file + " at " + std::to_string(factor));
  const Model m =
      scaled_loads(load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/" + file), factor);
  const Result r = solve(m, loaded_options());
  ASSERT_TRUE(r.linear);
  for (std::size_t e = 0; e < r.end_effectors.size(); ++e) {
    const EndEffectorResult& loaded = r.end_effectors[e];
    const EndEffectorResult& linear = r.linear->end_effectors[e];
    ASSERT_TRUE(loaded.compliance && linear.compliance);
    EXPECT_LT((*loaded.compliance - *linear.compliance).norm(),
              compliance_tolerance * linear.compliance->norm());
    if (linear.deflection && !linear.deflection->isZero(0))
      EXPECT_LT((*loaded.deflection - *linear.deflection).norm(),
                state_tolerance * linear.deflection->norm());
  }
  for (std::size_t s = 0; s < r.supports.size(); ++s)
    if (r.linear->supports[s].reaction && !r.linear->supports[s].reaction->isZero(0))
      EXPECT_LT((*r.supports[s].reaction - *r.linear->supports[s].reaction).norm(),
                state_tolerance * r.linear->supports[s].reaction->norm());
}

TEST(LoadedMode, TinyLoadsGiveTheLinearResults) {
  for (const char* file :
       {"planar-2r.yaml", "cantilever.yaml", "industrial-6axis.yaml", "tripteron.yaml"}) {
    // The tangent differs from the linear matrix by terms proportional to the loads.
    expect_linear_answers(file, 1e-8, 1e-9, 1e-4);
    // Deflections: the nonlinear part grows as the load, the rounding as its inverse.
    expect_linear_answers(file, 1e-4, 1e-5, 1e-6);
  }
}

// ---- critical points ---------------------------------------------------------------------

// A clamped–free column of rectangular section under a dead axial tip load of `factor` times
// Euler's load π²·E·I/(4·L²) about its weak axis.
Model column(double factor) {
  Model m;
  m.name = "column";
  const int n = 16;
  const double e = 2.1e11, b = 0.02, h = 0.04, length = 1;
  const double weak = h * b * b * b / 12;
  for (int i = 0; i <= n; ++i) m.add_point("p" + std::to_string(i), Vec3(0, 0, length * i / n));
  for (int i = 0; i < n; ++i)
    m.add_beam("c" + std::to_string(i), "p" + std::to_string(i), "p" + std::to_string(i + 1),
               Material{e, 0.3, std::nullopt, std::nullopt}, Section::rect(b, h));
  m.add_support("base", "p0", {}, Connection::rigid());
  Vec6 w = Vec6::Zero();
  w[2] = -factor * M_PI * M_PI * e * weak / (4 * length * length);
  m.add_load("p" + std::to_string(n), std::nullopt, w);
  m.add_end_effector("top", "p" + std::to_string(n));
  return m;
}

TEST(LoadedMode, ColumnBelowEulersLoadIsSolvedAndSofterThanLinear) {
  const Result r = solve(column(0.5), loaded_options());
  const EndEffectorResult& top = r.end_effector("top");
  const EndEffectorResult& linear = r.linear->end_effector("top");
  // Under compression the lateral compliance grows: by 1/(1 − P/P_cr) for the tip's sway
  // roughly, here within 20% of 2.
  double ratio = 0;
  for (int axis : {0, 1})
    ratio = std::max(ratio, (*top.compliance)(axis, axis) / (*linear.compliance)(axis, axis));
  EXPECT_GT(ratio, 1.6);
  EXPECT_LT(ratio, 2.4);
}

TEST(LoadedMode, ColumnBeyondEulersLoadReportsTheCriticalLoadFactor) {
  try {
    solve(column(2.0), loaded_options());
    FAIL() << "a column at twice its critical load was solved";
  } catch (const NoEquilibriumError& e) {
    // Euler's load is half the applied one: the path stops at λ = 0.5 (16 elements: within 1e-3).
    EXPECT_NEAR(e.load_factor(), 0.5, 2e-3) << e.what();
    EXPECT_NE(std::string(e.what()).find("load factor"), std::string::npos) << e.what();
  }
}

// ---- a workspace's poses ------------------------------------------------------------------

// Of two results of one pose: the largest difference of every end effector's compliance,
// stiffness and deflection and of every link end's deflection and wrench, each relative to the
// largest entry of its kind.
double largest_relative_difference(const Result& a, const Result& b) {
  double largest = 0;
  auto compare = [&](const auto& x, const auto& y, double scale) {
    EXPECT_EQ(x.has_value(), y.has_value());
    if (x && y && scale > 0) largest = std::max(largest, (*x - *y).cwiseAbs().maxCoeff() / scale);
  };
  double deflection = 0, wrench = 0;
  for (const LinkResult& l : b.links)
    for (const LinkEndResult* end : {&l.from, &l.to}) {
      if (end->deflection)
        deflection = std::max(deflection, end->deflection->cwiseAbs().maxCoeff());
      if (end->wrench) wrench = std::max(wrench, end->wrench->cwiseAbs().maxCoeff());
    }
  for (std::size_t l = 0; l < a.links.size(); ++l) {
    compare(a.links[l].from.deflection, b.links[l].from.deflection, deflection);
    compare(a.links[l].to.deflection, b.links[l].to.deflection, deflection);
    compare(a.links[l].from.wrench, b.links[l].from.wrench, wrench);
    compare(a.links[l].to.wrench, b.links[l].to.wrench, wrench);
  }
  for (std::size_t e = 0; e < a.end_effectors.size(); ++e) {
    const EndEffectorResult &x = a.end_effectors[e], &y = b.end_effectors[e];
    compare(x.compliance, y.compliance, y.compliance ? y.compliance->cwiseAbs().maxCoeff() : 0);
    compare(x.stiffness, y.stiffness, y.stiffness ? y.stiffness->cwiseAbs().maxCoeff() : 0);
    compare(x.deflection, y.deflection, y.deflection ? y.deflection->cwiseAbs().maxCoeff() : 0);
  }
  return largest;
}

// The loaded poses of a family solved through one workspace (the tangent's pattern, analysis
// and position map kept from pose to pose, docs/theory.md §15.7), in either order, against the
// one-shot loaded solve of each pose's model: the same results to 1e-12, the same iterations.
void expect_workspace_poses_equal_one_shot_solves(const std::string& file,
                                                  const std::vector<std::vector<double>>& poses,
                                                  const std::vector<std::string>& parameters) {
  SCOPED_TRACE(file);
  const ModelFamily family =
      load_model_family(std::string(STIFFMSA_SOURCE_DIR) + "/examples/" + file);
  const Structure structure = family.structure();
  std::vector<std::vector<double>> members;
  for (const std::vector<double>& pose : poses) {
    std::vector<double> values = family.default_values();
    for (std::size_t p = 0; p < parameters.size(); ++p)
      values[*family.find_parameter(parameters[p])] = pose[p];
    members.push_back(values);
  }
  std::vector<Result> one_shot;
  for (const std::vector<double>& member : members)
    one_shot.push_back(solve(family.build(member), loaded_options()));
  for (const bool reversed : {false, true}) {
    Workspace workspace(structure);
    ModelFamily::ValueWriter write = family.make_writer(structure);
    std::vector<double> slots = structure.default_values();
    std::vector<Diagnostic> warnings;
    for (std::size_t k = 0; k < members.size(); ++k) {
      const std::size_t pose = reversed ? members.size() - 1 - k : k;
      SCOPED_TRACE("pose " + std::to_string(pose) + (reversed ? " (reversed)" : ""));
      write(members[pose], slots, warnings);
      const Result through_workspace = solve(workspace, slots, loaded_options());
      ASSERT_EQ(through_workspace.analysis.mode, AnalysisMode::loaded);
      EXPECT_EQ(through_workspace.analysis.iterations, one_shot[pose].analysis.iterations);
      EXPECT_EQ(through_workspace.analysis.load_steps, one_shot[pose].analysis.load_steps);
      EXPECT_LE(largest_relative_difference(through_workspace, one_shot[pose]), 1e-12);
    }
  }
}

TEST(LoadedMode, WorkspacePosesEqualOneShotSolves) {
  expect_workspace_poses_equal_one_shot_solves(
      "tripteron-parametric.yaml",
      {{0.32, 0.28, 0.30}, {0.25, 0.35, 0.27}, {0.38, 0.22, 0.33}, {0.30, 0.30, 0.24}},
      {"px", "py", "pz"});
  expect_workspace_poses_equal_one_shot_solves(
      "planar-3rpr-parametric.yaml", {{0.46, 0.33, 0.0831}, {0.40, 0.30, 0.0}, {0.50, 0.36, 0.15}},
      {"x", "y", "phi"});
}

// ---- the command line ----------------------------------------------------------------------

int run_cli(const std::string& arguments, const std::string& output) {
  return testing::run_into(STIFFMSA_CLI, arguments, output);
}

TEST(LoadedModeCli, LoadedFlagWritesTheAnalysisAndTheLinearResults) {
  const auto dir = std::filesystem::temp_directory_path() / "stiffmsa-loaded-cli";
  std::filesystem::create_directories(dir);
  const std::string json = (dir / "arm.json").string();
  ASSERT_EQ(run_cli("solve " + std::string(STIFFMSA_SOURCE_DIR) +
                        "/examples/planar-2r.yaml --loaded --json " + json,
                    (dir / "arm.txt").string()),
            0)
      << testing::read_file(dir / "arm.txt");
  const std::string text = testing::read_file(json);
  EXPECT_NE(text.find("\"analysis\": {"), std::string::npos) << text;
  EXPECT_NE(text.find("\"mode\": \"loaded\""), std::string::npos);
  EXPECT_NE(text.find("\"linear\": {"), std::string::npos);
  EXPECT_NE(text.find("\"stiffness_asymmetry\""), std::string::npos);
  // The summary says which analysis ran, with its steps and iterations as the result file has
  // them, and each end effector's asymmetry.
  const std::string summary = testing::read_file(dir / "arm.txt");
  const Result r = solve(load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/planar-2r.yaml"),
                         loaded_options());
  const std::string steps = std::to_string(r.analysis.load_steps);
  EXPECT_NE(summary.find("Analysis: loaded (equilibrium in the deformed geometry) in " + steps +
                         (r.analysis.load_steps == 1 ? " load step, " : " load steps, ") +
                         std::to_string(r.analysis.iterations) + " Newton iterations"),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("Stiffness asymmetry: "), std::string::npos) << summary;
}

TEST(LoadedModeCli, ColumnBeyondItsCriticalLoadExitsWithOneAndTheLoadFactor) {
  const auto dir = std::filesystem::temp_directory_path() / "stiffmsa-loaded-cli";
  std::filesystem::create_directories(dir);
  const auto model = dir / "column.yaml";
  // Euler's load of this clamped-free column about its weak axis: π²·E·I/(4·L²) = 13 818 N.
  std::ofstream(model) << R"(format: stiffmsa/1
name: column
analysis: {mode: loaded}
materials:
  steel: {E: 2.1e11, nu: 0.3}
sections:
  bar: {shape: rect, b: 0.02, h: 0.04}
points:
  p0: [0, 0, 0]
  p1: [0, 0, 0.25]
  p2: [0, 0, 0.5]
  p3: [0, 0, 0.75]
  p4: [0, 0, 1]
links:
  c1: {type: beam, from: p0, to: p1, material: steel, section: bar}
  c2: {type: beam, from: p1, to: p2, material: steel, section: bar}
  c3: {type: beam, from: p2, to: p3, material: steel, section: bar}
  c4: {type: beam, from: p3, to: p4, material: steel, section: bar}
supports:
  base: {type: rigid, at: p0}
loads:
  - {at: p4, wrench: [0, 0, -30000, 0, 0, 0]}
end_effectors:
  top: {at: p4}
)";
  const auto out = dir / "column.txt";
  EXPECT_EQ(run_cli("solve " + model.string(), out.string()), 1) << testing::read_file(out);
  EXPECT_NE(testing::read_file(out).find("load factor"), std::string::npos)
      << testing::read_file(out);
}

}  // namespace
}  // namespace stiffmsa

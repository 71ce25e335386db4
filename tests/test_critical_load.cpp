// The critical load factor (docs/theory.md §14): Euler's columns with four end conditions and
// their convergence, Greenhill's column under its own weight, rigid bars on springs against
// their closed forms (the load terms of links and joints), tension and tiny loads; the kernels
// of the load-dependent stiffness against finite differences of the turned statics.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "analysis/critical_load.hpp"
#include "assembly/topology.hpp"
#include "builders.hpp"
#include "elements/free_directions.hpp"
#include "elements/geometric_load_terms.hpp"
#include "stiffmsa/io/result_file.hpp"
#include "stiffmsa/stiffmsa.hpp"

namespace stiffmsa {
namespace {

using testing::wrench;

constexpr double kPi = std::numbers::pi;
const Material kSteel{2.1e11, 0.3, std::nullopt, std::nullopt};
// 20 × 30 mm: the weak axis is unique, so that the mode bends about one local axis.
const Section kBar = Section::rect(0.02, 0.03);
constexpr double kHeight = 2.0;

double weak_inertia() {
  const SectionProperties s = section_properties(kBar);
  return std::min(s.Iy, s.Iz);
}

// How the column's ends are held.
enum class End { clamped, pinned, free, clamped_sliding };

Kinematics free_rows(std::vector<Vec6> rows) { return Kinematics::custom(std::move(rows)); }

// A column of `elements` beams along z from P0 (bottom) to Pn (top, height kHeight), held at
// its ends as asked, loaded by `top_force` along z at the top.
Model column(int elements, End bottom, End top, double top_force) {
  Model m = testing::beam_chain(
      elements, [&](int i) { return Vec3(0, 0, kHeight * i / elements); }, kSteel, kBar);
  m.supports.clear();
  const Vec6 slide_z = Vec6::Unit(2), turn_x = Vec6::Unit(3), turn_y = Vec6::Unit(4);
  if (bottom == End::clamped)
    m.add_support("bottom", "P0", {}, Connection::rigid());
  else
    m.add_support("bottom", "P0", {},
                  Connection::passive(Kinematics::universal(Vec3::UnitX(), Vec3::UnitY())));
  const std::string top_point = "P" + std::to_string(elements);
  if (top == End::pinned)
    m.add_support("top", top_point, {}, Connection::passive(free_rows({slide_z, turn_x, turn_y})));
  else if (top == End::clamped_sliding)
    m.add_support("top", top_point, {}, Connection::passive(free_rows({slide_z})));
  m.add_load(top_point, std::nullopt, wrench(0, 0, top_force));
  return m;
}

SolveOptions with_critical_load() {
  SolveOptions options;
  options.critical_load = true;
  return options;
}

// A test's number in its XML report (--gtest_output=xml), for the tables of theory.md §14.4.
void record(const std::string& key, double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2e", value);
  ::testing::Test::RecordProperty(key, text);
}

double critical_factor(const Model& model) {
  const Result r = solve(model, with_critical_load());
  EXPECT_TRUE(r.critical_load.has_value());
  EXPECT_TRUE(r.critical_load && r.critical_load->factor.has_value());
  return r.critical_load && r.critical_load->factor ? *r.critical_load->factor : 0.0;
}

// Euler's load for an effective length factor: π²EI/(K·L)².
double euler(double effective_length_factor) {
  const double l = effective_length_factor * kHeight;
  return kPi * kPi * kSteel.E * weak_inertia() / (l * l);
}

struct EulerCase {
  End bottom, top;
  double exact;  // N
};

// The relative errors of λ·P against the exact load for 1 (2 where one element has no free
// node), 2, 4, … 64 elements, and that they fall as h⁴ (the cubic elements' consistent geometric
// stiffness) to within 1e-6 at 64.
void expect_converges(const EulerCase& c) {
  constexpr double kForce = -1000.0;
  double previous = 0;
  const int fewest = c.bottom == End::clamped && c.top == End::clamped_sliding ? 2 : 1;
  for (int elements = fewest; elements <= 64; elements *= 2) {
    const double load = -kForce * critical_factor(column(elements, c.bottom, c.top, kForce));
    const double error = load / c.exact - 1;
    record("elements_" + std::to_string(elements), error);
    EXPECT_GT(error, 0) << elements << " elements: the discretised column is stiffer";
    if (elements == 64) {
      EXPECT_LT(error, 1e-6) << elements << " elements";
    }
    if (elements >= 8 && previous > 1e-12) {
      EXPECT_GT(previous / error, 12.0) << elements << " elements: not fourth order";
    }
    previous = error;
  }
}

TEST(CriticalLoad, PinnedPinnedColumnConvergesToEulersLoad) {
  expect_converges({End::pinned, End::pinned, euler(1.0)});
}

TEST(CriticalLoad, ClampedFreeColumnConvergesToEulersLoad) {
  expect_converges({End::clamped, End::free, euler(2.0)});
}

TEST(CriticalLoad, ClampedPinnedColumnConvergesToItsLoad) {
  // β² EI/L², β the first positive root of tan β = β.
  const double beta = 4.493409457909064;
  expect_converges(
      {End::clamped, End::pinned, beta * beta * kSteel.E * weak_inertia() / (kHeight * kHeight)});
}

TEST(CriticalLoad, ClampedClampedColumnConvergesToEulersLoad) {
  expect_converges({End::clamped, End::clamped_sliding, euler(0.5)});
}

TEST(CriticalLoad, ColumnModeBendsAboutItsWeakAxis) {
  const Result r = solve(column(1, End::clamped, End::free, -1000.0), with_critical_load());
  ASSERT_TRUE(r.critical_load && r.critical_load->factor);
  // The column bends about the local axis of the smaller moment of inertia.
  const SectionProperties s = section_properties(kBar);
  const std::string axis = s.Iy < s.Iz ? "y" : "z";
  EXPECT_EQ(r.critical_load->mode, "link 'L1' bends about its local " + axis + " axis");
}

TEST(CriticalLoad, TensionHasNoCriticalFactor) {
  const Result r = solve(column(8, End::clamped, End::free, +1000.0), with_critical_load());
  ASSERT_TRUE(r.critical_load.has_value());
  EXPECT_FALSE(r.critical_load->factor.has_value());
  EXPECT_EQ(r.critical_load->mode, "");
}

TEST(CriticalLoad, FactorScalesAsOneOverTheLoad) {
  const double big = critical_factor(column(16, End::pinned, End::pinned, -1000.0));
  const double tiny = critical_factor(column(16, End::pinned, End::pinned, -1e-6));
  EXPECT_NEAR(tiny * 1e-6 / (big * 1000.0), 1.0, 1e-12);
}

TEST(CriticalLoad, NotComputedUnlessAsked) {
  EXPECT_FALSE(solve(column(4, End::pinned, End::pinned, -1000.0)).critical_load.has_value());
}

// The result file gives the factor and its mode where asked, null where none is positive, and
// nothing where not asked (the files of models that do not ask stay as they were).
TEST(CriticalLoad, ResultFileGivesTheFactorAndItsMode) {
  const Result buckles = solve(column(2, End::clamped, End::free, -1000.0), with_critical_load());
  ASSERT_TRUE(buckles.critical_load && buckles.critical_load->factor);
  const std::string text = result_to_json(buckles);
  EXPECT_NE(text.find("\"critical_load_factor\": "), std::string::npos);
  EXPECT_NE(text.find("\"critical_load_mode\": \"" + buckles.critical_load->mode + "\""),
            std::string::npos);
  const std::string tension =
      result_to_json(solve(column(2, End::clamped, End::free, +1000.0), with_critical_load()));
  EXPECT_NE(tension.find("\"critical_load_factor\": null"), std::string::npos);
  const std::string unasked = result_to_json(solve(column(2, End::clamped, End::free, -1000.0)));
  EXPECT_EQ(unasked.find("critical_load"), std::string::npos);
}

// Each load case gets its own factor from its own loads; with no unnamed case the top level's
// is the first case's, with one the unnamed case's.
TEST(CriticalLoad, EveryLoadCaseGetsItsOwnFactor) {
  Model model = column(8, End::clamped, End::free, 0.0);
  model.loads.clear();
  for (const auto& [name, force] : {std::pair{"push", -1000.0}, std::pair{"pull", 1000.0}}) {
    LoadCase load_case;
    load_case.name = name;
    load_case.loads.push_back({"P8", std::nullopt, wrench(0, 0, force), false, {}});
    model.add_load_case(load_case);
  }
  const double push = critical_factor(column(8, End::clamped, End::free, -1000.0));
  const Result result = solve(model, with_critical_load());
  ASSERT_EQ(result.load_cases.size(), 2u);
  ASSERT_TRUE(result.load_cases[0].critical_load && result.load_cases[0].critical_load->factor);
  EXPECT_NEAR(*result.load_cases[0].critical_load->factor / push, 1.0, 1e-12);
  ASSERT_TRUE(result.load_cases[1].critical_load);
  EXPECT_FALSE(result.load_cases[1].critical_load->factor);
  ASSERT_TRUE(result.critical_load && result.critical_load->factor);
  EXPECT_EQ(*result.critical_load->factor, *result.load_cases[0].critical_load->factor);

  model.add_load("P8", std::nullopt, wrench(0, 0, -4000.0));
  const Result with_unnamed = solve(model, with_critical_load());
  ASSERT_TRUE(with_unnamed.critical_load && with_unnamed.critical_load->factor);
  EXPECT_NEAR(*with_unnamed.critical_load->factor / (push / 4), 1.0, 1e-12);
  ASSERT_TRUE(with_unnamed.load_cases[0].critical_load->factor);
  EXPECT_NEAR(*with_unnamed.load_cases[0].critical_load->factor / push, 1.0, 1e-12);
}

// Greenhill: a clamped–free column under its own weight q per metre buckles at
// qL³/EI = 7.837347… (9/4 · j², j the first zero of J₋₁/₃). `factor(elements)` is the critical
// load factor of a column of that many beams under a weight of `weight_per_metre`; its errors
// against Greenhill's load fall as h² from 8 to 64 elements, and the Richardson extrapolation
// from 32 and 64 elements removes them to 1e-7.
constexpr double kGreenhill = 7.837347438943483;

void expect_converges_to_greenhill(const std::function<double(int)>& factor,
                                   double weight_per_metre) {
  const double scale = weight_per_metre * std::pow(kHeight, 3) / (kSteel.E * weak_inertia());
  double previous_error = 0, previous = 0;
  for (int elements = 8; elements <= 64; elements *= 2) {
    const double value = factor(elements) * scale;
    const double error = std::abs(value / kGreenhill - 1);
    record("elements_" + std::to_string(elements), error);
    if (previous_error > 0) {
      EXPECT_NEAR(previous_error / error, 4.0, 0.2) << elements;
    }
    if (elements == 64) {
      EXPECT_LT(error, 1e-3);
      // Richardson, h²: the weight's discretisation error removed.
      record("richardson_32_64", (4 * value - previous) / 3 / kGreenhill - 1);
      EXPECT_NEAR((4 * value - previous) / 3 / kGreenhill, 1.0, 1e-7);
    }
    previous_error = error;
    previous = value;
  }
}

// The same column under its own weight along its beams (density and gravity, loads along links:
// docs/theory.md §13.3): each beam takes the mean of its ends' axial forces, which converges to
// Greenhill's load as h² like the lumped weight.
TEST(CriticalLoad, ColumnUnderItsWeightAlongItsBeamsConvergesToGreenhill) {
  constexpr double kDensity = 7850, kGravity = 9.81;
  const double weight = kDensity * section_properties(kBar).A * kGravity;  // N/m
  expect_converges_to_greenhill(
      [&](int elements) {
        Model m = column(elements, End::clamped, End::free, 0.0);
        m.loads.clear();
        for (Link& link : m.links) std::get<BeamLink>(link.kind).material.density = kDensity;
        m.gravity = Vec3(0, 0, -kGravity);
        return critical_factor(m);
      },
      weight);
}

// Beyond 6·kMostDenseNodes load directions the eigenproblem is solved by Arnoldi's iteration: the
// same factor as every eigenvalue of the reduced dense problem (1e-10), here for a column of 60
// beams (366 unknowns), and Euler's load.
TEST(CriticalLoad, ArnoldiIterationFindsTheDenseFactor) {
  const Model model = column(60, End::pinned, End::pinned, -1000.0);
  const Result result = solve(model);
  const detail::Topology topology = detail::build_topology(model);
  std::vector<std::string> notes;
  auto factor = [&](detail::EigenMethod method) {
    const CriticalLoad critical =
        detail::critical_load(model, topology, {}, with_critical_load(), result,
                              detail::loads_at_ends(model, topology), notes, method);
    EXPECT_TRUE(critical.factor);
    return critical.factor.value_or(0.0);
  };
  const double dense = factor(detail::EigenMethod::dense);
  const double iterative = factor(detail::EigenMethod::iterative);
  EXPECT_NEAR(iterative / dense, 1.0, 1e-10);
  // From above, by the discretisation error of 60 elements (8.1e-9 at 64, times (64/60)⁴).
  EXPECT_GT(dense * 1000.0 / euler(1.0) - 1, 0.0);
  EXPECT_LT(dense * 1000.0 / euler(1.0) - 1, 2e-8);
  EXPECT_TRUE(notes.empty());
  // The same, automatically: 60 nodes of 5 load directions each are beyond the dense bound.
  EXPECT_EQ(critical_factor(model), iterative);
}

// The weight lumped at the nodes (qL/n inside, qL/2n at the top).
double greenhill_factor(int elements, double weight_per_metre) {
  Model m = column(elements, End::clamped, End::free, 0.0);
  m.loads.clear();
  const double share = weight_per_metre * kHeight / elements;
  for (int i = 1; i <= elements; ++i)
    m.add_load("P" + std::to_string(i), "L" + std::to_string(i),
               wrench(0, 0, -(i == elements ? share / 2 : share)));
  return critical_factor(m);
}

TEST(CriticalLoad, ColumnUnderItsOwnWeightConvergesToGreenhill) {
  constexpr double kWeight = 100.0;  // N/m
  expect_converges_to_greenhill([&](int elements) { return greenhill_factor(elements, kWeight); },
                                kWeight);
}

// A rigid bar of length L standing on a torsional spring k (an elastic revolute support),
// compressed by P at its top: P_cr = k/L, from the load term of the rigid link alone.
TEST(CriticalLoad, RigidBarOnATorsionalSpringBucklesAtKOverL) {
  constexpr double k = 5e4, L = 0.8, P = 1000;
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("E", Vec3(0, 0, L));
  m.add_rigid_link("bar", "O", "E");
  m.add_support("hinge", "O", {}, Connection::elastic(Kinematics::revolute(Vec3::UnitY()), k));
  m.add_load("E", std::nullopt, wrench(0, 0, -P));
  const Result r = solve(m, with_critical_load());
  ASSERT_TRUE(r.critical_load && r.critical_load->factor);
  EXPECT_NEAR(*r.critical_load->factor * P / (k / L), 1.0, 1e-12);
  EXPECT_EQ(r.critical_load->mode, "support 'hinge' rotates");
}

// Two rigid bars L1 (below) and L2 on springs k1 (at the ground) and k2 (between them), P at the
// top: K·θ = P·diag(L1, L2)·θ with K = [[k1 + k2, −k2], [−k2, k2]], θ the bars' tilts; the
// smallest root of L1·L2·P² − (L1·k2 + L2·(k1 + k2))·P + k1·k2 = 0.
TEST(CriticalLoad, TwoRigidBarsOnSpringsMatchTheirTwoByTwoEigenproblem) {
  constexpr double k1 = 8e4, k2 = 3e4, L1 = 0.6, L2 = 0.9, P = 500;
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("B", Vec3(0, 0, L1));
  m.add_point("C", Vec3(0, 0, L1 + L2));
  m.add_rigid_link("lower", "O", "B");
  m.add_rigid_link("upper", "B", "C");
  m.add_support("ground", "O", {}, Connection::elastic(Kinematics::revolute(Vec3::UnitY()), k1));
  m.add_joint("knee", "B", {"lower", "upper"},
              Connection::elastic(Kinematics::revolute(Vec3::UnitY()), k2));
  m.add_load("C", std::nullopt, wrench(0, 0, -P));
  const double a = L1 * L2, b = -(L1 * k2 + L2 * (k1 + k2)), c = k1 * k2;
  const double exact = (-b - std::sqrt(b * b - 4 * a * c)) / (2 * a);
  const Result r = solve(m, with_critical_load());
  ASSERT_TRUE(r.critical_load && r.critical_load->factor);
  EXPECT_NEAR(*r.critical_load->factor * P / exact, 1.0, 1e-12);
  // The first mode turns both springs; the knee's relative turn θ2 − θ1 and the ground's θ1.
  EXPECT_NE(r.critical_load->mode.find("joint 'knee' rotates"), std::string::npos)
      << r.critical_load->mode;
}

// The same column of bars, the top bar a lever sideways: a horizontal arm from C carries the
// load at its end, so that the knee's moment about x is held by the hinge's constraint. The
// arm's yaw under the load is what the joint's turned axis sees; the critical factor must not
// depend on which of two equivalent descriptions of the top is used: the arm as one rigid link
// or as two in line welded at their middle.
TEST(CriticalLoad, ARigidLinkSplitInTwoGivesTheSameFactor) {
  auto build = [](bool split) {
    Model m;
    m.add_point("O", Vec3::Zero());
    m.add_point("B", Vec3(0, 0, 0.7));
    m.add_point("C", Vec3(0.2, 0.1, 1.2));
    m.add_point("M", Vec3(0.45, 0.1, 1.25));
    m.add_point("T", Vec3(0.7, 0.1, 1.3));
    m.add_beam("post", "O", "B", kSteel, Section::tube(0.05, 0.004));
    m.add_rigid_link("upper", "B", "C");
    if (split) {
      m.add_rigid_link("arm1", "C", "M");
      m.add_rigid_link("arm2", "M", "T");
    } else {
      m.add_rigid_link("arm", "C", "T");
    }
    m.add_support("ground", "O", {}, Connection::rigid());
    m.add_joint("knee", "B", {"post", "upper"},
                Connection::elastic(Kinematics::revolute(Vec3::UnitY()), 2e4));
    m.add_joint("wrist", "C", {"upper", split ? "arm1" : "arm"},
                Connection::elastic(Kinematics::revolute(Vec3::UnitZ()), 1e4));
    m.add_load("T", std::nullopt, wrench(0, 0, -300, 0, 0, 0));
    return m;
  };
  const double whole = critical_factor(build(false)), split = critical_factor(build(true));
  EXPECT_NEAR(split / whole, 1.0, 1e-10);
}

// A post of height h on a torsional spring k1 about x (an elastic support), a wrist at its top
// turning about z on a spring k2 (its first end the post), a rigid arm of length b along x,
// and the dead force F = (−Q, 0, −P) at the arm's end T. With θ1, θ2 the two turns,
// T = R_x(θ1)·(h·e_z + R_z(θ2)·b·e_x), and the load's potential −F·T has the Hessian −H,
// H = [[−h·F_z, b·F_z], [b·F_z, −b·F_x]] = [[h·P, −b·P], [−b·P, b·Q]]: det(diag(k1, k2) − λ·H)
// = 0. The cross term b·F_z is the wrist's: its moment b·P about y, across its axis, seen along
// the axis turned by θ1.
TEST(CriticalLoad, WristTurnedByItsPostMatchesTheEnergyHessian) {
  constexpr double h = 1.0, b = 0.5, P = 100, Q = 300, k1 = 2e4, k2 = 1e4;
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("A", Vec3(0, 0, h));
  m.add_point("T", Vec3(b, 0, h));
  m.add_rigid_link("post", "O", "A");
  m.add_rigid_link("arm", "A", "T");
  m.add_support("ground", "O", {}, Connection::elastic(Kinematics::revolute(Vec3::UnitX()), k1));
  m.add_joint("wrist", "A", {"post", "arm"},
              Connection::elastic(Kinematics::revolute(Vec3::UnitZ()), k2));
  m.add_load("T", std::nullopt, wrench(-Q, 0, -P));
  const double a2 = h * P * b * Q - b * b * P * P, a1 = -(k1 * b * Q + k2 * h * P), a0 = k1 * k2;
  const double exact = (-a1 - std::sqrt(a1 * a1 - 4 * a2 * a0)) / (2 * a2);
  const Result r = solve(m, with_critical_load());
  ASSERT_TRUE(r.critical_load && r.critical_load->factor);
  EXPECT_NEAR(*r.critical_load->factor / exact, 1.0, 1e-12);
}

// ---- a workspace's poses and sweeps ---------------------------------------------------------

// The tripteron at its default pose and two more: members of one structure.
std::vector<Model> tripteron_poses() {
  const ModelFamily family =
      load_model_family(std::string(STIFFMSA_SOURCE_DIR) + "/examples/tripteron-parametric.yaml");
  std::vector<Model> poses;
  for (const Vec3& p : {Vec3(0.32, 0.28, 0.30), Vec3(0.35, 0.25, 0.28), Vec3(0.29, 0.31, 0.33)}) {
    std::vector<double> values = family.default_values();
    values[*family.find_parameter("px")] = p.x();
    values[*family.find_parameter("py")] = p.y();
    values[*family.find_parameter("pz")] = p.z();
    poses.push_back(family.build(values));
  }
  return poses;
}

void expect_same_critical_load(const Result& reused, const Result& alone) {
  ASSERT_TRUE(reused.critical_load && reused.critical_load->factor);
  ASSERT_TRUE(alone.critical_load && alone.critical_load->factor);
  EXPECT_NEAR(*reused.critical_load->factor / *alone.critical_load->factor, 1.0, 1e-12);
  EXPECT_EQ(reused.critical_load->mode, alone.critical_load->mode);
}

// A workspace's solve lends the critical load its blocks, tree order and buffers
// (CriticalLoadReuse): each pose gets the factor and mode of its own one-shot solve, whatever
// was solved before it, in the linear mode and in the loaded one (which finds it unasked).
TEST(CriticalLoad, AWorkspaceOfManyPosesGivesEachPoseItsOneShotFactor) {
  const std::vector<Model> poses = tripteron_poses();
  SolveOptions loaded;
  loaded.mode = AnalysisMode::loaded;
  for (const SolveOptions& options : {with_critical_load(), loaded}) {
    Workspace workspace(poses.front());
    for (int round = 0; round < 2; ++round)
      for (const Model& pose : poses)
        expect_same_critical_load(solve(workspace, pose, options), solve(pose, options));
  }
}

// Where the linear solve factorises (a frame), each load case's factor too.
TEST(CriticalLoad, AFrameSolvedTwiceInItsWorkspaceGivesTheOneShotFactors) {
  const Model frame =
      load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/portal-frame-load-cases.yaml");
  const Result alone = solve(frame, with_critical_load());
  ASSERT_FALSE(alone.load_cases.empty());
  Workspace workspace(frame);
  for (int round = 0; round < 2; ++round) {
    const Result reused = solve(workspace, frame, with_critical_load());
    expect_same_critical_load(reused, alone);
    ASSERT_EQ(reused.load_cases.size(), alone.load_cases.size());
    for (std::size_t c = 0; c < alone.load_cases.size(); ++c)
      expect_same_critical_load(reused.load_cases[c], alone.load_cases[c]);
  }
}

// The tripteron's tree solve cuts 21 unknowns: a second tree solve on the same blocks, of other
// columns, that takes the first one's factorised cut system (tree_solve_with_cut_system_of)
// gives the solution of a tree solve of its own, at each pose.
TEST(CriticalLoad, TheLinearSolvesCutSystemSolvesOtherColumnsAsATreeSolveOfTheirOwn) {
  for (const Model& pose : tripteron_poses()) {
    const detail::Topology topology = detail::build_topology(pose);
    const detail::Blocks blocks = detail::make_blocks(pose, topology, {});
    const std::optional<detail::TreeOrder> order = detail::tree_order(topology);
    ASSERT_TRUE(order);
    detail::TreeScratch linear, alone, reused;
    const std::optional<detail::Index> cuts = detail::tree_solve(
        blocks, topology, *order, detail::load_cases(pose, topology), 1e-14, linear);
    ASSERT_TRUE(cuts);
    EXPECT_EQ(*cuts, 21);
    // A unit wrench in each direction at every second link end, no preload.
    detail::EndWrenches external;
    const detail::Index columns = 6 * ((topology.end_count() + 1) / 2);
    external.reset(topology.end_count(), columns, 0);
    for (int end = 0; end < topology.end_count(); end += 2)
      for (int c = 0; c < 6; ++c) external.add(end, 6 * (end / 2) + c, Vec6::Unit(c));
    ASSERT_TRUE(detail::tree_solve(blocks, topology, *order, external, 1e-14, alone));
    const std::optional<detail::Index> reused_cuts =
        detail::tree_solve_with_cut_system_of(linear, blocks, topology, *order, external, reused);
    ASSERT_TRUE(reused_cuts);
    EXPECT_EQ(*reused_cuts, 21);
    ASSERT_EQ(reused.x.rows(), alone.x.rows());
    ASSERT_EQ(reused.x.cols(), columns);
    ASSERT_GT(alone.x.cwiseAbs().maxCoeff(), 0.0);
    // The same operations on each column: the same numbers.
    EXPECT_TRUE(reused.x == alone.x);
    // Nothing to take from a scratch that holds no cut system.
    detail::TreeScratch empty;
    EXPECT_FALSE(
        detail::tree_solve_with_cut_system_of(empty, blocks, topology, *order, external, reused));
  }
}

// A workspace's critical load takes the linear solve's cut system (solver "tree_with_cuts"):
// the very factor and mode of the computation that takes nothing from the solve, at each pose,
// in the linear mode and the loaded one.
TEST(CriticalLoad, ThePosesCutSystemGivesTheFactorOfAComputationOfItsOwn) {
  const std::vector<Model> poses = tripteron_poses();
  SolveOptions loaded;
  loaded.mode = AnalysisMode::loaded;
  for (const SolveOptions& options : {with_critical_load(), loaded}) {
    Workspace workspace(poses.front());
    for (const Model& pose : poses) {
      const Result reused = solve(workspace, pose, options);
      const Result linear = solve(pose, with_critical_load());
      ASSERT_EQ(linear.report.solver, SolverUsed::tree_with_cuts);
      const detail::Topology topology = detail::build_topology(pose);
      std::vector<std::string> notes;
      const CriticalLoad alone =
          detail::critical_load(pose, topology, {}, with_critical_load(), linear,
                                detail::loads_at_ends(pose, topology), notes);
      EXPECT_TRUE(notes.empty());
      ASSERT_TRUE(reused.critical_load && reused.critical_load->factor && alone.factor);
      EXPECT_EQ(*reused.critical_load->factor, *alone.factor);
      EXPECT_EQ(reused.critical_load->mode, alone.mode);
    }
  }
}

// A sweep keeps no critical load factor, so its workspaces skip it (skip_critical_loads): its
// loaded poses are measured as the solves that find it measure them.
TEST(CriticalLoad, ASweepSkipsItAndMeasuresItsPosesAsTheSolvesThatFindIt) {
  const std::vector<Model> poses = tripteron_poses();
  const Structure structure(poses.front());
  std::vector<double> sets;
  for (const Model& pose : poses) {
    const std::vector<double> values = structure.values_of(pose);
    sets.insert(sets.end(), values.begin(), values.end());
  }
  SweepOptions options;
  options.solve.mode = AnalysisMode::loaded;
  options.keep_matrices = true;
  options.threads = 1;
  const std::vector<PoseResult> swept = solve_poses(structure, sets, options);
  ASSERT_EQ(swept.size(), poses.size());
  Workspace workspace(structure);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Result solved = solve(workspace, structure.values_of(poses[i]), options.solve);
    ASSERT_TRUE(solved.critical_load && solved.critical_load->factor);
    ASSERT_EQ(swept[i].status, PoseStatus::ok) << swept[i].message;
    EXPECT_EQ(*swept[i].end_effectors[0].compliance, *solved.end_effectors[0].compliance);
  }
}

// ---- SolveOptions::critical_load: unset, true, false -----------------------------------------

// A result file's text without its critical load keys (critical_load_factor, _mode), at every
// level: what the rest of the result says.
std::string without_critical_load_lines(const Result& result) {
  std::istringstream in(result_to_json(result));
  std::string line, kept;
  while (std::getline(in, line))
    if (line.find("\"critical_load_") == std::string::npos) kept += line + '\n';
  return kept;
}

void expect_no_critical_load(const Result& result) {
  EXPECT_FALSE(result.critical_load.has_value());
  for (const Result& c : result.load_cases) EXPECT_FALSE(c.critical_load.has_value());
  if (result.linear) EXPECT_FALSE(result.linear->critical_load.has_value());
}

// The loaded mode finds the factor unasked (its result file's contract has it); a caller that
// says false gets none, and every other number of the result to the last bit, through a
// workspace pose after pose as in one-shot solves.
TEST(CriticalLoad, TheLoadedModeToldNotToFindItHasNoneAndTheSameOtherNumbers) {
  const std::vector<Model> poses = tripteron_poses();
  SolveOptions loaded;
  loaded.mode = AnalysisMode::loaded;
  SolveOptions without = loaded;
  without.critical_load = false;
  Workspace with_factor(poses.front()), without_factor(poses.front());
  for (const Model& pose : poses) {
    const Result usual = solve(with_factor, pose, loaded);
    ASSERT_TRUE(usual.critical_load && usual.critical_load->factor);
    const Result skipped = solve(without_factor, pose, without);
    expect_no_critical_load(skipped);
    EXPECT_EQ(result_to_json(skipped).find("critical_load"), std::string::npos);
    ASSERT_TRUE(usual.end_effectors.front().compliance && skipped.end_effectors.front().compliance);
    EXPECT_TRUE(*usual.end_effectors.front().compliance ==
                *skipped.end_effectors.front().compliance);
    EXPECT_EQ(without_critical_load_lines(skipped), without_critical_load_lines(usual));
    EXPECT_EQ(without_critical_load_lines(solve(pose, without)),
              without_critical_load_lines(solve(pose, loaded)));
  }
}

// The same for a model whose linear results carry the factor unasked (load cases): false finds
// none in any case, true and unset the same factors.
TEST(CriticalLoad, LoadCasesToldNotToFindItHaveNoneAndTheSameOtherNumbers) {
  const Model frame =
      load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/portal-frame-load-cases.yaml");
  const Result usual = solve(frame);
  ASSERT_FALSE(usual.load_cases.empty());
  ASSERT_TRUE(usual.critical_load);
  for (const Result& c : usual.load_cases) ASSERT_TRUE(c.critical_load);
  SolveOptions never;
  never.critical_load = false;
  const Result skipped = solve(frame, never);
  expect_no_critical_load(skipped);
  EXPECT_EQ(without_critical_load_lines(skipped), without_critical_load_lines(usual));
  EXPECT_EQ(result_to_json(solve(frame, with_critical_load())), result_to_json(usual));
}

// True finds it where the contract does not (a model of plain loads, the linear mode), and
// changes nothing else; unset and false find none there.
TEST(CriticalLoad, TrueFindsItWhereTheContractDoesNot) {
  const Model model = column(4, End::pinned, End::pinned, -1000.0);
  EXPECT_FALSE(solve(model).critical_load.has_value());
  SolveOptions never;
  never.critical_load = false;
  EXPECT_FALSE(solve(model, never).critical_load.has_value());
  const Result asked = solve(model, with_critical_load());
  ASSERT_TRUE(asked.critical_load && asked.critical_load->factor);
  EXPECT_EQ(without_critical_load_lines(asked), without_critical_load_lines(solve(model)));
}

// ---- the reduced eigenproblem's eigenvalues ---------------------------------------------------

// Both spectra sorted alike, and each eigenvalue of the QR iteration within `relative` of the
// spectral radius from Eigen's.
void expect_same_spectrum(const MatX& a, double relative) {
  auto sorted = [](Eigen::VectorXcd v) {
    std::vector<std::complex<double>> values(v.data(), v.data() + v.size());
    std::sort(values.begin(), values.end(), [](auto x, auto y) {
      return x.real() != y.real() ? x.real() < y.real() : x.imag() < y.imag();
    });
    return values;
  };
  const auto ours = sorted(detail::eigenvalues_of(a).values);
  const auto eigen = sorted(Eigen::EigenSolver<MatX>(a, false).eigenvalues());
  ASSERT_EQ(ours.size(), eigen.size());
  double radius = 0;
  for (const auto& e : eigen) radius = std::max(radius, std::abs(e));
  for (std::size_t i = 0; i < ours.size(); ++i)
    EXPECT_LE(std::abs(ours[i] - eigen[i]), relative * radius) << a.rows() << "×" << a.cols();
}

// The double-shift QR iteration gives Eigen's EigenSolver's eigenvalues to rounding: on
// matrices of every size up to 40 (random, with complex pairs), of low rank (the reduced
// eigenproblem's zero eigenvalues), with known real eigenvalues (similar to a diagonal), a
// rotation's pure imaginary pair, a triangular matrix, and the empty, 1×1 and zero ones.
TEST(CriticalLoad, TheQrIterationFindsEigensEigenvalues) {
  constexpr double kRounding = 1e-12;
  // A spectrum built as B·D·B⁻¹ carries the rounding of B's inverse, amplified by B's condition.
  constexpr double kBuiltSpectrum = 1e-10;
  std::srand(7);
  for (Eigen::Index n = 1; n <= 40; n += (n < 8 ? 1 : 7)) {
    const MatX random = MatX::Random(n, n);
    expect_same_spectrum(random, kRounding);
    const Eigen::Index rank = std::max<Eigen::Index>(1, n / 3);
    expect_same_spectrum(MatX::Random(n, rank) * MatX::Random(rank, n), kRounding);
    VecX diagonal(n);
    for (Eigen::Index i = 0; i < n; ++i) diagonal(i) = 1.0 + static_cast<double>(i % 5);
    const MatX basis = MatX::Random(n, n) + static_cast<double>(n) * MatX::Identity(n, n);
    const MatX known = basis * diagonal.asDiagonal() * basis.inverse();
    expect_same_spectrum(known, kBuiltSpectrum);
  }
  MatX rotation(2, 2);
  rotation << 0, -1, 1, 0;
  const Eigen::VectorXcd pair = detail::eigenvalues_of(rotation).values;
  EXPECT_EQ(std::abs(pair(0).imag()), 1.0);
  EXPECT_EQ(pair(0).real(), 0.0);
  MatX triangular = MatX::Identity(6, 6) * 2.0;  // split everywhere from the start
  for (Eigen::Index i = 0; i + 1 < 6; ++i) triangular(i, i + 1) = 1e-3;
  expect_same_spectrum(triangular, kRounding);
  EXPECT_EQ(detail::eigenvalues_of(MatX(0, 0)).values.size(), 0);
  EXPECT_EQ(detail::eigenvalues_of(MatX::Constant(1, 1, -3.5)).values(0),
            std::complex<double>(-3.5));
  EXPECT_TRUE(detail::eigenvalues_of(MatX::Zero(5, 5)).values.isZero(0));
  MatX poisoned = MatX::Identity(4, 4);
  poisoned(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(detail::eigenvalues_of(poisoned).values.size(), 0);
  poisoned(2, 1) = std::numeric_limits<double>::infinity();
  EXPECT_EQ(detail::eigenvalues_of(poisoned).values.size(), 0);
}

// The QR iteration's eigenvalues of `a` are `exact` (in any order, matched one to one), each
// within `tolerance`, and Eigen's EigenSolver was not needed.
void expect_spectrum_without_fallback(const MatX& a, const std::vector<std::complex<double>>& exact,
                                      double tolerance, const std::string& label) {
  const detail::Eigenvalues found = detail::eigenvalues_of(a);
  EXPECT_FALSE(found.by_eigen_solver) << label;
  ASSERT_EQ(found.values.size(), static_cast<Eigen::Index>(exact.size())) << label;
  std::vector<std::complex<double>> left(found.values.data(),
                                         found.values.data() + found.values.size());
  for (const std::complex<double>& value : exact) {
    const auto nearest = std::min_element(left.begin(), left.end(), [&](auto x, auto y) {
      return std::abs(x - value) < std::abs(y - value);
    });
    EXPECT_LE(std::abs(*nearest - value), tolerance) << label << ": " << value;
    left.erase(nearest);
  }
}

// Matrices on which the double shifts of the trailing 2 × 2 block cycle, so that only the
// exceptional shift moves the iteration, about 1000·I: the exceptional pair centred at the
// trailing diagonal entry, as LAPACK's, converges without Eigen's EigenSolver. Day's 4 × 4
// example of a cycle (two 2-cycles coupled by h; its eigenvalues ±√(1 − h²/4) ± i·h/2) ran out
// of sweeps with the pair centred at 0, which barely moves a matrix near 1000·I; 1000·I plus a
// cyclic permutation (1000 plus the n-th roots of unity) converged with it too, in more
// sweeps. Each eigenvalue is within the backward error of the orthogonal similarity
// transformations, a few ε of the spectral radius: both matrices are far from defective.
TEST(CriticalLoad, TheExceptionalShiftFindsASpectrumFarFromZero) {
  constexpr double kCentre = 1000;
  constexpr double kBackwardError = 1e-14 * (kCentre + 1);  // of the spectral radius
  for (double h : {1e-2, 1e-4, 1e-6}) {
    MatX day = kCentre * MatX::Identity(4, 4);
    day(0, 1) = day(1, 0) = day(2, 3) = day(3, 2) = 1;
    day(1, 2) = -h;
    day(2, 1) = h;
    const double real = std::sqrt(1 - h * h / 4);
    expect_spectrum_without_fallback(day,
                                     {{kCentre + real, h / 2},
                                      {kCentre + real, -h / 2},
                                      {kCentre - real, h / 2},
                                      {kCentre - real, -h / 2}},
                                     kBackwardError, "Day's matrix, h = " + std::to_string(h));
  }
  for (Eigen::Index n = 3; n <= 16; ++n) {
    MatX cyclic = kCentre * MatX::Identity(n, n);
    for (Eigen::Index i = 0; i < n; ++i) cyclic((i + 1) % n, i) = 1;
    std::vector<std::complex<double>> roots;
    for (Eigen::Index k = 0; k < n; ++k)
      roots.push_back(kCentre + std::polar(1.0, 2 * std::numbers::pi * static_cast<double>(k) /
                                                    static_cast<double>(n)));
    expect_spectrum_without_fallback(cyclic, roots, kBackwardError,
                                     "cyclic, n = " + std::to_string(n));
  }
}

// ---- kernels ---------------------------------------------------------------------------------

// A rotation by the rotation vector v (Rodrigues).
Mat3 rotation(const Vec3& v) {
  const double angle = v.norm();
  if (angle == 0) return Mat3::Identity();
  return Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
}

// The rigid link's moment balance about its from end in the turned geometry, M_from =
// −M_to − R(φ)·d × F_to, changes with φ as the chord term says: M_from's change is
// +[F×]·(Δp_to − Δp_from) with Δp_to − Δp_from = φ × d.
TEST(LoadTerms, ChordTermIsTheTurnedLeversMoment) {
  const Vec3 d(0.3, -0.2, 0.5), force(120, -40, 75), m_to(3, 1, -2);
  const Mat12 k = detail::chord_load_stiffness(force);
  for (int axis = 0; axis < 3; ++axis) {
    const double h = 1e-6;
    const Vec3 phi = h * Vec3::Unit(axis);
    auto moment_from = [&](const Vec3& turn) {
      return Vec3(-m_to - (rotation(turn) * d).cross(force));
    };
    const Vec3 change = (moment_from(phi) - moment_from(-phi)) / 2;
    Eigen::Matrix<double, 12, 1> deflection = Eigen::Matrix<double, 12, 1>::Zero();
    deflection.segment<3>(3) = phi;           // the from end turns
    deflection.segment<3>(6) = phi.cross(d);  // and the to end follows rigidly
    const Eigen::Matrix<double, 12, 1> extra = k * deflection;
    // The wrench the link's from end needs beside the linear one: the turned balance's change.
    EXPECT_LT((extra.segment<3>(3) - change).norm(), 1e-9 * change.norm() + 1e-15) << axis;
    EXPECT_TRUE(extra.head<3>().isZero(0));
    EXPECT_TRUE(extra.tail<6>().isZero(0));
  }
}

// A joint whose axes turn with its first end: the generalised force along the turned free
// directions, Λ_p(φ)·R = Λ_p·R(φ)ᵀ·R, changes by −Λ_p·[φ × F; φ × M]; the joint's linear rows
// see the link end's wrench plus the term's, so Λ_p·(K_L·Δt) must be that change.
TEST(LoadTerms, JointTermIsTheReactionSeenAlongTurnedAxes) {
  for (const Kinematics& kinematics :
       {Kinematics::revolute(Vec3(0.3, 0.4, 0.866).normalized()),
        Kinematics::universal(Vec3::UnitX(), Vec3(0, 0.6, 0.8)),
        Kinematics::prismatic(Vec3(1, 1, 0).normalized()), Kinematics::planar(Vec3::UnitZ())}) {
    const detail::FreeDirections directions = detail::free_directions(kinematics);
    const Vec6 reaction = (Vec6() << 50, -20, 35, 4, -7, 2).finished();
    const MatX k = detail::joint_load_stiffness(directions, {reaction, -reaction});
    const MatX free = directions.free();
    for (int axis = 0; axis < 3; ++axis) {
      const double h = 1e-6;
      auto seen = [&](const Vec3& turn) {
        Vec6 turned_back;
        turned_back << rotation(turn).transpose() * reaction.head<3>(),
            rotation(turn).transpose() * reaction.tail<3>();
        return VecX(free * turned_back);
      };
      const VecX change = (seen(h * Vec3::Unit(axis)) - seen(-h * Vec3::Unit(axis))) / 2;
      VecX deflection = VecX::Zero(12);
      deflection.segment<3>(3) = h * Vec3::Unit(axis);
      deflection.segment<3>(9) = h * Vec3::Unit(axis);
      const VecX extra = k * deflection;
      EXPECT_LT((free * extra.head<6>() - change).norm(), 1e-9 * reaction.norm() * h)
          << to_string(kinematics.type) << " axis " << axis;
      EXPECT_LT((extra.head<6>() + extra.tail<6>()).norm(), 1e-12 * reaction.norm() * h);
    }
  }
}

}  // namespace
}  // namespace stiffmsa

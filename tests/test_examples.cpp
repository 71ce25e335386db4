// Every model in examples/ is loaded, solved, and compared with the closed forms of
// theory-notes.md ("Closed forms a test can pin"). The reference numbers are computed here from
// the model's inputs (points, sections, materials, joint stiffnesses) with textbook formulas,
// never from the engine's output. Where a formula is exact only for a variant of the file (rigid
// links, say), the test builds that variant from the loaded model and says why.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cctype>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "builders.hpp"
#include "closed_forms.hpp"
#include "solve_comparison.hpp"
#include "stiffmsa/stiffmsa.hpp"

namespace {

using reference::relative_difference_scaled;
using stiffmsa::BeamLink;
using stiffmsa::Connection;
using stiffmsa::EndEffectorResult;
using stiffmsa::JointType;
using stiffmsa::Mat3;
using stiffmsa::Mat6;
using stiffmsa::MatX;
using stiffmsa::Model;
using stiffmsa::Result;
using stiffmsa::Vec3;
using stiffmsa::Vec6;

// Every comparison with a closed form: the arithmetic of both sides is exact to rounding.
constexpr double kTolerance = 1e-9;

const std::vector<std::string> kExampleFiles = {
    "cantilever.yaml",       "planar-2r.yaml",          "industrial-6axis.yaml",
    "planar-3rpr.yaml",      "gough-stewart-6ups.yaml", "tripteron.yaml",
    "delta-parametric.yaml", "delta-us-parametric.yaml"};

Model load_example(const std::string& file_name) {
  return stiffmsa::load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/" + file_name);
}

// ---- lookups by the names the example files use -------------------------------------------

Vec3 position(const Model& model, const std::string& point) {
  const stiffmsa::Point* p = model.find_point(point);
  if (p == nullptr) throw std::invalid_argument("no point named " + point);
  return p->position;
}

const stiffmsa::Link& link(const Model& model, const std::string& name) {
  const stiffmsa::Link* l = model.find_link(name);
  if (l == nullptr) throw std::invalid_argument("no link named " + name);
  return *l;
}

const EndEffectorResult& end_effector(const Result& result, const std::string& name) {
  for (const auto& ee : result.end_effectors)
    if (ee.name == name) return ee;
  throw std::invalid_argument("no end effector named " + name);
}

// The effort of a one-direction actuated joint, or its support reaction, by name.
double actuator_effort(const Result& result, const std::string& name) {
  for (const auto& j : result.joints)
    if (j.name == name) {
      if (!j.effort || j.effort->size() != 1)
        throw std::invalid_argument(name + " has no scalar effort");
      return (*j.effort)(0);
    }
  throw std::invalid_argument("no joint named " + name);
}

Vec6 support_reaction(const Result& result, const std::string& name) {
  for (const auto& s : result.supports)
    if (s.name == name) {
      if (!s.reaction) throw std::invalid_argument(name + " has no reaction");
      return *s.reaction;
    }
  throw std::invalid_argument("no support named " + name);
}

// A joint or a support: where it is and what it does.
struct NamedConnection {
  Vec3 at;
  const Connection* connection = nullptr;
};

NamedConnection connection(const Model& model, const std::string& name) {
  for (const auto& j : model.joints)
    if (j.name == name) return {position(model, j.at), &j.connection};
  for (const auto& s : model.supports)
    if (s.name == name) return {position(model, s.at), &s.connection};
  throw std::invalid_argument("no joint or support named " + name);
}

stiffmsa::Joint& joint(Model& model, const std::string& name) {
  for (auto& j : model.joints)
    if (j.name == name) return j;
  throw std::invalid_argument("no joint named " + name);
}

// The scalar spring of a one-direction (revolute or prismatic) elastic joint or support.
double scalar_stiffness(const Connection& c) {
  if (!c.stiffness || c.stiffness->rows() != 1 || c.stiffness->cols() != 1)
    throw std::invalid_argument("expected a scalar stiffness");
  return (*c.stiffness)(0, 0);
}

// ---- beams, from sections.md and model-format.md ("Beam axes") -----------------------------

struct BeamProperties {
  double E = 0, G = 0, A = 0, Iy = 0, Iz = 0, J = 0;
};

// Section and material constants from the section's dimensions, for the shapes the examples
// use; written from sections.md, not taken from the library.
BeamProperties beam_properties(const BeamLink& beam) {
  constexpr double pi = std::numbers::pi;
  const stiffmsa::Section& s = beam.section;
  BeamProperties p;
  p.E = beam.material.E;
  p.G = beam.material.G ? *beam.material.G : p.E / (2 * (1 + *beam.material.nu));
  switch (s.shape) {
    case stiffmsa::SectionShape::circle:
      p.A = pi * s.D * s.D / 4;
      p.Iy = p.Iz = pi * std::pow(s.D, 4) / 64;
      p.J = pi * std::pow(s.D, 4) / 32;
      break;
    case stiffmsa::SectionShape::tube: {
      const double d = s.D - 2 * s.t;
      p.A = pi * (s.D * s.D - d * d) / 4;
      p.Iy = p.Iz = pi * (std::pow(s.D, 4) - std::pow(d, 4)) / 64;
      p.J = pi * (std::pow(s.D, 4) - std::pow(d, 4)) / 32;
      break;
    }
    case stiffmsa::SectionShape::rect_tube: {
      const double bi = s.b - 2 * s.t, hi = s.h - 2 * s.t;
      p.A = s.b * s.h - bi * hi;
      p.Iy = (s.b * std::pow(s.h, 3) - bi * std::pow(hi, 3)) / 12;
      p.Iz = (s.h * std::pow(s.b, 3) - hi * std::pow(bi, 3)) / 12;
      p.J = 2 * s.t * std::pow(s.b - s.t, 2) * std::pow(s.h - s.t, 2) / (s.b + s.h - 2 * s.t);
      break;
    }
    default: throw std::invalid_argument("no reference formula for this section shape");
  }
  return p;
}

// Rows: the beam's local x, y, z in global coordinates.
Mat3 beam_axes(const Vec3& from, const Vec3& to, const std::optional<Vec3>& zref) {
  const Vec3 x = (to - from).normalized();
  const Vec3 default_zref = x.cross(Vec3::UnitZ()).norm() < 1e-9 ? Vec3::UnitX() : Vec3::UnitZ();
  const Vec3 y = zref.value_or(default_zref).cross(x).normalized();
  Mat3 R;
  R.row(0) = x;
  R.row(1) = y;
  R.row(2) = x.cross(y);
  return R;
}

// Compliance of the beam's `to` end with its `from` end clamped, in global axes at `to`.
Mat6 cantilever_compliance(const Model& model, const std::string& link_name) {
  const stiffmsa::Link& beam_link = link(model, link_name);
  const auto& beam = std::get<BeamLink>(beam_link.kind);
  const Vec3 from = position(model, beam_link.from), to = position(model, beam_link.to);
  const BeamProperties p = beam_properties(beam);
  const Mat6 local =
      reference::cantilever_compliance((to - from).norm(), p.E, p.G, p.A, p.Iy, p.Iz, p.J);
  const Mat6 R6 = reference::rotate6(beam_axes(from, to, beam.zref));
  return R6.transpose() * local * R6;
}

// L/(EA) of a beam: its axial compliance, the only one a bar pinned at both ends uses.
double axial_compliance(const Model& model, const std::string& link_name) {
  const stiffmsa::Link& bar = link(model, link_name);
  const BeamProperties p = beam_properties(std::get<BeamLink>(bar.kind));
  return (position(model, bar.to) - position(model, bar.from)).norm() / (p.E * p.A);
}

// ---- chains of joints and links (virtual joint model) -------------------------------------

// End-effector twist per unit motion along a joint's single free direction.
Vec6 joint_twist(const NamedConnection& joint, const Vec3& ee) {
  const Vec3 axis = joint.connection->kinematics.axis.normalized();
  Vec6 twist;
  switch (joint.connection->kinematics.type) {
    case JointType::revolute: twist << axis.cross(ee - joint.at), axis; break;
    case JointType::prismatic: twist << axis, Vec3::Zero(); break;
    default: throw std::invalid_argument("only revolute and prismatic joints have a twist here");
  }
  return twist;
}

// One serial chain of a model, by the names of its parts: every beam among `links` adds its
// cantilever compliance, every spring its joint compliance. Exact for a chain whose beams run
// from the base towards the end effector (each clamped at `from` by the rest of the chain).
struct Chain {
  std::vector<std::string> links;    // rigid links among them add nothing
  std::vector<std::string> springs;  // elastic revolute or prismatic joints and supports
  std::vector<std::string> passive;  // passive revolute joints and supports
};

// Theory notes, VJM with flexible links: C = Σ J_i k_i⁻¹ J_iᵀ + Σ Ad_i C_i Ad_iᵀ, with every
// passive joint locked.
Mat6 locked_chain_compliance(const Model& model, const Chain& chain, const Vec3& ee) {
  Mat6 C = Mat6::Zero();
  for (const auto& name : chain.springs) {
    const NamedConnection spring = connection(model, name);
    const Vec6 J = joint_twist(spring, ee);
    C += J * J.transpose() / scalar_stiffness(*spring.connection);
  }
  for (const auto& name : chain.links) {
    const stiffmsa::Link& l = link(model, name);
    if (!std::holds_alternative<BeamLink>(l.kind)) continue;
    const Mat6 Ad = reference::twist_transport(ee - position(model, l.to));
    C += Ad * cantilever_compliance(model, name) * Ad.transpose();
  }
  return C;
}

// Theory notes, leg with passive joints: K = K0 − K0·Jq·(Jqᵀ·K0·Jq)⁻¹·Jqᵀ·K0.
Mat6 leg_stiffness(const Model& model, const Chain& leg, const Vec3& ee) {
  const Mat6 K0 = locked_chain_compliance(model, leg, ee).inverse();
  MatX Jq(6, static_cast<Eigen::Index>(leg.passive.size()));
  for (std::size_t i = 0; i < leg.passive.size(); ++i)
    Jq.col(static_cast<Eigen::Index>(i)) = joint_twist(connection(model, leg.passive[i]), ee);
  const MatX K0Jq = K0 * Jq;
  return K0 - K0Jq * (Jq.transpose() * K0Jq).ldlt().solve(K0Jq.transpose());
}

// Every link and every elastic joint or support of a purely serial model.
Chain whole_serial_model(const Model& model) {
  Chain chain;
  for (const auto& l : model.links) chain.links.push_back(l.name);
  for (const auto& j : model.joints)
    if (j.connection.stiffness) chain.springs.push_back(j.name);
  for (const auto& s : model.supports)
    if (s.connection.stiffness) chain.springs.push_back(s.name);
  return chain;
}

// Replaces every beam by a rigid link: the variant for which the joint-only formulas are exact.
void make_links_rigid(Model& model) {
  for (auto& link : model.links) link.kind = stiffmsa::RigidLink{};
}

// ---- checks -------------------------------------------------------------------------------

// The natural size of direction i of a compliance: C_ii, or, where the end effector is held
// rigidly in that direction (C_ii = 0), the largest C_kk. The examples' lengths are of the order
// of a metre, so that m and rad weigh alike there.
double diagonal_scale(const Mat6& compliance, int i) {
  return compliance(i, i) > 0 ? compliance(i, i) : compliance.diagonal().maxCoeff();
}

// Directions (0..5) in which the end effector is held rigidly: their rows of the compliance
// vanish, each entry against sqrt(scale_i·scale_j).
void expect_held_rigidly(const Mat6& compliance, const std::vector<int>& held) {
  for (int i : held)
    for (int j = 0; j < 6; ++j)
      EXPECT_LT(std::abs(compliance(i, j)), kTolerance * std::sqrt(diagonal_scale(compliance, i) *
                                                                   diagonal_scale(compliance, j)))
          << "direction " << i << ", column " << j;
}

// Under the model's loads, all at the end effector, the deflection is C·W. Each component is
// compared with sqrt(C_ii·WᵀCW), which bounds it for a positive semi-definite C.
void expect_deflection(const Vec6& deflection, const Mat6& reference_compliance, const Vec6& load) {
  const Vec6 expected = reference_compliance * load;
  const double energy = load.dot(expected);
  for (int i = 0; i < 6; ++i)
    EXPECT_LT(std::abs(deflection(i) - expected(i)),
              kTolerance * std::sqrt(diagonal_scale(reference_compliance, i) * energy))
        << "component " << i;
}

// The sum of the model's loads, all of which the examples apply at the end effector.
Vec6 total_load(const Model& model) {
  Vec6 sum = Vec6::Zero();
  for (const auto& load : model.loads) sum += load.wrench;
  return sum;
}

using stiffmsa::testing::wrench;

// ---- every example ------------------------------------------------------------------------

class EveryExample : public testing::TestWithParam<std::string> {};

TEST_P(EveryExample, LoadsSolvesAndGivesAConsistentEndEffector) {
  const Model model = load_example(GetParam());
  const Result result = stiffmsa::solve(model);

  EXPECT_LT(result.report.relative_residual, 1e-10);
  EXPECT_LT(result.report.equilibrium_error, 1e-9);
  EXPECT_TRUE(result.report.warnings.empty());

  // A newcomer's example: one named end effector, every load applied at it.
  ASSERT_EQ(model.end_effectors.size(), 1u);
  ASSERT_FALSE(model.loads.empty());
  for (const auto& load : model.loads) EXPECT_EQ(load.at, model.end_effectors[0].at);

  ASSERT_EQ(result.end_effectors.size(), 1u);
  const EndEffectorResult& ee = result.end_effectors[0];
  ASSERT_TRUE(ee.compliance);
  ASSERT_TRUE(ee.stiffness) << "every example is held elastically in all six directions";
  ASSERT_TRUE(ee.deflection);
  const Mat6& C = *ee.compliance;
  const Mat6& K = *ee.stiffness;

  EXPECT_LT(relative_difference_scaled(Mat6(C.transpose()), C), kTolerance);
  EXPECT_LT(relative_difference_scaled(Mat6(K.transpose()), K), kTolerance);
  Eigen::SelfAdjointEigenSolver<Mat6> eigen(K);
  EXPECT_GT(eigen.eigenvalues().minCoeff(), 0.0);

  // K·C = I, made dimensionless: with S = diag(sqrt(C_ii)), (S·K·S)(S⁻¹·C·S⁻¹) = S·(K·C)·S⁻¹.
  const Eigen::Array<double, 6, 1> s = C.diagonal().cwiseSqrt().array();
  const Mat6 scaled_product =
      (s.matrix().asDiagonal() * (K * C)) * s.inverse().matrix().asDiagonal();
  EXPECT_LT((scaled_product - Mat6::Identity()).cwiseAbs().maxCoeff(), kTolerance);

  // The deflection is the compliance times the load (all loads sit at the end effector).
  expect_deflection(*ee.deflection, C, total_load(model));
}

INSTANTIATE_TEST_SUITE_P(Examples, EveryExample, testing::ValuesIn(kExampleFiles),
                         [](const testing::TestParamInfo<std::string>& info) {
                           std::string name;
                           for (char c : info.param.substr(0, info.param.find('.')))
                             if (std::isalnum(static_cast<unsigned char>(c))) name += c;
                           return name;
                         });

// ---- cantilever.yaml ----------------------------------------------------------------------

// The data the file's header states, so that this test also checks the file reads as written.
constexpr double kCantileverLength = 1.2;
constexpr double kTubeDiameter = 0.06, kTubeWall = 0.004;
constexpr double kSteelE = 2.1e11, kSteelNu = 0.3;
constexpr double kTipForceZ = -500;

TEST(CantileverExample, TipComplianceIsTheTextbookBeam) {
  const Result result = stiffmsa::solve(load_example("cantilever.yaml"));
  const EndEffectorResult& tip = end_effector(result, "tip");
  ASSERT_TRUE(tip.compliance);
  const Mat6& C = *tip.compliance;

  constexpr double pi = std::numbers::pi, L = kCantileverLength, E = kSteelE;
  const double G = E / (2 * (1 + kSteelNu));
  const double d = kTubeDiameter - 2 * kTubeWall;
  const double A = pi * (kTubeDiameter * kTubeDiameter - d * d) / 4;
  const double I = pi * (std::pow(kTubeDiameter, 4) - std::pow(d, 4)) / 64, J = 2 * I;

  // Each entry against its own closed form, signs as in theory-notes: w' = −θy.
  EXPECT_NEAR(C(0, 0) / (L / (E * A)), 1.0, kTolerance);
  EXPECT_NEAR(C(1, 1) / (L * L * L / (3 * E * I)), 1.0, kTolerance);
  EXPECT_NEAR(C(2, 2) / (L * L * L / (3 * E * I)), 1.0, kTolerance);
  EXPECT_NEAR(C(3, 3) / (L / (G * J)), 1.0, kTolerance);
  EXPECT_NEAR(C(4, 4) / (L / (E * I)), 1.0, kTolerance);
  EXPECT_NEAR(C(5, 5) / (L / (E * I)), 1.0, kTolerance);
  EXPECT_NEAR(C(2, 4) / (-L * L / (2 * E * I)), 1.0, kTolerance);
  EXPECT_NEAR(C(4, 2) / (-L * L / (2 * E * I)), 1.0, kTolerance);
  EXPECT_NEAR(C(1, 5) / (L * L / (2 * E * I)), 1.0, kTolerance);
  EXPECT_NEAR(C(5, 1) / (L * L / (2 * E * I)), 1.0, kTolerance);
  // Everything else is uncoupled.
  const Mat6 expected = reference::cantilever_compliance(L, E, G, A, I, I, J);
  EXPECT_LT(relative_difference_scaled(C, expected), kTolerance);
}

TEST(CantileverExample, TipLoadDeflectsByTheBeamFormulasAndTheClampCarriesIt) {
  const Result result = stiffmsa::solve(load_example("cantilever.yaml"));
  const EndEffectorResult& tip = end_effector(result, "tip");
  ASSERT_TRUE(tip.deflection);
  const Vec6& deflection = *tip.deflection;

  constexpr double pi = std::numbers::pi, L = kCantileverLength, E = kSteelE, F = kTipForceZ;
  const double G = E / (2 * (1 + kSteelNu));
  const double d = kTubeDiameter - 2 * kTubeWall;
  const double A = pi * (kTubeDiameter * kTubeDiameter - d * d) / 4;
  const double I = pi * (std::pow(kTubeDiameter, 4) - std::pow(d, 4)) / 64;
  EXPECT_NEAR(deflection(2) / (F * L * L * L / (3 * E * I)), 1.0, kTolerance);
  EXPECT_NEAR(deflection(4) / (-F * L * L / (2 * E * I)), 1.0, kTolerance);
  // and nothing else moves.
  const Vec6 load = wrench(0, 0, F, 0, 0, 0);
  expect_deflection(deflection, reference::cantilever_compliance(L, E, G, A, I, I, 2 * I), load);

  // The clamp gives back the load moved to the root: moment (L, 0, 0) × (0, 0, F) = (0, −L·F, 0).
  const Vec6 load_about_root = wrench(0, 0, F, 0, -L * F, 0);
  EXPECT_LT(
      reference::relative_difference(support_reaction(result, "clamp"), Vec6(-load_about_root)),
      kTolerance);
}

// ---- planar-2r.yaml -----------------------------------------------------------------------

TEST(Planar2rExample, ComplianceIsJointsAndLinksInSeries) {
  const Model model = load_example("planar-2r.yaml");
  const Result result = stiffmsa::solve(model);
  const EndEffectorResult& ee = end_effector(result, "tool");
  ASSERT_TRUE(ee.compliance && ee.stiffness && ee.deflection);

  const Mat6 expected =
      locked_chain_compliance(model, whole_serial_model(model), position(model, "tip"));
  EXPECT_LT(relative_difference_scaled(*ee.compliance, expected), kTolerance);
  EXPECT_LT(relative_difference_scaled(*ee.stiffness, Mat6(expected.inverse())), kTolerance);
  expect_deflection(*ee.deflection, expected, total_load(model));
}

TEST(Planar2rExample, RigidLinkVariantIsTheVirtualJointModel) {
  // With rigid links only the two joint springs give: C = Σ J_i J_iᵀ / k_i, rank 2 (in-plane).
  Model model = load_example("planar-2r.yaml");
  make_links_rigid(model);
  const Result result = stiffmsa::solve(model);
  const EndEffectorResult& ee = end_effector(result, "tool");
  ASSERT_TRUE(ee.compliance && ee.deflection);

  const Vec3 tip = position(model, "tip");
  Mat6 expected = Mat6::Zero();
  for (const char* name : {"shoulder_joint", "elbow_joint"}) {
    const NamedConnection j = connection(model, name);
    const Vec6 twist = joint_twist(j, tip);
    expected += twist * twist.transpose() / scalar_stiffness(*j.connection);
  }
  EXPECT_LT(relative_difference_scaled(*ee.compliance, expected), kTolerance);
  // The joints are rigid out of their plane, so z, rx and ry are held rigidly, and two joints
  // leave the tip only two of its three in-plane freedoms: the stiffness is unbounded (null).
  expect_held_rigidly(*ee.compliance, {2, 3, 4});
  EXPECT_FALSE(ee.stiffness);
  expect_deflection(*ee.deflection, expected, total_load(model));
}

TEST(Planar2rExample, RigidLinkVariantHasItsStiffnessOnTheDirectionsItCanMoveIn) {
  // C = J·K⁻¹·Jᵀ with J = [J_shoulder J_elbow] (6×2) is held rigidly along z, rx, ry and along
  // the in-plane direction that neither joint moves, so its stiffness is null. The reduced
  // stiffness spans J's columns with orthonormal directions T, and Tᵀ·K_r·T is the
  // pseudo-inverse of C: J·(JᵀJ)⁻¹·K·(JᵀJ)⁻¹·Jᵀ.
  Model model = load_example("planar-2r.yaml");
  make_links_rigid(model);
  const Result result = stiffmsa::solve(model);
  const EndEffectorResult& ee = end_effector(result, "tool");
  ASSERT_FALSE(ee.stiffness);
  ASSERT_TRUE(ee.reduced_stiffness);
  const MatX& T = ee.reduced_stiffness->directions;
  ASSERT_EQ(T.rows(), 2);
  ASSERT_EQ(T.cols(), 6);
  EXPECT_LT((T * T.transpose() - MatX::Identity(2, 2)).cwiseAbs().maxCoeff(), kTolerance);
  for (int held : {2, 3, 4}) EXPECT_EQ(T.col(held).cwiseAbs().maxCoeff(), 0.0) << held;

  const Vec3 tip = position(model, "tip");
  Eigen::Matrix<double, 6, 2> J;
  Eigen::Vector2d k;
  int column = 0;
  for (const char* name : {"shoulder_joint", "elbow_joint"}) {
    const NamedConnection j = connection(model, name);
    J.col(column) = joint_twist(j, tip);
    k(column++) = scalar_stiffness(*j.connection);
  }
  const Eigen::Matrix2d gram_inverse = (J.transpose() * J).inverse();
  const Mat6 expected = J * gram_inverse * k.asDiagonal() * gram_inverse * J.transpose();
  // T spans J's columns: projecting them on T leaves them whole.
  EXPECT_LT(reference::relative_difference(MatX(T.transpose() * T * J), MatX(J)), kTolerance);
  const Mat6 reconstructed = T.transpose() * ee.reduced_stiffness->matrix * T;
  EXPECT_LT(reference::relative_difference(reconstructed, expected), kTolerance);
  EXPECT_EQ(result.report.notes.front(),
            "end effector 'tool' is held rigidly in some direction (or is so nearly a mechanism "
            "that double precision "
            "cannot tell): its stiffness is unbounded (null); reduced_stiffness gives it on the 2 "
            "directions it can "
            "move in");
}

// ---- industrial-6axis.yaml ----------------------------------------------------------------

TEST(Industrial6AxisExample, ComplianceIsJointsAndLinksInSeries) {
  const Model model = load_example("industrial-6axis.yaml");
  const Result result = stiffmsa::solve(model);
  const EndEffectorResult& ee = end_effector(result, "tool_centre");
  ASSERT_TRUE(ee.compliance && ee.stiffness && ee.deflection);

  const Mat6 expected =
      locked_chain_compliance(model, whole_serial_model(model), position(model, "tcp"));
  EXPECT_LT(relative_difference_scaled(*ee.compliance, expected), kTolerance);
  EXPECT_LT(relative_difference_scaled(*ee.stiffness, Mat6(expected.inverse())), kTolerance);
  expect_deflection(*ee.deflection, expected, total_load(model));
}

TEST(Industrial6AxisExample, RigidLinkVariantIsTheVirtualJointModel) {
  Model model = load_example("industrial-6axis.yaml");
  make_links_rigid(model);
  const Result result = stiffmsa::solve(model);
  const EndEffectorResult& ee = end_effector(result, "tool_centre");
  ASSERT_TRUE(ee.compliance && ee.stiffness && ee.deflection);

  // C = J·diag(k)⁻¹·Jᵀ with one column [a × (p_e − p); a] per joint; the pose is not
  // singular, so J is invertible and K = J⁻ᵀ·diag(k)·J⁻¹.
  const Vec3 tcp = position(model, "tcp");
  Mat6 J;
  Vec6 k;
  for (int i = 0; i < 6; ++i) {
    const NamedConnection axis = connection(model, "A" + std::to_string(i + 1));
    J.col(i) = joint_twist(axis, tcp);
    k(i) = scalar_stiffness(*axis.connection);
  }
  const Mat6 expected_compliance = J * k.cwiseInverse().asDiagonal() * J.transpose();
  const Mat6 J_inverse = J.inverse();
  const Mat6 expected_stiffness = J_inverse.transpose() * k.asDiagonal() * J_inverse;
  EXPECT_LT(relative_difference_scaled(*ee.compliance, expected_compliance), kTolerance);
  EXPECT_LT(relative_difference_scaled(*ee.stiffness, expected_stiffness), kTolerance);
}

// ---- planar-3rpr.yaml ---------------------------------------------------------------------

Chain rpr_leg(int i) {
  const std::string n = std::to_string(i);
  return Chain{{"leg" + n + "_cylinder", "leg" + n + "_rod", "platform_" + n},
               {"actuator_" + n},
               {"base_" + n, "pin_" + n}};
}

TEST(Planar3rprExample, StiffnessIsTheSumOfLegStiffnessesWithPassiveJoints) {
  const Model model = load_example("planar-3rpr.yaml");
  const Result result = stiffmsa::solve(model);
  const EndEffectorResult& ee = end_effector(result, "platform");
  ASSERT_TRUE(ee.compliance && ee.stiffness && ee.deflection);

  const Vec3 centre = position(model, "centre");
  Mat6 expected = Mat6::Zero();
  for (int i = 1; i <= 3; ++i) expected += leg_stiffness(model, rpr_leg(i), centre);
  EXPECT_LT(relative_difference_scaled(*ee.stiffness, expected), kTolerance);
  EXPECT_LT(relative_difference_scaled(*ee.compliance, Mat6(expected.inverse())), kTolerance);
}

// Rows [u_x, u_y, (r × u)_z] of the planar inverse kinematic Jacobian, r from the platform
// centre to the platform joint, u the unit leg direction.
Eigen::Matrix3d rpr_jacobian(const Model& model) {
  const Vec3 centre = position(model, "centre");
  Eigen::Matrix3d J;
  for (int i = 0; i < 3; ++i) {
    const std::string n = std::to_string(i + 1);
    const Vec3 base = position(model, "B" + n), top = position(model, "P" + n);
    const Vec3 u = (top - base).normalized();
    J.row(i) << u.x(), u.y(), (top - centre).cross(u).z();
  }
  return J;
}

constexpr int kInPlane[] = {0, 1, 5};     // x, y, rz
constexpr int kOutOfPlane[] = {2, 3, 4};  // z, rx, ry

TEST(Planar3rprExample, InPlaneStiffnessIsTheJacobianFormulaWithLegLinksInSeries) {
  // In the plane each leg is pinned at both ends, so its links carry only an axial force and
  // add L/(EA) in series with the actuator: K_plane = Jᵀ·diag(k_leg)·J. The planar structure
  // does not couple in-plane and out-of-plane motion, so K_plane is exactly the x, y, rz block
  // and the coupling blocks are zero. (The out-of-plane block, the legs' bending, is pinned by
  // the test above and taken as it is here.)
  const Model model = load_example("planar-3rpr.yaml");
  const Result result = stiffmsa::solve(model);
  const EndEffectorResult& platform = end_effector(result, "platform");
  ASSERT_TRUE(platform.stiffness);
  const Mat6& K = *platform.stiffness;

  Eigen::Vector3d leg_axial_stiffness;
  for (int i = 0; i < 3; ++i) {
    const std::string n = std::to_string(i + 1);
    const double compliance = 1 / scalar_stiffness(*connection(model, "actuator_" + n).connection) +
                              axial_compliance(model, "leg" + n + "_cylinder") +
                              axial_compliance(model, "leg" + n + "_rod");
    leg_axial_stiffness(i) = 1 / compliance;
  }
  const Eigen::Matrix3d J = rpr_jacobian(model);
  const Eigen::Matrix3d in_plane = J.transpose() * leg_axial_stiffness.asDiagonal() * J;

  Mat6 expected = Mat6::Zero();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      expected(kInPlane[r], kInPlane[c]) = in_plane(r, c);
      expected(kOutOfPlane[r], kOutOfPlane[c]) = K(kOutOfPlane[r], kOutOfPlane[c]);
    }
  EXPECT_LT(relative_difference_scaled(K, expected), kTolerance);

  // Statics of the same two-force legs: a leg in tension f_i pulls the platform by −f_i·u_i, so
  // the in-plane load is balanced when Jᵀ·f = [Fx, Fy, Mz]; the actuator efforts are f.
  const Vec6 load = total_load(model);
  const Eigen::Vector3d leg_forces =
      J.transpose().lu().solve(Eigen::Vector3d(load(0), load(1), load(5)));
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(actuator_effort(result, "actuator_" + std::to_string(i + 1)), leg_forces(i),
                kTolerance * leg_forces.cwiseAbs().maxCoeff());
}

TEST(Planar3rprExample, RigidLegVariantIsTheTextbookJacobianFormula) {
  // The textbook 3-RPR (rigid links, elastic actuators) in 3-D: with rigid legs the revolute
  // joints about z at both ends would hold the platform out of plane three times over. Making
  // the platform joints spherical leaves each rigid leg holding just the height of its platform
  // corner, so the out-of-plane directions are held rigidly but determinately, and in the plane
  // a ball joint turns like the pin it replaces: C_plane = (Jᵀ·diag(k)·J)⁻¹.
  Model model = load_example("planar-3rpr.yaml");
  make_links_rigid(model);
  for (const char* pin : {"pin_1", "pin_2", "pin_3"})
    joint(model, pin).connection.kinematics = stiffmsa::Kinematics::spherical();
  const Result result = stiffmsa::solve(model);
  const EndEffectorResult& ee = end_effector(result, "platform");
  ASSERT_TRUE(ee.compliance && ee.deflection);

  Eigen::Vector3d k;
  for (int i = 0; i < 3; ++i)
    k(i) = scalar_stiffness(*connection(model, "actuator_" + std::to_string(i + 1)).connection);
  const Eigen::Matrix3d J = rpr_jacobian(model);
  const Eigen::Matrix3d in_plane_compliance = (J.transpose() * k.asDiagonal() * J).inverse();
  Mat6 expected = Mat6::Zero();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) expected(kInPlane[r], kInPlane[c]) = in_plane_compliance(r, c);

  EXPECT_LT(relative_difference_scaled(*ee.compliance, expected), kTolerance);
  expect_held_rigidly(*ee.compliance, {2, 3, 4});
  EXPECT_FALSE(ee.stiffness);
  expect_deflection(*ee.deflection, expected, total_load(model));
}

TEST(Planar3rprExample, RigidLinkVariantHasItsInPlaneStiffnessAndPartlyDeterminedReactions) {
  // Rigid legs pinned about z at both ends hold the platform out of plane three times over:
  // z, rx, ry are held rigidly (stiffness null) and the out-of-plane wrenches in the legs are
  // undetermined. In the plane, each leg is its actuator alone: K_plane = Jᵀ·diag(k)·J on the
  // directions x, y, rz, which are coordinate axes, written exactly.
  Model model = load_example("planar-3rpr.yaml");
  make_links_rigid(model);
  const Result result = stiffmsa::solve(model);
  const EndEffectorResult& ee = end_effector(result, "platform");
  ASSERT_FALSE(ee.stiffness);
  ASSERT_TRUE(ee.reduced_stiffness);
  MatX axes = MatX::Zero(3, 6);
  for (int r = 0; r < 3; ++r) axes(r, kInPlane[r]) = 1;
  EXPECT_EQ(ee.reduced_stiffness->directions, axes);

  Eigen::Vector3d k;
  for (int i = 0; i < 3; ++i)
    k(i) = scalar_stiffness(*connection(model, "actuator_" + std::to_string(i + 1)).connection);
  const Eigen::Matrix3d J = rpr_jacobian(model);
  const Eigen::Matrix3d expected = J.transpose() * k.asDiagonal() * J;
  EXPECT_LT(reference::relative_difference(Eigen::Matrix3d(ee.reduced_stiffness->matrix), expected),
            kTolerance);

  // Each base reaction is null, but its in-plane part is the leg's force: the ground pulls a
  // leg in tension f_i by −f_i·u_i, with Jᵀ·f = [Fx, Fy, Mz] of the load. The note gives them
  // with 6 digits.
  const Vec6 load = total_load(model);
  const Eigen::Vector3d f = J.transpose().lu().solve(Eigen::Vector3d(load(0), load(1), load(5)));
  for (int i = 0; i < 3; ++i) {
    const std::string n = std::to_string(i + 1);
    EXPECT_FALSE(result.supports[static_cast<std::size_t>(i)].reaction);
    const std::string head = "the reaction of support 'base_" + n +
                             "' is null, as the rigid model does not determine all of it; its "
                             "determined components are Fx = ";
    std::string note;
    for (const auto& candidate : result.report.notes)
      if (candidate.starts_with(head)) note = candidate;
    ASSERT_FALSE(note.empty()) << n;
    const Vec3 u = (position(model, "P" + n) - position(model, "B" + n)).normalized();
    const auto value_after = [&](const std::string& label) {
      return std::stod(note.substr(note.find(label) + label.size()));
    };
    EXPECT_NEAR(value_after("Fx = "), -f(i) * u.x(), 1e-5 * std::abs(f(i))) << note;
    EXPECT_NEAR(value_after("Fy = "), -f(i) * u.y(), 1e-5 * std::abs(f(i))) << note;
    // A pin carries no moment about its axis: exactly 0, rounding not shown.
    EXPECT_TRUE(note.ends_with(", Mz = 0 N·m")) << note;
    EXPECT_EQ(note.find("Fz"), std::string::npos) << note;
  }
}

// ---- gough-stewart-6ups.yaml --------------------------------------------------------------

TEST(GoughStewartExample, StiffnessIsTheJacobianFormula) {
  // Rigid links and elastic actuators only, as the file is written: K = Jᵀ·diag(k)·J, rows
  // [u_iᵀ, (r_i × u_i)ᵀ], u_i the unit leg direction, r_i from the platform centre to P_i.
  const Model model = load_example("gough-stewart-6ups.yaml");
  const Result result = stiffmsa::solve(model);
  const EndEffectorResult& ee = end_effector(result, "platform");
  ASSERT_TRUE(ee.compliance && ee.stiffness && ee.deflection);

  const Vec3 centre = position(model, "centre");
  Mat6 J;
  Vec6 k;
  for (int i = 0; i < 6; ++i) {
    const std::string n = std::to_string(i + 1);
    const Vec3 base = position(model, "B" + n), top = position(model, "P" + n);
    const Vec3 u = (top - base).normalized();
    J.row(i) << u.transpose(), (top - centre).cross(u).transpose();
    k(i) = scalar_stiffness(*connection(model, "actuator_" + n).connection);
  }
  const Mat6 expected = J.transpose() * k.asDiagonal() * J;
  EXPECT_LT(relative_difference_scaled(*ee.stiffness, expected), kTolerance);
  EXPECT_LT(relative_difference_scaled(*ee.compliance, Mat6(expected.inverse())), kTolerance);
  const Vec6 load = total_load(model);
  expect_deflection(*ee.deflection, expected.inverse(), load);

  // Statics: a leg in tension f_i pulls the platform by −f_i·u_i, so Jᵀ·f balances the load and
  // the actuator efforts are f = J⁻ᵀ·W, whatever the stiffnesses.
  const Vec6 leg_forces = J.transpose().lu().solve(load);
  for (int i = 0; i < 6; ++i)
    EXPECT_NEAR(actuator_effort(result, "actuator_" + std::to_string(i + 1)), leg_forces(i),
                kTolerance * leg_forces.cwiseAbs().maxCoeff());
}

// ---- tripteron.yaml -----------------------------------------------------------------------

Chain tripteron_leg(char axis) {
  const std::string s = std::string("_") + axis;
  return Chain{{"carriage" + s, "proximal" + s, "distal" + s, "platform" + s},
               {"screw" + s},
               {"R1" + s, "R2" + s, "R3" + s}};
}

TEST(TripteronExample, StiffnessIsTheSumOfLegStiffnessesWithPassiveJoints) {
  const Model model = load_example("tripteron.yaml");
  const Result result = stiffmsa::solve(model);
  const EndEffectorResult& ee = end_effector(result, "platform");
  ASSERT_TRUE(ee.compliance && ee.stiffness && ee.deflection);

  const Vec3 centre = position(model, "centre");
  Mat6 expected = Mat6::Zero();
  for (char axis : {'x', 'y', 'z'}) expected += leg_stiffness(model, tripteron_leg(axis), centre);
  EXPECT_LT(relative_difference_scaled(*ee.stiffness, expected), kTolerance);
  EXPECT_LT(relative_difference_scaled(*ee.compliance, Mat6(expected.inverse())), kTolerance);
  expect_deflection(*ee.deflection, expected.inverse(), total_load(model));

  // Each leg fixes only its own axis among the translations: the translational block is
  // diagonal, each term from one leg alone.
  // Legs y and z slide freely along x and pass no force along it, so screw x alone carries the
  // load's x component; likewise for y and z.
  const Vec6 load = total_load(model);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(support_reaction(result, std::string("screw_") + "xyz"[i])(i), -load(i),
                kTolerance * load.head<3>().norm());

  const Mat6& K = *ee.stiffness;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      if (r == c) continue;
      EXPECT_LT(std::abs(K(r, c)), kTolerance * std::sqrt(K(r, r) * K(c, c))) << r << ", " << c;
    }
  }
}

TEST(TripteronExample, RigidLinkVariantIsThreeScrewsAlongTheirAxes) {
  // With rigid links each leg holds two rotations rigidly and every rotation is held twice: an
  // over-constrained rigid assembly. Its deflections are still determined: the platform only
  // translates, each screw taking the load along its own axis, C = diag(1/kx, 1/ky, 1/kz, 0, 0, 0).
  Model model = load_example("tripteron.yaml");
  make_links_rigid(model);
  const Result result = stiffmsa::solve(model);
  const EndEffectorResult& ee = end_effector(result, "platform");
  ASSERT_TRUE(ee.compliance && ee.deflection);

  Mat6 expected = Mat6::Zero();
  for (int i = 0; i < 3; ++i)
    expected(i, i) =
        1 / scalar_stiffness(*connection(model, std::string("screw_") + "xyz"[i]).connection);
  EXPECT_LT(relative_difference_scaled(*ee.compliance, expected), kTolerance);
  expect_held_rigidly(*ee.compliance, {3, 4, 5});
  EXPECT_FALSE(ee.stiffness);
  expect_deflection(*ee.deflection, expected, total_load(model));
  // The internal moments that the rigid legs share are left null, and a note says so.
  EXPECT_FALSE(result.report.notes.empty());
}

}  // namespace

// ---- delta-parametric.yaml and delta-us-parametric.yaml -------------------------------------

// The Delta robot at its default pose and at poses across its workspace: off centre towards and
// between the legs, low and high.
std::vector<Model> delta_poses(const std::string& file_name) {
  const stiffmsa::ModelFamily family =
      stiffmsa::load_model_family(std::string(STIFFMSA_SOURCE_DIR) + "/examples/" + file_name);
  std::vector<Model> members;
  for (const Vec3& p : {Vec3(0, 0, -0.40), Vec3(0.15, 0.05, -0.40), Vec3(-0.12, -0.16, -0.33),
                        Vec3(0.05, -0.1, -0.55)}) {
    std::vector<double> values = family.default_values();
    values[*family.find_parameter("px")] = p.x();
    values[*family.find_parameter("py")] = p.y();
    values[*family.find_parameter("pz")] = p.z();
    members.push_back(family.build(values));
  }
  return members;
}

bool has_note_containing(const Result& result, const std::string& text) {
  for (const auto& note : result.report.notes)
    if (note.find(text) != std::string::npos) return true;
  return false;
}

TEST(DeltaExample, HoldingTheRodSpinsGivesEveryResultOfTheFreeMotionAnalysis) {
  // `auto` holds each ball-jointed rod's spin about its own axis (a universal joint at one end
  // whose missing direction is the rod); `sparse_lu` finds the six spins as free motions of the
  // singular system and solves it bordered with them. Every number both report must agree, the
  // joint wrenches and support reactions too, and both leave the same deflections null.
  const std::vector<Model> poses = delta_poses("delta-parametric.yaml");
  stiffmsa::Workspace workspace(poses.front());
  stiffmsa::SolveOptions factorised;
  factorised.solver = stiffmsa::SolverKind::sparse_lu;
  for (const Model& pose : poses) {
    Result held = stiffmsa::solve(workspace, pose);
    const Result analysed = stiffmsa::solve(pose, factorised);
    EXPECT_TRUE(has_note_containing(held, "spin freely about the line through the ball joints"));
    EXPECT_TRUE(has_note_containing(held, "idle motions accepted"));
    EXPECT_FALSE(has_note_containing(held, "free motion 1"));
    // Six free motions, a note each (the culprit messages of issue 18 name them one by one).
    EXPECT_TRUE(has_note_containing(analysed, "free motion 6: "));
    EXPECT_FALSE(has_note_containing(analysed, "free motion 7"));
    EXPECT_TRUE(has_note_containing(analysed, "idle motions accepted"));
    EXPECT_TRUE(held.report.warnings.empty());
    // The held directions change which coefficients are zero, not the unknowns or equations.
    ASSERT_EQ(held.system.unknowns, analysed.system.unknowns);
    held.system.nonzeros = analysed.system.nonzeros;
    stiffmsa::testing::expect_same_results(held, analysed, kTolerance);
    for (const auto& link : held.links)
      EXPECT_EQ(link.from.deflection.has_value(), link.name.rfind("rod_", 0) != 0) << link.name;
  }
}

TEST(DeltaExample, UniversalJointsAtTheRodTopsGiveTheBallJointedRobot) {
  // The rod passes no moment about its own axis with a ball joint at its foot, so the universal
  // joint at its top changes no result but the rod ends' deflections, which the ball-jointed
  // robot leaves null.
  const std::vector<Model> ball = delta_poses("delta-parametric.yaml");
  const std::vector<Model> universal = delta_poses("delta-us-parametric.yaml");
  for (std::size_t i = 0; i < ball.size(); ++i) {
    const Result s = stiffmsa::solve(ball[i]), u = stiffmsa::solve(universal[i]);
    EXPECT_FALSE(has_note_containing(u, "idle"));
    const EndEffectorResult &es = end_effector(s, "platform"), &eu = end_effector(u, "platform");
    ASSERT_TRUE(es.stiffness && eu.stiffness && es.deflection && eu.deflection);
    EXPECT_LT(relative_difference_scaled(*eu.stiffness, *es.stiffness), kTolerance);
    EXPECT_LT(relative_difference_scaled(*eu.compliance, *es.compliance), kTolerance);
    expect_deflection(*eu.deflection, *es.compliance, total_load(ball[i]));
    for (const char* motor : {"motor_1", "motor_2", "motor_3"}) {
      const Vec6 rs = support_reaction(s, motor), ru = support_reaction(u, motor);
      EXPECT_LT((ru - rs).norm(), kTolerance * rs.norm()) << motor;
    }
  }
}

TEST(DeltaExample, StiffnessHasTheRobotsThreefoldSymmetry) {
  // At the centre the three legs sit 120 degrees apart about z: the translational stiffness is
  // the same along every horizontal direction and the platform is not coupled between the
  // horizontal and vertical translations.
  const Result result = stiffmsa::solve(delta_poses("delta-parametric.yaml").front());
  const Mat6& K = *end_effector(result, "platform").stiffness;
  const double horizontal = K(0, 0);
  EXPECT_NEAR(K(1, 1), horizontal, kTolerance * horizontal);
  EXPECT_NEAR(K(0, 1), 0.0, kTolerance * horizontal);
  EXPECT_NEAR(K(0, 2), 0.0, kTolerance * horizontal);
  EXPECT_NEAR(K(1, 2), 0.0, kTolerance * horizontal);
}

TEST(DeltaExample, WithoutAcceptingIdleMotionsTheRodSpinsAreStillAnError) {
  Model model = load_example("delta-parametric.yaml");
  model.options.accept_idle_motions = false;
  try {
    (void)stiffmsa::solve(model);
    FAIL() << "the rods' spins are free motions";
  } catch (const stiffmsa::SingularModelError& e) {
    std::string details;
    for (const auto& d : e.details()) details += d + "\n";
    EXPECT_NE(details.find("'rod_1a'"), std::string::npos) << details;
  }
  // One workspace serves both: refused without the option, held with it.
  stiffmsa::Workspace workspace(model);
  EXPECT_THROW((void)stiffmsa::solve(workspace, model), stiffmsa::SingularModelError);
  stiffmsa::SolveOptions accepting;
  accepting.accept_idle_motions = true;
  EXPECT_TRUE(has_note_containing(stiffmsa::solve(workspace, model, accepting),
                                  "spin freely about the line"));
  EXPECT_THROW((void)stiffmsa::solve(workspace, model), stiffmsa::SingularModelError);
}

TEST(DeltaExample, ARodLoadedAtItsEndKeepsItsSpinFree) {
  // A moment about the rod's axis at its end has nothing to hold it: holding the spin would
  // hide that, so a loaded rod's spin is left to the free-motion analysis, which refuses it.
  Model model = load_example("delta-parametric.yaml");
  const Vec3 axis = (position(model, "P1a") - position(model, "E1a")).normalized();
  model.loads.push_back(
      stiffmsa::Load{"P1a", "rod_1a", wrench(0, 0, 0, axis.x(), axis.y(), axis.z()), {}});
  EXPECT_THROW((void)stiffmsa::solve(model), stiffmsa::SingularModelError);
}

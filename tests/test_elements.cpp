// Each element block on its own: its matrices and its equations, against independent facts
// (symmetry, rigid-body null spaces, eq. (1) equivalence, spring signs, row counts).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "closed_forms.hpp"
#include "elements/beam_element.hpp"
#include "elements/cad_link.hpp"
#include "elements/connection_blocks.hpp"
#include "elements/free_directions.hpp"
#include "elements/link_blocks.hpp"
#include "solver/frame_solver.hpp"
#include "solver/tree_passes.hpp"

using namespace stiffmsa;
using namespace stiffmsa::detail;

namespace {

// Writes a block's equations into a dense matrix over the unknowns of `ends` link ends.
class DenseWriter final : public CoefficientWriter<DenseWriter> {
 public:
  DenseWriter(Index rows, int ends) : matrix(MatX::Zero(rows, 12 * ends)) {}
  void put(Index row, Index column, double value) { matrix(row, column) += value; }
  MatX matrix;
};

MatX equations_of(const ElementBlock& block, int ends) {
  DenseWriter writer(block.equation_count(), ends);
  block.write_equations(0, writer);
  return writer.matrix;
}

// Unknown vector of `ends` link ends from per-end deflections and wrenches.
VecX unknowns(const std::vector<Vec6>& deflections, const std::vector<Vec6>& wrenches) {
  VecX x(12 * static_cast<Index>(deflections.size()));
  for (std::size_t k = 0; k < deflections.size(); ++k) {
    x.segment<6>(12 * static_cast<Index>(k)) = deflections[k];
    x.segment<6>(12 * static_cast<Index>(k) + 6) = wrenches[k];
  }
  return x;
}

// The small rigid motion with translation u at the origin and rotation w, seen at point p.
Vec6 rigid_motion(const Vec3& u, const Vec3& w, const Vec3& p) {
  Vec6 t;
  t << u + w.cross(p), w;
  return t;
}

BeamLink sample_beam(bool shear) {
  BeamLink beam;
  beam.material = Material{7.0e10, 0.33, std::nullopt, std::nullopt};
  beam.section = Section::rect_tube(0.06, 0.09, 0.004);
  beam.shear = shear;
  beam.zref = Vec3(0.1, 0.3, 1.0);
  return beam;
}

const Vec3 kFrom(0.2, -0.1, 0.3), kTo(0.9, 0.4, 0.1);

}  // namespace

// A block held by columns reaches the writer in place (a view with the block's stride), any
// other expression evaluated first; either way as scale × its coefficients, where the call puts it.
TEST(EquationWriter, WritesBlocksInPlaceOrEvaluatedTimesTheirScale) {
  Mat6 m;
  for (Index j = 0; j < 6; ++j)
    for (Index i = 0; i < 6; ++i) m(i, j) = 1 + i + 10 * j;  // every entry distinct
  DenseWriter writer(12, 1);
  writer.add_block(1, 2, m.bottomRows(4), -1.0);  // in place: a 4×6 view, stride 6
  writer.add_block(7, 8, m.topLeftCorner<3, 3>().transpose(), 2.0);  // row-major: evaluated
  writer.add_block(10, 0, m.block<2, 2>(1, 4));                      // in place, scale 1
  MatX expected = MatX::Zero(12, 12);
  expected.block(1, 2, 4, 6) = -m.bottomRows(4);
  expected.block(7, 8, 3, 3) = 2.0 * m.topLeftCorner<3, 3>().transpose();
  expected.block(10, 0, 2, 2) = m.block<2, 2>(1, 4);
  EXPECT_EQ(writer.matrix, expected);
}

TEST(BeamElement, LocalStiffnessIsSymmetricWithSixRigidBodyModes) {
  for (bool shear : {false, true}) {
    const BeamConstants c = beam_constants(sample_beam(shear), 0.8);
    const Mat12 k = beam_local_stiffness(c);
    EXPECT_LT((k - k.transpose()).cwiseAbs().maxCoeff(), 1e-12 * k.cwiseAbs().maxCoeff());
    const Eigen::SelfAdjointEigenSolver<Mat12> eigen(k);
    EXPECT_LT(std::abs(eigen.eigenvalues()(5)), 1e-9 * eigen.eigenvalues()(11));
    EXPECT_GT(eigen.eigenvalues()(6), 1e-9 * eigen.eigenvalues()(11));
  }
}

TEST(BeamElement, ClampedComplianceIsTheInverseOfTheTipBlockAndMatchesTextbook) {
  for (bool shear : {false, true}) {
    const BeamLink beam = sample_beam(shear);
    const BeamConstants c = beam_constants(beam, 0.8);
    const Mat6 from_stiffness = beam_local_stiffness(c).bottomRightCorner<6, 6>().inverse();
    EXPECT_LT(reference::relative_difference_scaled(beam_local_compliance(c), from_stiffness),
              1e-12);
    const SectionProperties s = section_properties(beam.section);
    const Mat6 textbook = reference::cantilever_compliance(
        0.8, c.E, c.G, s.A, s.Iy, s.Iz, s.J, shear ? *s.Asy : 0.0, shear ? *s.Asz : 0.0);
    EXPECT_LT(reference::relative_difference_scaled(beam_local_compliance(c), textbook), 1e-13);
  }
}

TEST(BeamElement, LocalAxesFollowZref) {
  // Default zref is global Z: a beam along x has local y = Z × x = y, local z = Z.
  const Mat3 horizontal = link_axes(Vec3::Zero(), Vec3(2, 0, 0), std::nullopt);
  EXPECT_LT((horizontal - Mat3::Identity()).norm(), 1e-15);
  // A vertical beam uses global X instead: y = X × Z = −Y, z = x × y = Z × −Y = X.
  const Mat3 vertical = link_axes(Vec3::Zero(), Vec3(0, 0, 3), std::nullopt);
  EXPECT_LT((vertical.row(1) - Vec3(0, -1, 0).transpose()).norm(), 1e-15);
  EXPECT_LT((vertical.row(2) - Vec3(1, 0, 0).transpose()).norm(), 1e-15);
  EXPECT_THROW(link_axes(Vec3::Zero(), Vec3(1, 0, 0), Vec3(2, 0, 0)), InputError);
}

TEST(BeamElement, GlobalStiffnessHasTheRigidMotionsOfItsEndsInItsNullSpace) {
  const Mat12 K = beam_global_stiffness(sample_beam(true), kFrom, kTo);
  for (int c = 0; c < 6; ++c) {
    const Vec3 u = c < 3 ? Vec3(Vec3::Unit(c)) : Vec3::Zero();
    const Vec3 w = c >= 3 ? Vec3(Vec3::Unit(c - 3)) : Vec3::Zero();
    Eigen::Matrix<double, 12, 1> motion;
    motion << rigid_motion(u, w, kFrom), rigid_motion(u, w, kTo);
    EXPECT_LT((K * motion).norm(), 1e-9 * K.norm());
  }
  // K22 inverted is the global clamped compliance.
  const Mat6 C = beam_global_compliance(sample_beam(true), kFrom, kTo);
  EXPECT_LT(reference::relative_difference_scaled(*clamped_compliance(K), C), 1e-11);
}

TEST(CadLink, FreeFreeStiffnessFromComplianceRoundTrips) {
  const Mat6 C = beam_global_compliance(sample_beam(false), kFrom, kTo);
  const Mat12 K = free_free_stiffness(C, kTo - kFrom);
  EXPECT_LT(
      reference::relative_difference(K, beam_global_stiffness(sample_beam(false), kFrom, kTo)),
      1e-10);
  EXPECT_LT(reference::relative_difference_scaled(*clamped_compliance(K), C), 1e-11);
  // A matrix whose clamped block is singular has no compliance.
  Mat12 bar = Mat12::Zero();
  bar(0, 0) = bar(6, 6) = 1e8;
  bar(0, 6) = bar(6, 0) = -1e8;
  EXPECT_FALSE(clamped_compliance(bar).has_value());
}

TEST(CadLink, LocalFrameComplianceIsRotatedIntoGlobalAxes) {
  ComplianceLink link;
  link.C = beam_local_compliance(beam_constants(sample_beam(false), (kTo - kFrom).norm()));
  link.frame = LinkFrame::local;
  link.zref = sample_beam(false).zref;
  EXPECT_LT(
      reference::relative_difference_scaled(compliance_link_global_compliance(link, kFrom, kTo),
                                            beam_global_compliance(sample_beam(false), kFrom, kTo)),
      1e-13);
}

// The compliance form of a flexible link holds exactly where eq. (1) holds.
TEST(LinkBlock, FlexibleEquationsAreSatisfiedByEveryStateOfEquationOne) {
  const Vec3 d = kTo - kFrom;
  const Mat6 C = beam_global_compliance(sample_beam(true), kFrom, kTo);
  const Mat12 K = free_free_stiffness(C, d);
  const LinkBlock block(0, 1, d, C);
  const MatX A = equations_of(block, 2);
  ASSERT_EQ(A.rows(), 12);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Matrix<double, 12, 1> deflection = Eigen::Matrix<double, 12, 1>::Random() * 1e-4;
    const Eigen::Matrix<double, 12, 1> wrench = K * deflection;  // eq. (1)
    const VecX x = unknowns({deflection.head<6>(), deflection.tail<6>()},
                            {wrench.head<6>(), wrench.tail<6>()});
    EXPECT_LT((A * x).norm(), 1e-10 * wrench.norm());
  }
  // And the 12 rows are independent: the link leaves 12 of its 24 unknowns free.
  Eigen::FullPivLU<MatX> lu(A);
  EXPECT_EQ(lu.rank(), 12);
}

// What the frame solve condenses a link to (solver/frame_solver.hpp): a flexible link's K12 of
// eq. (1), which the test above holds the block's rows to; a stiffness-only link's own K12; a
// rigid link none.
TEST(LinkBlock, EndStiffnessIsTheLinksFreeFreeStiffness) {
  const Vec3 d = kTo - kFrom;
  const Mat6 C = beam_global_compliance(sample_beam(true), kFrom, kTo);
  const std::optional<Mat12> k12 = end_stiffness(LinkBlock(0, 1, d, C));
  ASSERT_TRUE(k12);
  EXPECT_EQ(*k12, free_free_stiffness(C, d));
  EXPECT_LT((*k12 - k12->transpose()).cwiseAbs().maxCoeff(), 1e-12 * k12->cwiseAbs().maxCoeff());
  const Mat12 K = beam_global_stiffness(sample_beam(false), kFrom, kTo);
  EXPECT_EQ(*end_stiffness(StiffnessLinkBlock(0, 1, K)), K);
  EXPECT_FALSE(end_stiffness(LinkBlock(0, 1, d, std::nullopt)));
}

TEST(LinkBlock, RigidLinkCarriesRigidMotionsAndBalancedWrenches) {
  const Vec3 d = kTo - kFrom;
  const LinkBlock block(0, 1, d, std::nullopt);
  const MatX A = equations_of(block, 2);
  const Vec3 u(1e-3, -2e-3, 5e-4), w(3e-3, 1e-3, -2e-3);
  Vec6 tip_wrench;
  tip_wrench << 10, -4, 7, 1.5, -2, 0.5;
  // The wrench at i that balances W_j on a rigid body: W_i = −Dᵀ W_j (moments about each end).
  Vec6 root_wrench;
  root_wrench << -tip_wrench.head<3>(), -tip_wrench.tail<3>() - d.cross(tip_wrench.head<3>());
  const VecX x =
      unknowns({rigid_motion(u, w, kFrom), rigid_motion(u, w, kTo)}, {root_wrench, tip_wrench});
  EXPECT_LT((A * x).norm(), 1e-13);
}

TEST(StiffnessLinkBlock, WritesEquationOneAsPrinted) {
  const Mat12 K = beam_global_stiffness(sample_beam(false), kFrom, kTo);
  const MatX A = equations_of(StiffnessLinkBlock(0, 1, K), 2);
  const Eigen::Matrix<double, 12, 1> deflection = Eigen::Matrix<double, 12, 1>::Random() * 1e-4;
  const Eigen::Matrix<double, 12, 1> wrench = K * deflection;
  const VecX x =
      unknowns({deflection.head<6>(), deflection.tail<6>()}, {wrench.head<6>(), wrench.tail<6>()});
  EXPECT_LT((A * x).norm(), 1e-12 * wrench.norm());
}

TEST(FreeDirections, RowsFollowTheDocumentedOrderAndTheComplementIsOrthonormal) {
  const FreeDirections cylindrical = free_directions(Kinematics::cylindrical(Vec3(0, 0, 2)));
  ASSERT_EQ(cylindrical.free().rows(), 2);
  EXPECT_EQ(Vec6(cylindrical.free().row(0).transpose()), (Vec6() << 0, 0, 1, 0, 0, 0).finished());
  EXPECT_EQ(Vec6(cylindrical.free().row(1).transpose()), (Vec6() << 0, 0, 0, 0, 0, 1).finished());

  // Planar with normal z: g = x (first on a tie), t1 = z × x = y, t2 = z × y = −x.
  const FreeDirections planar = free_directions(Kinematics::planar(Vec3(0, 0, 5)));
  EXPECT_LT((planar.free().row(0).transpose() - (Vec6() << 0, 1, 0, 0, 0, 0).finished()).norm(),
            1e-15);
  EXPECT_LT((planar.free().row(1).transpose() - (Vec6() << -1, 0, 0, 0, 0, 0).finished()).norm(),
            1e-15);
  EXPECT_LT((planar.free().row(2).transpose() - (Vec6() << 0, 0, 0, 0, 0, 1).finished()).norm(),
            1e-15);

  for (const Kinematics& k :
       {Kinematics::rigid(), Kinematics::revolute(Vec3(1, 2, 3)),
        Kinematics::prismatic(Vec3(-3, 0.5, 2)), Kinematics::cylindrical(Vec3(0.2, -1, 0.7)),
        Kinematics::universal(Vec3(1, 0, 0), Vec3(0, 1, 1)),
        Kinematics::universal(Vec3(1, 2, 0.5), Vec3(-0.3, 0.1, 2)), Kinematics::spherical(),
        Kinematics::planar(Vec3(1, -2, 2)),
        Kinematics::custom({(Vec6() << 1, 0, 0, 0, 2, 0).finished()})}) {
    const FreeDirections d = free_directions(k);
    EXPECT_EQ(d.free().rows() + d.constrained().rows(), 6);
    EXPECT_LT((d.constrained() * d.constrained().transpose() -
               MatX::Identity(d.constrained().rows(), d.constrained().rows()))
                  .norm(),
              1e-14);
    if (d.free().rows() > 0) EXPECT_LT((d.constrained() * d.free().transpose()).norm(), 1e-14);
  }
  EXPECT_THROW(free_directions(Kinematics::revolute(Vec3::Zero())), InputError);
  EXPECT_THROW(free_directions(Kinematics::custom({Vec6::Ones(), 2 * Vec6::Ones()})), InputError);
}

// A universal joint's axes are independent down to an angle of 2e-9 rad (singular-value ratio
// ≈ θ/2 against 1e-9); 1 − cos θ would cancel to zero long before. The constrained rows stay
// orthogonal to both axes down to that angle.
TEST(FreeDirections, UniversalAxesAtTinyAnglesAreToldApartWithoutCancellation) {
  const Vec3 a = Vec3(1, 2, 3).normalized();
  const Vec3 across = a.cross(Vec3::UnitX()).normalized();
  for (double angle : {1e-1, 1e-5, 1e-8, 3e-9}) {
    const Vec3 b = std::cos(angle) * a + std::sin(angle) * across;
    const FreeDirections d = free_directions(Kinematics::universal(a, b));
    // Λ_r stays orthogonal to both axes however close they are.
    EXPECT_LT((d.constrained() * d.free().transpose()).cwiseAbs().maxCoeff(), 4e-15) << angle;
    EXPECT_LT((d.constrained() * d.constrained().transpose() - Mat6::Identity().topLeftCorner(4, 4))
                  .norm(),
              4e-15)
        << angle;
  }
  EXPECT_THROW(free_directions(Kinematics::universal(a, a)), InputError);
  EXPECT_THROW(
      free_directions(Kinematics::universal(a, std::cos(1e-9) * a + std::sin(1e-9) * across)),
      InputError);
  EXPECT_THROW(free_directions(Kinematics::universal(a, -a)), InputError);
}

TEST(ConstraintJoint, PassiveRevoluteLetsOnlyTheAxisTurnAndPassesNoTorqueAlongIt) {
  const Vec3 axis = Vec3(1, 1, 0).normalized();
  const ConstraintJointBlock block({0, 1, 2}, free_directions(Kinematics::revolute(axis)),
                                   std::nullopt);
  EXPECT_EQ(block.equation_count(), 18);
  const MatX A = equations_of(block, 3);
  const Vec6 common = (Vec6() << 1e-3, 2e-3, 0, 0, 1e-3, 0).finished();
  Vec6 turn = common;
  turn.tail<3>() += 4e-3 * axis;
  // Wrenches free of moment along the axis and summing to zero.
  Vec6 w1 = (Vec6() << 5, 0, 1, axis.y(), -axis.x(), 2).finished();
  Vec6 w2 = (Vec6() << -2, 3, 0, 0, 0, -1).finished();
  w2.tail<3>() -= axis.dot(w2.tail<3>()) * axis;
  w1.tail<3>() -= axis.dot(w1.tail<3>()) * axis;
  const Vec6 w3 = -w1 - w2;
  EXPECT_LT((A * unknowns({common, turn, common}, {w1, w2, w3})).norm(), 1e-13);
  // Turning about another axis breaks compatibility; a torque along the axis breaks passivity.
  Vec6 bent = common;
  bent(3) += 1e-3;
  EXPECT_GT((A * unknowns({common, bent, common}, {w1, w2, w3})).norm(), 1e-4);
  Vec6 torqued = w1;
  torqued.tail<3>() += axis;
  EXPECT_GT((A * unknowns({common, turn, common}, {torqued, w2, -torqued - w2})).norm(), 0.5);
}

TEST(ElasticJoint, SpringPullsTheFirstEndTowardTheSecond) {
  const double k = 3e4;
  const ElasticJointBlock block(0, 1, free_directions(Kinematics::prismatic(Vec3::UnitX())),
                                MatX::Constant(1, 1, k), std::nullopt);
  const MatX A = equations_of(block, 2);
  // End 2 moved +q along x relative to end 1: the joint pushes end 1 by +k·q and end 2 by −k·q.
  const double q = 2e-4;
  const Vec6 t1 = Vec6::Zero(), t2 = (Vec6() << q, 0, 0, 0, 0, 0).finished();
  const Vec6 w1 = (Vec6() << k * q, 0, 0, 0, 0, 0).finished();
  EXPECT_LT((A * unknowns({t1, t2}, {w1, -w1})).norm(), 1e-12);
  EXPECT_GT((A * unknowns({t1, t2}, {-w1, w1})).norm(), 1.0);
}

TEST(Support, ElasticSupportResistsWithMinusKQ) {
  const double k = 800;
  const SupportBlock block({0}, free_directions(Kinematics::revolute(Vec3::UnitZ())),
                           MatX::Constant(1, 1, k), std::nullopt);
  EXPECT_EQ(block.equation_count(), 6);
  const MatX A = equations_of(block, 1);
  const Vec6 t = (Vec6() << 0, 0, 0, 0, 0, 0.01).finished();
  const Vec6 ground_wrench = (Vec6() << 3, -2, 1, 4, 5, -k * 0.01).finished();
  EXPECT_LT((A * unknowns({t}, {ground_wrench})).norm(), 1e-12);
}

TEST(Support, SeveralEndsAreJoinedRigidlyFirst) {
  const SupportBlock block({0, 1, 2}, free_directions(Kinematics::rigid()), std::nullopt,
                           std::nullopt);
  EXPECT_EQ(block.equation_count(), 18);
  const MatX A = equations_of(block, 3);
  Eigen::FullPivLU<MatX> lu(A);
  EXPECT_EQ(lu.rank(), 18);
  // Every deflection zero, any wrenches: satisfied.
  EXPECT_LT((A * unknowns({Vec6::Zero(), Vec6::Zero(), Vec6::Zero()},
                          {Vec6::Ones(), -Vec6::Ones(), Vec6::Constant(7)}))
                .norm(),
            1e-15);
}

TEST(FreeEnd, WrenchEqualsTheLoad) {
  const FreeEndBlock block(0);
  const MatX A = equations_of(block, 1);
  VecX rhs = VecX::Zero(6);
  const Vec6 load = (Vec6() << 1, 2, 3, 4, 5, 6).finished();
  block.add_external_wrench(0, 0, load, rhs);
  EXPECT_LT((A * unknowns({Vec6::Random()}, {load}) - rhs).norm(), 1e-15);
}

// ---- the tree solve's passes (solver/tree_passes.hpp) over each kind's equations ----------

namespace {

// Unknowns and external wrenches of `ends` link ends, three load cases, the preloads in the
// first. The unknowns start random: a pass must set what it hands on whatever was there.
struct TreeFixture {
  static constexpr Index kColumns = 3;
  // `compensated`: the passes carry their running sums in two parts (TreeState), else in one.
  // Passes in one part neither read nor write the low parts: there they start as NaN, and must
  // stay so without reaching x.
  explicit TreeFixture(int end_count, bool compensated_ = true)
      : ends(end_count),
        compensated(compensated_),
        x(RowMajorMatX::Random(12 * end_count, kColumns)),
        low(12 * end_count, kColumns),
        external(end_count, kColumns) {
    reset_low();
  }
  void reset_low() { low.setConstant(compensated ? 0.0 : std::nan("")); }
  RowMajorMatX increment;  // the passes' scratch
  // The unknowns the passes mean: both parts where compensated.
  RowMajorMatX solution() const { return compensated ? RowMajorMatX(x + low) : x; }
  TreeState state() { return TreeState(x, low, external, compensated, increment); }
  // Both passes of `block` toward `toward_root`, then the residual of its rows. What they hand
  // on starts as NaN in both parts (the solve does not zero its unknowns): W at `toward_root`,
  // and Δt at the link's other end (no `held` ends) or at the group's other ends.
  double passed(const ElementBlock& block, int toward_root, const std::vector<int>& held) {
    poison(wrench_column(toward_root));
    if (held.empty()) poison(deflection_column(toward_root ^ 1));
    for (int end : held)
      if (end != toward_root) poison(deflection_column(end));
    auto s = state();
    pass_wrench_to_root(block, toward_root, s);
    pass_deflection_from_root(block, toward_root, s);
    return residual(block, held);
  }
  void load(int end) {
    for (Index c = 0; c < kColumns; ++c) external.add(end, c, Vec6::Random() * 100.0);
  }
  void poison(Index first_row) {
    x.middleRows<6>(first_row).setConstant(std::nan(""));
    low.middleRows<6>(first_row).setConstant(std::nan(""));
  }
  // Cut unknowns: random values for each load case, which the passes must take as given.
  void cut(Index count) { cut_values = RowMajorMatX::Random(count, kColumns); }
  TreeState cut_state() {
    TreeState s = state();
    s.cut_values = &cut_values;
    return s;
  }
  // max |equations·x − rhs| over the block's rows but `skipped`, relative to the largest term.
  double residual(const ElementBlock& block, const std::vector<int>& held,
                  const std::vector<Index>& skipped = {}) const {
    const MatX a = equations_of(block, ends);
    if (!compensated)
      EXPECT_TRUE(low.array().isNaN().all()) << "a pass in one part wrote a low part";
    const MatX solution = this->solution();
    MatX rhs = MatX::Zero(block.equation_count(), kColumns);
    for (Index c = 0; c < kColumns; ++c) {
      VecX column = VecX::Zero(block.equation_count());
      for (int end : held) block.add_external_wrench(0, end, external.at(end).col(c), column);
      if (c == kLoadCase) block.add_preload(0, column);
      rhs.col(c) = column;
    }
    const double scale =
        (a.cwiseAbs() * solution.cwiseAbs()).maxCoeff() + rhs.cwiseAbs().maxCoeff();
    MatX error = a * solution - rhs;
    for (const Index row : skipped) error.row(row).setZero();
    const double largest = error.cwiseAbs().maxCoeff();
    return scale > 0 ? largest / scale : largest;  // a rigid support's rows over zero deflections
  }
  int ends;
  bool compensated;
  RowMajorMatX x, low;
  EndWrenches external;
  RowMajorMatX cut_values;
};

Mat6 sample_compliance() {
  const Mat6 m = Mat6::Random();
  return 1e-6 * (m * m.transpose() + Mat6::Identity());
}

}  // namespace

TEST(TreePasses, LinkPassesWrenchesAndDeflectionsEitherWay) {
  for (const bool compensated : {true, false}) {
    SCOPED_TRACE(compensated ? "running sums in two parts" : "running sums in one part");
    for (const std::optional<Mat6>& compliance :
         {std::optional<Mat6>(sample_compliance()), std::optional<Mat6>()}) {
      const LinkBlock link(0, 1, kTo - kFrom, compliance);
      ASSERT_TRUE(passes_tree(link));
      for (int toward_root : {0, 1}) {
        TreeFixture f(2, compensated);
        EXPECT_LT(f.passed(link, toward_root, {}), 1e-15) << "toward end " << toward_root;
      }
    }
  }
}

TEST(TreePasses, RigidJointOfThreeEndsBalancesItsLoadsAndMovesAsOne) {
  for (const bool compensated : {true, false}) {
    SCOPED_TRACE(compensated ? "running sums in two parts" : "running sums in one part");
    const ConstraintJointBlock joint({0, 2, 4}, free_directions(Kinematics::rigid()), std::nullopt);
    ASSERT_TRUE(passes_tree(joint));
    for (int toward_root : {0, 2, 4}) {
      TreeFixture f(5, compensated);
      f.load(0);
      f.load(4);
      EXPECT_LT(f.passed(joint, toward_root, {0, 2, 4}), 1e-15) << "toward end " << toward_root;
    }
  }
}

TEST(TreePasses, ElasticJointWithPreloadSolvesItsSpringEitherWay) {
  for (const bool compensated : {true, false}) {
    SCOPED_TRACE(compensated ? "running sums in two parts" : "running sums in one part");
    MatX universal_stiffness(2, 2);
    universal_stiffness << 4e4, 1e3, 1e3, 2e4;
    const std::vector<std::pair<Kinematics, MatX>> springs = {
        {Kinematics::revolute(Vec3(1, 2, 3)), MatX::Constant(1, 1, 3e4)},
        {Kinematics::universal(Vec3(1, 0, 0), Vec3(0, 1, 1)), universal_stiffness},
        {Kinematics::custom({(Vec6() << 1, 0, 0, 0, 2, 0).finished()}), MatX::Constant(1, 1, 5e5)}};
    for (const auto& [kinematics, stiffness] : springs) {
      const ElasticJointBlock joint(0, 2, free_directions(kinematics), stiffness,
                                    VecX::Constant(stiffness.rows(), 7.5));
      for (int toward_root : {0, 2}) {
        TreeFixture f(3, compensated);
        f.load(0);
        f.load(2);
        EXPECT_LT(f.passed(joint, toward_root, {0, 2}), 1e-14)
            << to_string(kinematics.type) << ", toward end " << toward_root;
      }
    }
  }
}

TEST(TreePasses, RootSupportHoldsItsEndsRigidlyOrOnItsSpring) {
  for (const bool compensated : {true, false}) {
    SCOPED_TRACE(compensated ? "running sums in two parts" : "running sums in one part");
    Eigen::Matrix3d k;
    k << 5e6, 1e5, 0, 1e5, 4e6, 2e5, 0, 2e5, 6e6;
    const SupportBlock elastic({0, 2}, free_directions(Kinematics::spherical()), MatX(k),
                               VecX::Constant(3, -40.0));
    const SupportBlock rigid({0, 2}, free_directions(Kinematics::rigid()), std::nullopt,
                             std::nullopt);
    for (const SupportBlock* support : {&elastic, &rigid}) {
      ASSERT_TRUE(passes_tree(*support));
      TreeFixture f(3, compensated);
      f.load(2);
      auto state = f.state();
      set_root_deflection(*support, state);
      EXPECT_LT(f.residual(*support, {0, 2}), 1e-15);
    }
  }
}

TEST(TreePasses, FreeEndCarriesItsLoad) {
  for (const bool compensated : {true, false}) {
    SCOPED_TRACE(compensated ? "running sums in two parts" : "running sums in one part");
    const FreeEndBlock free_end(1);
    TreeFixture f(2, compensated);
    f.load(1);
    EXPECT_EQ(f.passed(free_end, 1, {1}), 0.0);
  }
}

TEST(TreePasses, PassiveJointTakesItsFreeMotionsAndLeavesItsFreeComponents) {
  for (const bool compensated : {true, false}) {
    SCOPED_TRACE(compensated ? "running sums in two parts" : "running sums in one part");
    struct Case {
      Kinematics kinematics;
      std::vector<int> ends;
      std::optional<VecX> preload;
    };
    const std::vector<Case> cases = {
        {Kinematics::revolute(Vec3(1, 2, 3)), {0, 2}, VecX::Constant(1, 12.5)},
        {Kinematics::universal(Vec3(1, 0, 0), Vec3(0, 1, 1)), {0, 2, 4}, std::nullopt},
        {Kinematics::custom({(Vec6() << 1, 0, 0, 0, 2, 0).finished()}),
         {0, 2},
         VecX::Constant(1, -3.0)},
        {Kinematics::spherical(), {0, 2}, VecX::Constant(3, 4.0)},
        {Kinematics::spherical(), {0, 2, 4}, VecX::Constant(3, -6.0)}};
    for (const Case& c : cases) {
      const ConstraintJointBlock joint(c.ends, free_directions(c.kinematics), c.preload);
      const Index p = free_directions(c.kinematics).p;
      ASSERT_TRUE(passes_tree(joint));
      for (int toward_root : c.ends) {
        EXPECT_EQ(cut_unknowns(joint, toward_root), p * static_cast<Index>(c.ends.size() - 1));
        std::vector<Index> rows;
        add_cut_rows(joint, toward_root, rows);
        ASSERT_EQ(static_cast<Index>(rows.size()), cut_unknowns(joint, toward_root));
        const FreeDirections directions = free_directions(c.kinematics);
        TreeFixture f(5, compensated);
        for (int end : c.ends) f.load(end);
        f.cut(cut_unknowns(joint, toward_root));
        // Random wrenches beyond the root break the cut rows: the passes do not hold them.
        RowMajorMatX random_start = f.x;
        {
          auto state = f.cut_state();
          pass_wrench_to_root(joint, toward_root, state);
          pass_deflection_from_root(joint, toward_root, state);
          EXPECT_GT(f.residual(joint, c.ends), 1e-6) << to_string(c.kinematics.type);
        }
        // Where the wrenches beyond the root hold their cut rows (Λ_p·W_k = Λ_p·W_ext,k, + G·w_0
        // on the first end and − on the second), the passes hold every other row. What they hand
        // on starts as NaN.
        f.x = random_start;
        f.reset_low();
        f.poison(wrench_column(toward_root));
        for (int end : c.ends)
          if (end != toward_root) f.poison(deflection_column(end));
        const MatX gram_inverse = directions.gram().inverse();
        for (std::size_t i = 0; i < c.ends.size(); ++i) {
          const int end = c.ends[i];
          if (end == toward_root) continue;
          for (Index column = 0; column < TreeFixture::kColumns; ++column) {
            VecX target = directions.free() * f.external.at(end).col(column);
            if (column == kLoadCase && c.preload && i < 2)
              target += (i == 0 ? 1.0 : -1.0) * directions.gram() * *c.preload;
            auto w = f.x.block<6, 1>(wrench_column(end), column);
            const VecX correction =
                directions.free().transpose() * (gram_inverse * (target - directions.free() * w));
            w += correction;
          }
        }
        auto state = f.cut_state();
        pass_wrench_to_root(joint, toward_root, state);
        pass_deflection_from_root(joint, toward_root, state);
        EXPECT_LT(f.residual(joint, c.ends), 1e-15)
            << to_string(c.kinematics.type) << ", toward end " << toward_root;
        // The free motions are the given ones: Δt_k − Δt_root = Λ_pᵀ·q_k.
        const RowMajorMatX solution = f.solution();
        Index motion = 0;
        for (int end : c.ends) {
          if (end == toward_root) continue;
          const MatX relative = solution.middleRows<6>(deflection_column(end)) -
                                solution.middleRows<6>(deflection_column(toward_root));
          EXPECT_LT((relative - directions.free().transpose() * f.cut_values.middleRows(motion, p))
                        .cwiseAbs()
                        .maxCoeff(),
                    1e-15);
          motion += p;
        }
      }
    }
    // The cut rows in the block's layout: r·(m − 1) compatibility rows, r equilibrium rows, then
    // p rows per end; those of the ends beyond the root's.
    std::vector<Index> rows;
    add_cut_rows(ConstraintJointBlock({0, 2}, free_directions(Kinematics::revolute(Vec3::UnitZ())),
                                      std::nullopt),
                 0, rows);
    EXPECT_EQ(rows, std::vector<Index>{11});
    rows.clear();
    add_cut_rows(ConstraintJointBlock({0, 2}, free_directions(Kinematics::revolute(Vec3::UnitZ())),
                                      std::nullopt),
                 2, rows);
    EXPECT_EQ(rows, std::vector<Index>{10});
    rows.clear();
    const ConstraintJointBlock universal(
        {0, 2, 4}, free_directions(Kinematics::universal(Vec3::UnitX(), Vec3::UnitY())),
        std::nullopt);
    add_cut_rows(universal, 2, rows);
    EXPECT_EQ(rows, (std::vector<Index>{12, 13, 16, 17}));
  }
}

TEST(TreePasses, SupportAwayFromTheRootTakesItsReactionAndLeavesItsHold) {
  for (const bool compensated : {true, false}) {
    SCOPED_TRACE(compensated ? "running sums in two parts" : "running sums in one part");
    Eigen::Matrix3d k;
    k << 5e6, 1e5, 0, 1e5, 4e6, 2e5, 0, 2e5, 6e6;
    const SupportBlock elastic({0, 2}, free_directions(Kinematics::spherical()), MatX(k),
                               VecX::Constant(3, -40.0));
    const SupportBlock rigid({0, 2, 4}, free_directions(Kinematics::rigid()), std::nullopt,
                             std::nullopt);
    const SupportBlock passive({0, 2},
                               free_directions(Kinematics::universal(Vec3(1, 0, 0), Vec3(0, 1, 0))),
                               std::nullopt, std::nullopt);
    for (const SupportBlock* support : {&elastic, &rigid, &passive}) {
      const std::vector<int> ends =
          support == &rigid ? std::vector<int>{0, 2, 4} : std::vector<int>{0, 2};
      for (int toward_root : ends) {
        ASSERT_EQ(cut_unknowns(*support, toward_root), 6);
        std::vector<Index> rows;
        add_cut_rows(*support, toward_root, rows);
        ASSERT_EQ(rows.size(), 6u);
        TreeFixture f(5, compensated);
        for (int end : ends) f.load(end);
        f.cut(6);
        f.poison(wrench_column(toward_root));
        for (int end : ends)
          if (end != toward_root) f.poison(deflection_column(end));
        auto state = f.cut_state();
        pass_wrench_to_root(*support, toward_root, state);
        pass_deflection_from_root(*support, toward_root, state);
        EXPECT_LT(f.residual(*support, ends, rows), 1e-15) << "toward end " << toward_root;
        // The reaction is the given one: Σ(W_k − W_ext,k) = R.
        const RowMajorMatX solution = f.solution();
        MatX reaction = MatX::Zero(6, TreeFixture::kColumns);
        for (int end : ends)
          reaction += solution.middleRows<6>(wrench_column(end)) - f.external.at(end);
        EXPECT_LT((reaction - f.cut_values).cwiseAbs().maxCoeff(), 1e-13);
      }
    }
  }
}

TEST(TreePasses, PassiveRootSupportTakesItsFreeMotion) {
  for (const bool compensated : {true, false}) {
    SCOPED_TRACE(compensated ? "running sums in two parts" : "running sums in one part");
    const SupportBlock passive({0, 2}, free_directions(Kinematics::revolute(Vec3(0, 1, 1))),
                               std::nullopt, std::nullopt);
    ASSERT_EQ(cut_unknowns(passive, -1), 1);
    std::vector<Index> rows;
    add_cut_rows(passive, -1, rows);
    ASSERT_EQ(rows, std::vector<Index>{11});  // Λ_p·Σ W_k = Λ_p·Σ W_ext,k, its last row
    TreeFixture f(3, compensated);
    f.load(2);
    f.cut(1);
    f.poison(deflection_column(0));
    f.poison(deflection_column(2));
    auto state = f.cut_state();
    set_root_deflection(passive, state);
    EXPECT_LT(f.residual(passive, {0, 2}, rows), 1e-15);
    const Vec6 axis = free_directions(Kinematics::revolute(Vec3(0, 1, 1))).free().transpose();
    EXPECT_LT((f.x.middleRows<6>(deflection_column(2)) - axis * f.cut_values).cwiseAbs().maxCoeff(),
              1e-15);
    // Rigid and elastic roots take none.
    EXPECT_EQ(cut_unknowns(SupportBlock({0}, free_directions(Kinematics::rigid()), std::nullopt,
                                        std::nullopt),
                           -1),
              0);
    EXPECT_EQ(cut_unknowns(SupportBlock({0}, free_directions(Kinematics::revolute(Vec3::UnitZ())),
                                        MatX::Constant(1, 1, 5e3), std::nullopt),
                           -1),
              0);
  }
}

TEST(TreePasses, SingularLinkMatricesAreLeftToTheFactorisingSolve) {
  EXPECT_FALSE(passes_tree(StiffnessLinkBlock(0, 1, Mat12::Identity())));
  EXPECT_EQ(
      cut_unknowns(ConstraintJointBlock({0, 2}, free_directions(Kinematics::rigid()), std::nullopt),
                   0),
      0);
}

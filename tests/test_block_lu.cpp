// The block LU of the loaded mode's tangent (src/solver/block_lu.hpp, docs/theory.md §15.10)
// against Eigen's dense LU with partial pivoting: on random matrices with the loaded tangent's
// block layouts (a serial chain, closed loops), on the loaded tangents of the examples, on
// singular and near-singular matrices, on fronts with swapped and zero blocks, and across a
// change of layout; the equilibration's power-of-two scales against frexp and their exactness;
// and the loaded mode's determinant sign of the unloaded tangent against KLU's on every example
// and test model.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "analysis/loaded_mode.hpp"
#include "assembly/topology.hpp"
#include "solver/block_lu.hpp"
#include "stiffmsa/io/model_file.hpp"

namespace stiffmsa::detail {
namespace {

// The block LU's solutions agree with the exact ones to this (relative, ∞-norm), or to what
// the dense LU's condition allows.
constexpr double kAgreement = 1e-12;
// Two backward-stable solves of an ill-conditioned matrix lose about as many digits, the
// rounding deciding which loses more: within this factor of each other.
constexpr double kSameDigits = 10;
// A backward-stable solve leaves a normwise backward error of a few rounding units.
constexpr double kBackwardStable = 1e-15;
// Models with more unknowns are not compared with a dense factorisation.
constexpr Index kLargestDense = 2000;

// A layout built as the loaded mode builds its tangent: per link its 12 rows over its two ends,
// per joint 6 rows per end over its ends, per support 6 rows per end, per free end 6 rows.
struct LayoutBuilder {
  BlockLayout layout;
  void block(int rows, std::vector<int> groups) {
    layout.rows.push_back(rows);
    layout.groups.push_back(std::move(groups));
  }
  void link(int from, int to) { block(12, {from, to}); }
  void connection(const std::vector<int>& ends) { block(6 * static_cast<int>(ends.size()), ends); }
};

// A serial arm of `links` links on one support: ends 2l, 2l+1; joints between links.
BlockLayout chain(int links) {
  LayoutBuilder b;
  b.layout.group_count = 2 * links;
  for (int l = 0; l < links; ++l) b.link(2 * l, 2 * l + 1);
  b.connection({0});
  for (int l = 0; l + 1 < links; ++l) b.connection({2 * l + 1, 2 * l + 2});
  b.connection({2 * links - 1});  // the free tip
  return b.layout;
}

// Three legs of two links each from three supports to one platform link end each, the three
// platform ends joined by one joint: closed loops through the ground.
BlockLayout three_legs() {
  LayoutBuilder b;
  b.layout.group_count = 12;  // per leg 4 ends: 4k … 4k+3
  for (int k = 0; k < 3; ++k) {
    b.link(4 * k, 4 * k + 1);
    b.link(4 * k + 2, 4 * k + 3);
  }
  for (int k = 0; k < 3; ++k) {
    b.connection({4 * k});
    b.connection({4 * k + 1, 4 * k + 2});
  }
  b.connection({3, 7, 11});
  return b.layout;
}

std::vector<MatX> random_values(const BlockLayout& layout, std::mt19937& random) {
  std::uniform_real_distribution<double> entry(-1.0, 1.0), decade(-4.0, 4.0);
  // Rows and columns of many decades, as stiffness entries beside identities: the block LU's
  // equilibration takes them out.
  VecX column_size(12 * layout.group_count);
  for (Index j = 0; j < column_size.size(); ++j) column_size(j) = std::pow(10.0, decade(random));
  std::vector<MatX> values;
  for (std::size_t b = 0; b < layout.rows.size(); ++b) {
    MatX v(layout.rows[b], 12 * static_cast<Index>(layout.groups[b].size()));
    for (Index i = 0; i < v.rows(); ++i) {
      const double row_size = std::pow(10.0, decade(random));
      for (Index j = 0; j < v.cols(); ++j)
        v(i, j) = row_size * column_size(12 * layout.groups[b][j / 12] + j % 12) * entry(random);
    }
    values.push_back(std::move(v));
  }
  return values;
}

MatX dense(const BlockLayout& layout, const std::vector<MatX>& values) {
  const Index n = 12 * layout.group_count;
  MatX a = MatX::Zero(n, n);
  Index row = 0;
  for (std::size_t b = 0; b < layout.rows.size(); ++b) {
    for (std::size_t k = 0; k < layout.groups[b].size(); ++k)
      a.block(row, 12 * layout.groups[b][k], layout.rows[b], 12) +=
          values[b].middleCols(12 * static_cast<Index>(k), 12);
    row += layout.rows[b];
  }
  return a;
}

double relative_difference(const MatX& x, const MatX& reference) {
  return (x - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff();
}

// b − A·x with the products summed in long double.
MatX residual_extended(const MatX& a, const MatX& x, const MatX& b) {
  MatX r(b.rows(), b.cols());
  for (Index c = 0; c < b.cols(); ++c)
    for (Index i = 0; i < a.rows(); ++i) {
      long double sum = b(i, c);
      for (Index j = 0; j < a.cols(); ++j)
        sum -= static_cast<long double>(a(i, j)) * static_cast<long double>(x(j, c));
      r(i, c) = static_cast<double>(sum);
    }
  return r;
}

// ‖b − A·x‖∞ / (‖A‖∞·‖x‖∞ + ‖b‖∞), the largest over the columns.
double backward_error(const MatX& a, const MatX& x, const MatX& b) {
  const MatX r = residual_extended(a, x, b);
  const double a_norm = a.cwiseAbs().rowwise().sum().maxCoeff();
  double largest = 0;
  for (Index c = 0; c < b.cols(); ++c)
    largest = std::max(
        largest, r.col(c).cwiseAbs().maxCoeff() /
                     (a_norm * x.col(c).cwiseAbs().maxCoeff() + b.col(c).cwiseAbs().maxCoeff()));
  return largest;
}

// The block LU's solution and determinant sign against the dense LU's, on the matrix of
// `values` (regular). The reference solution is the dense LU's refined with residuals in
// extended precision, so that it holds the digits the matrix's condition allows: the block LU's
// solution must be as close to it as kAgreement, or as the dense LU's own unrefined solution
// (both lose about the condition number times the rounding unit), and backward stable.
void expect_as_dense(BlockLU& lu, const std::vector<MatX>& values, std::mt19937& random,
                     const std::string& what) {
  const MatX a = dense(lu.layout(), values);
  ASSERT_EQ(lu.factorise(values), BlockLU::Outcome::factorised) << what;
  const Eigen::PartialPivLU<MatX> reference(a);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  MatX b(a.rows(), 3);
  for (Index i = 0; i < b.size(); ++i) b.data()[i] = entry(random);
  MatX x = b;
  lu.solve(x);
  const MatX dense_solution = reference.solve(b);
  MatX exact = dense_solution;
  for (int step = 0; step < 3; ++step) exact += reference.solve(residual_extended(a, exact, b));
  EXPECT_LE(relative_difference(x, exact),
            std::max(kAgreement, kSameDigits * relative_difference(dense_solution, exact)))
      << what;
  EXPECT_LT(backward_error(a, x, b), kBackwardStable) << what;
  const double determinant = reference.determinant();
  EXPECT_EQ(lu.determinant_sign(), determinant > 0 ? 1.0 : -1.0) << what;
}

// One factorisation's solution of b and what it tells of its pivots: two factorisations of one
// matrix are compared by these, bit for bit.
struct Solved {
  MatX x;
  double sign = 0;
  double smallest_pivot = 0;
};

Solved factorise_and_solve(BlockLU& lu, const std::vector<MatX>& values, const MatX& b,
                           const BlockScaling* kept = nullptr) {
  if (lu.factorise(values, kept) != BlockLU::Outcome::factorised) {
    ADD_FAILURE() << "not factorised";
    return {};
  }
  Solved solved{b, lu.determinant_sign(), lu.smallest_pivot()};
  lu.solve(solved.x);
  return solved;
}

void expect_same_bits(const Solved& actual, const Solved& expected) {
  EXPECT_EQ(actual.x, expected.x);
  EXPECT_EQ(actual.sign, expected.sign);
  EXPECT_EQ(actual.smallest_pivot, expected.smallest_pivot);
}

TEST(BlockLU, RandomChainsAndLoopsAsDenseLU) {
  std::mt19937 random(20261126);
  for (const auto& [name, layout] : {std::pair{std::string("chain of 1"), chain(1)},
                                     std::pair{std::string("chain of 7"), chain(7)},
                                     std::pair{std::string("three legs"), three_legs()}}) {
    BlockLU lu;
    lu.analyze(layout);
    for (int trial = 0; trial < 20; ++trial)
      expect_as_dense(lu, random_values(layout, random), random,
                      name + ", trial " + std::to_string(trial));
  }
}

TEST(BlockLU, LayoutChangesBetweenFactorisations) {
  std::mt19937 random(7);
  BlockLU lu;
  for (const BlockLayout& layout : {chain(3), three_legs(), chain(3), chain(5)}) {
    lu.analyze(layout);
    expect_as_dense(lu, random_values(layout, random), random,
                    "layout of " + std::to_string(layout.group_count) + " ends");
  }
}

TEST(BlockLU, SingularAndNearSingularDetected) {
  std::mt19937 random(11);
  const BlockLayout layout = chain(4);
  BlockLU lu;
  lu.analyze(layout);
  // Two rows of one block the same: exactly singular (a zero pivot, or one at rounding level).
  std::vector<MatX> values = random_values(layout, random);
  values[2].row(5) = values[2].row(3);
  EXPECT_NE(lu.factorise(values), BlockLU::Outcome::factorised);
  // Dependent to 1e-13: the matrix is singular within the rounding of its entries.
  values[2].row(5) = values[2].row(3) * (1 + 1e-13);
  EXPECT_EQ(lu.factorise(values), BlockLU::Outcome::tiny_pivot);
  // A zero column (a link end nothing acts on).
  values = random_values(layout, random);
  for (std::size_t b = 0; b < layout.rows.size(); ++b)
    for (std::size_t k = 0; k < layout.groups[b].size(); ++k)
      if (layout.groups[b][k] == 3) values[b].col(12 * static_cast<Index>(k) + 4).setZero();
  EXPECT_EQ(lu.factorise(values), BlockLU::Outcome::singular);
  // Fewer rows than unknowns at a link end: structurally singular.
  LayoutBuilder short_of_rows;
  short_of_rows.layout.group_count = 2;
  short_of_rows.block(6, {0});
  short_of_rows.block(6, {1});
  short_of_rows.block(12, {1});
  lu.analyze(short_of_rows.layout);
  EXPECT_EQ(lu.factorise(random_values(short_of_rows.layout, random)), BlockLU::Outcome::singular);
}

// The scale read off the exponent's bits as frexp and ldexp give it, over the whole range of
// doubles: subnormal sizes, the largest normal ones (whose scale is subnormal), and between.
TEST(BlockLU, PowerOfTwoScaleAsFrexp) {
  const auto by_frexp = [](double largest) {
    int exponent = 0;
    std::frexp(largest, &exponent);
    return std::ldexp(1.0, -exponent);
  };
  std::vector<double> sizes = {std::numeric_limits<double>::denorm_min(),
                               std::numeric_limits<double>::min(),
                               std::numeric_limits<double>::max(),
                               std::nextafter(std::numeric_limits<double>::min(), 0.0),
                               0.5,
                               1.0,
                               std::nextafter(1.0, 0.0),
                               3e-200,
                               7e250};
  for (int exponent = -1074; exponent <= 1023; ++exponent)
    for (double mantissa : {1.0, 1.5, std::nextafter(2.0, 0.0)})
      sizes.push_back(std::ldexp(mantissa, exponent));
  for (double size : sizes) {
    EXPECT_EQ(power_of_two_scale(size), by_frexp(size)) << size;
    EXPECT_EQ(power_of_two_scale(-size), 1.0) << -size;
  }
  EXPECT_EQ(power_of_two_scale(0.0), 1.0);
  EXPECT_EQ(power_of_two_scale(std::numeric_limits<double>::infinity()), 1.0);
  EXPECT_EQ(power_of_two_scale(std::numeric_limits<double>::quiet_NaN()), 1.0);
}

// Columns scaled by powers of two far apart (2^±800), and all rows by one more, leave the
// equilibrated matrix, and so the factors, exactly as they were: the solution scales back
// exactly, the sign and the smallest pivot are the same. (Rows scaled apart would change which
// entry is each column's largest: the scaling is column first.)
TEST(BlockLU, PowerOfTwoScalingsTakenOutExactly) {
  std::mt19937 random(5);
  std::uniform_int_distribution<int> exponent(-800, 800);
  for (const BlockLayout& layout : {chain(4), three_legs()}) {
    BlockLU lu;
    lu.analyze(layout);
    const std::vector<MatX> values = random_values(layout, random);
    const Index n = 12 * layout.group_count;
    const MatX b = MatX::Random(n, 2);
    const Solved fresh = factorise_and_solve(lu, values, b);

    const double row_scale = std::ldexp(1.0, 100);
    VecX column_scale(n);
    for (Index j = 0; j < n; ++j) column_scale(j) = std::ldexp(1.0, exponent(random));
    std::vector<MatX> scaled = values;
    for (std::size_t k = 0; k < scaled.size(); ++k)
      for (Index j = 0; j < scaled[k].cols(); ++j)
        scaled[k].col(j) *= row_scale * column_scale(12 * layout.groups[k][j / 12] + j % 12);
    Solved scaled_back = factorise_and_solve(lu, scaled, row_scale * b);
    scaled_back.x = (scaled_back.x.array().colwise() * column_scale.array()).matrix();
    expect_same_bits(scaled_back, fresh);
  }
}

// A front whose pivot rows are all at its bottom (the row swaps of every step, in the
// factorised columns and the ones updated after) and a tangent with whole zero blocks in its
// fronts (the updates a zero multiplier skips): as the dense LU.
TEST(BlockLU, SwappedAndSparseFrontsAsDenseLU) {
  std::mt19937 random(17);
  const BlockLayout layout = three_legs();
  BlockLU lu;
  lu.analyze(layout);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<MatX> values = random_values(layout, random);
    // Every link's entries in its first end's columns small: after the scaling, those columns'
    // pivots come from the connections' rows, stacked below the link's in the fronts.
    for (std::size_t k = 0; k < 6; ++k) values[k].leftCols(12) *= 1e-6;
    // Zero couplings in half the blocks' second ends.
    for (std::size_t k = 0; k < values.size(); ++k)
      if (values[k].cols() > 12 && k % 2 == 0) values[k].middleCols(12, 6).setZero();
    expect_as_dense(lu, values, random, "trial " + std::to_string(trial));
  }
}

// A kept scaling (another matrix's, a Newton tangent's reference) on a matrix whose entries
// differ from that one's: solved as the dense LU solves it, backward stable, with its own
// determinant's sign. And the kept scaling of the same matrix gives the fresh factors' bits.
TEST(BlockLU, KeptScalingSolvesANeighbouringMatrix) {
  std::mt19937 random(19);
  std::uniform_real_distribution<double> change(-1e-2, 1e-2);
  for (const BlockLayout& layout : {chain(4), three_legs()}) {
    BlockLU lu;
    lu.analyze(layout);
    const std::vector<MatX> reference = random_values(layout, random);
    const Index n = 12 * layout.group_count;
    const MatX b = MatX::Random(n, 2);
    const Solved fresh = factorise_and_solve(lu, reference, b);
    const BlockScaling kept = lu.scaling();
    expect_same_bits(factorise_and_solve(lu, reference, b, &kept), fresh);

    for (int trial = 0; trial < 5; ++trial) {
      std::vector<MatX> neighbour = reference;
      for (MatX& v : neighbour)
        for (Index k = 0; k < v.size(); ++k) v.data()[k] *= 1 + change(random);
      // Some entries change sign: the determinant's sign is the neighbour's own.
      if (trial % 2 == 1) neighbour[1] *= -1;
      const MatX a = dense(layout, neighbour);
      ASSERT_EQ(lu.factorise(neighbour, &kept), BlockLU::Outcome::factorised);
      MatX x = b;
      lu.solve(x);
      const Eigen::PartialPivLU<MatX> dense_lu(a);
      const MatX dense_solution = dense_lu.solve(b);
      MatX exact = dense_solution;
      for (int step = 0; step < 3; ++step) exact += dense_lu.solve(residual_extended(a, exact, b));
      EXPECT_LE(relative_difference(x, exact),
                std::max(kAgreement, kSameDigits * relative_difference(dense_solution, exact)));
      EXPECT_LT(backward_error(a, x, b), kBackwardStable);
      EXPECT_EQ(lu.determinant_sign(), dense_lu.determinant() > 0 ? 1.0 : -1.0);
    }
  }
}

// A kept scaling of another layout's size is not taken (the matrix is scaled afresh); a
// non-finite entry is singular under a kept scaling too; a column shrunk far below what the
// kept scaling was made for reads as a tiny pivot (the caller then scales afresh), which its own
// scaling factorises.
TEST(BlockLU, KeptScalingOfAnotherSizeOrStale) {
  std::mt19937 random(23);
  const BlockLayout layout = chain(3);
  BlockLU lu;
  lu.analyze(layout);
  const std::vector<MatX> values = random_values(layout, random);
  const MatX b = MatX::Random(12 * layout.group_count, 1);
  const Solved fresh = factorise_and_solve(lu, values, b);
  const BlockScaling kept = lu.scaling();
  const BlockScaling other_size{VecX::Ones(12), VecX::Ones(12)};
  expect_same_bits(factorise_and_solve(lu, values, b, &other_size), fresh);

  std::vector<MatX> not_finite = values;
  not_finite[2](3, 5) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(lu.factorise(not_finite, &kept), BlockLU::Outcome::singular);

  std::vector<MatX> shrunk = values;
  for (std::size_t k = 0; k < layout.rows.size(); ++k)
    for (std::size_t g = 0; g < layout.groups[k].size(); ++g)
      if (layout.groups[k][g] == 2) shrunk[k].col(12 * static_cast<Index>(g) + 7) *= 1e-12;
  EXPECT_EQ(lu.factorise(shrunk, &kept), BlockLU::Outcome::tiny_pivot);
  EXPECT_EQ(lu.factorise(shrunk), BlockLU::Outcome::factorised);
}

std::vector<std::string> model_files() {
  std::vector<std::string> files;
  for (const char* folder : {"/examples", "/examples/robots", "/tests/data/frame3dd"}) {
    const std::filesystem::path path = std::string(STIFFMSA_SOURCE_DIR) + folder;
    if (!std::filesystem::is_directory(path)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(path))
      if (entry.path().extension() == ".yaml") files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The models of model_files() that load as one model, with their files.
std::vector<std::pair<std::string, Model>> loadable_models() {
  std::vector<std::pair<std::string, Model>> models;
  for (const std::string& file : model_files()) {
    try {
      models.emplace_back(file, load_model(file));
    } catch (const Error&) {
      // a parametric family, or a model of the invalid corpus
    }
  }
  return models;
}

// Every link end at its unloaded position, no wrench.
std::vector<EndState> unloaded_ends(const Model& model, const Topology& topology) {
  std::vector<EndState> ends(static_cast<std::size_t>(topology.end_count()));
  for (int e = 0; e < topology.end_count(); ++e)
    ends[static_cast<std::size_t>(e)].position =
        model.points[static_cast<std::size_t>(topology.end_points[static_cast<std::size_t>(e)])]
            .position;
  return ends;
}

// The loaded blocks' values at the unloaded pose under the model's loads (`factor` of them).
std::vector<MatX> loaded_values(const Model& model, const Topology& topology,
                                const std::vector<std::unique_ptr<LoadedBlock>>& blocks,
                                double factor) {
  const std::vector<EndState> ends = unloaded_ends(model, topology);
  std::vector<Vec6> external = end_loads(model, topology);
  for (Vec6& w : external) w *= factor;
  std::vector<MatX> values(blocks.size());
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    VecX residual(blocks[b]->equation_count());
    blocks[b]->evaluate(LoadedInputs{ends, external, factor}, residual, &values[b]);
  }
  return values;
}

BlockLayout layout_of(const std::vector<std::unique_ptr<LoadedBlock>>& blocks, int ends) {
  BlockLayout layout;
  layout.group_count = ends;
  for (const auto& b : blocks) {
    layout.rows.push_back(static_cast<int>(b->equation_count()));
    layout.groups.push_back(b->ends());
  }
  return layout;
}

TEST(BlockLU, LoadedTangentsOfTheExamplesAsDenseLU) {
  std::mt19937 random(3);
  int checked = 0;
  for (const auto& [file, model] : loadable_models()) {
    const Topology topology = build_topology(model);
    if (topology.unknowns() > kLargestDense) continue;
    const auto blocks = make_loaded_blocks(
        model, topology, std::vector<std::vector<LoadAlongLink>>(model.links.size()));
    BlockLU lu;
    lu.analyze(layout_of(blocks, topology.end_count()));
    for (double factor : {0.0, 1.0}) {
      const std::vector<MatX> values = loaded_values(model, topology, blocks, factor);
      // A mechanism's tangent (the planar robots' out-of-plane motions) is singular.
      if (lu.factorise(values) != BlockLU::Outcome::factorised) continue;
      expect_as_dense(lu, values, random, file + " at load factor " + std::to_string(factor));
      ++checked;
    }
  }
  EXPECT_GE(checked, 10);
}

// The loaded mode's sign of the unloaded tangent (the critical-point check): by the block LU
// as by KLU on every example and test model.
TEST(BlockLU, UnloadedDeterminantSignAsKlu) {
  if (!solver_available(SolverKind::klu)) GTEST_SKIP() << "built without KLU";
  int checked = 0;
  for (const auto& [file, model] : loadable_models()) {
    const Topology topology = build_topology(model);
    const auto blocks = make_loaded_blocks(
        model, topology, std::vector<std::vector<LoadAlongLink>>(model.links.size()));
    const std::vector<EndState> ends = unloaded_ends(model, topology);
    const std::vector<Vec6> none(ends.size(), Vec6::Zero());
    LoadedTangent block(SolverKind::automatic), klu(SolverKind::klu);
    block.begin(blocks, topology.unknowns());
    klu.begin(blocks, topology.unknowns());
    const double sign = block.unloaded_determinant_sign(LoadedInputs{ends, none, 0.0});
    EXPECT_EQ(sign, klu.unloaded_determinant_sign(LoadedInputs{ends, none, 0.0})) << file;
    block.end();
    klu.end();
    if (sign != 0) ++checked;
  }
  EXPECT_GE(checked, 10);
}

// The unloaded tangent of a second pose on the first pose's kept scaling (a sweep's next pose:
// the same layout, the ends moved): its sign is a fresh tangent's and KLU's, on every example
// and test model.
TEST(BlockLU, UnloadedSignOnAKeptScalingAsAFreshOneAndKlu) {
  if (!solver_available(SolverKind::klu)) GTEST_SKIP() << "built without KLU";
  std::mt19937 random(29);
  std::uniform_real_distribution<double> shift(-1e-3, 1e-3);
  int checked = 0;
  for (const auto& [file, model] : loadable_models()) {
    const Topology topology = build_topology(model);
    const auto blocks = make_loaded_blocks(
        model, topology, std::vector<std::vector<LoadAlongLink>>(model.links.size()));
    const std::vector<EndState> first_pose = unloaded_ends(model, topology);
    std::vector<EndState> second_pose = first_pose;
    for (EndState& end : second_pose)
      for (int i = 0; i < 3; ++i) end.position(i) += shift(random);
    const std::vector<Vec6> none(first_pose.size(), Vec6::Zero());
    LoadedTangent kept(SolverKind::automatic), fresh(SolverKind::automatic), klu(SolverKind::klu);
    for (LoadedTangent* tangent : {&kept, &fresh, &klu})
      tangent->begin(blocks, topology.unknowns());
    if (kept.unloaded_determinant_sign(LoadedInputs{first_pose, none, 0.0}) == 0) continue;
    const double sign = kept.unloaded_determinant_sign(LoadedInputs{second_pose, none, 0.0});
    EXPECT_EQ(sign, fresh.unloaded_determinant_sign(LoadedInputs{second_pose, none, 0.0})) << file;
    EXPECT_EQ(sign, klu.unloaded_determinant_sign(LoadedInputs{second_pose, none, 0.0})) << file;
    for (LoadedTangent* tangent : {&kept, &fresh, &klu}) tangent->end();
    if (sign != 0) ++checked;
  }
  EXPECT_GE(checked, 10);
}

// The loaded tangent's determinant sign is the last Newton tangent's: asked for before one is
// factorised (after `begin`, or after the unloaded tangent's, whose factors it does not keep),
// it is a usage error, not a read of factors that are not there.
TEST(LoadedTangent, DeterminantSignBeforeAFactorisationIsAUsageError) {
  const std::string file = std::string(STIFFMSA_SOURCE_DIR) + "/examples/industrial-6axis.yaml";
  const Model model = load_model(file);
  const Topology topology = build_topology(model);
  const auto blocks = make_loaded_blocks(
      model, topology, std::vector<std::vector<LoadAlongLink>>(model.links.size()));
  const std::vector<EndState> ends = unloaded_ends(model, topology);
  const std::vector<Vec6> none(ends.size(), Vec6::Zero());
  std::vector<SolverKind> kinds{SolverKind::automatic};
  if (solver_available(SolverKind::klu)) kinds.push_back(SolverKind::klu);
  for (SolverKind kind : kinds) {
    LoadedTangent tangent(kind);
    EXPECT_THROW(tangent.determinant_sign(), UsageError);
    tangent.begin(blocks, topology.unknowns());
    EXPECT_THROW(tangent.determinant_sign(), UsageError);
    const double unloaded = tangent.unloaded_determinant_sign(LoadedInputs{ends, none, 0.0});
    ASSERT_NE(unloaded, 0);
    EXPECT_THROW(tangent.determinant_sign(), UsageError);
    VecX residual;
    ASSERT_TRUE(tangent.evaluate(LoadedInputs{ends, none, 0.0}, residual, true));
    EXPECT_EQ(tangent.determinant_sign(), unloaded);
    tangent.end();
  }
}

}  // namespace
}  // namespace stiffmsa::detail

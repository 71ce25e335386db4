#pragma once
// What the solves that do not factorise the mixed system (the tree solve, the frame solve) are
// tested against: every number a factorising solve of the same model reports. And a frame to
// test them on.
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>

#include "stiffmsa/stiffmsa.hpp"

namespace stiffmsa::testing {

inline const Material kFrameSteel{2.1e11, 0.3, std::nullopt};

inline SolverKind factorising_solver() {
  return solver_available(SolverKind::klu) ? SolverKind::klu : SolverKind::sparse_lu;
}

// Largest difference between two optional vectors or matrices over the largest entry of the
// factorised one (both absent counts as equal, one absent as a failure).
template <class T>
void expect_same(const std::optional<T>& tested, const std::optional<T>& factorised,
                 double& largest_difference, double scale, const std::string& what) {
  ASSERT_EQ(tested.has_value(), factorised.has_value()) << what;
  if (!tested) return;
  ASSERT_EQ(tested->size(), factorised->size()) << what;
  if (factorised->size() == 0) return;  // a rigid joint's relative deflection
  const double size = std::max(scale, factorised->cwiseAbs().maxCoeff());
  if (size == 0) return;
  largest_difference =
      std::max(largest_difference, (*tested - *factorised).cwiseAbs().maxCoeff() / size);
}

// Every reported number of two results of one model, each kind relative to its largest entry.
// `most_residual`: the relative residual and the equilibrium error the result under test must
// stay below (the equilibrium error below 1e-13 at least).
inline void expect_same_results(const Result& tested, const Result& factorised, double tolerance,
                                double most_residual = 1e-15) {
  auto largest_deflection = 0.0, largest_wrench = 0.0;
  for (const auto& l : factorised.links)
    for (const auto* end : {&l.from, &l.to}) {
      if (end->deflection)
        largest_deflection = std::max(largest_deflection, end->deflection->cwiseAbs().maxCoeff());
      if (end->wrench)
        largest_wrench = std::max(largest_wrench, end->wrench->cwiseAbs().maxCoeff());
    }
  double difference = 0;
  ASSERT_EQ(tested.links.size(), factorised.links.size());
  for (std::size_t l = 0; l < tested.links.size(); ++l) {
    const std::string name = "link " + factorised.links[l].name;
    expect_same(tested.links[l].from.deflection, factorised.links[l].from.deflection, difference,
                largest_deflection, name);
    expect_same(tested.links[l].to.deflection, factorised.links[l].to.deflection, difference,
                largest_deflection, name);
    expect_same(tested.links[l].from.wrench, factorised.links[l].from.wrench, difference,
                largest_wrench, name);
    expect_same(tested.links[l].to.wrench, factorised.links[l].to.wrench, difference,
                largest_wrench, name);
  }
  for (std::size_t j = 0; j < tested.joints.size(); ++j) {
    const std::string name = "joint " + factorised.joints[j].name;
    expect_same(tested.joints[j].wrench, factorised.joints[j].wrench, difference, largest_wrench,
                name);
    expect_same(tested.joints[j].effort, factorised.joints[j].effort, difference, largest_wrench,
                name);
    ASSERT_EQ(tested.joints[j].relative_deflection.has_value(),
              factorised.joints[j].relative_deflection.has_value());
    if (tested.joints[j].relative_deflection)
      for (std::size_t k = 0; k < tested.joints[j].relative_deflection->size(); ++k)
        expect_same(std::optional<VecX>((*tested.joints[j].relative_deflection)[k]),
                    std::optional<VecX>((*factorised.joints[j].relative_deflection)[k]), difference,
                    largest_deflection, name);
  }
  for (std::size_t s = 0; s < tested.supports.size(); ++s)
    expect_same(tested.supports[s].reaction, factorised.supports[s].reaction, difference,
                largest_wrench, "support " + factorised.supports[s].name);
  for (std::size_t e = 0; e < tested.end_effectors.size(); ++e) {
    const std::string name = "end effector " + factorised.end_effectors[e].name;
    expect_same(tested.end_effectors[e].compliance, factorised.end_effectors[e].compliance,
                difference, 0.0, name);
    expect_same(tested.end_effectors[e].stiffness, factorised.end_effectors[e].stiffness,
                difference, 0.0, name);
    expect_same(tested.end_effectors[e].deflection, factorised.end_effectors[e].deflection,
                difference, largest_deflection, name);
  }
  EXPECT_LT(difference, tolerance);
  // Counted block by block, the system the factorising solve assembles.
  EXPECT_EQ(tested.system.unknowns, factorised.system.unknowns);
  EXPECT_EQ(tested.system.equations, factorised.system.equations);
  EXPECT_EQ(tested.system.nonzeros, factorised.system.nonzeros);
  EXPECT_LT(tested.report.relative_residual, most_residual);
  EXPECT_LT(tested.report.equilibrium_error, std::max(1e-13, most_residual));
  EXPECT_TRUE(tested.report.failed_checks.empty());
}

// A building frame: (nx+1)×(ny+1) columns per storey, girders along x and y on every floor,
// clamped at the ground. Its stacked system is far from structurally symmetric.
inline Model building(int nx, int ny, int storeys) {
  auto node = [](int i, int j, int k) {
    return "n" + std::to_string(i) + "_" + std::to_string(j) + "_" + std::to_string(k);
  };
  Model m;
  for (int k = 0; k <= storeys; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.add_point(node(i, j, k), Vec3(4.0 * i, 4.0 * j, 3.5 * k));
  for (int k = 1; k <= storeys; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        m.add_beam("c" + node(i, j, k), node(i, j, k - 1), node(i, j, k), kFrameSteel,
                   Section::rect_tube(0.3, 0.3, 0.012));
        if (i < nx)
          m.add_beam("x" + node(i, j, k), node(i, j, k), node(i + 1, j, k), kFrameSteel,
                     Section::rect_tube(0.2, 0.35, 0.01));
        if (j < ny)
          m.add_beam("y" + node(i, j, k), node(i, j, k), node(i, j + 1, k), kFrameSteel,
                     Section::rect_tube(0.2, 0.35, 0.01));
      }
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.add_support("g" + node(i, j, 0), node(i, j, 0), {}, Connection::rigid());
  m.add_end_effector("roof", node(nx, ny, storeys), "c" + node(nx, ny, storeys));
  return m;
}

}  // namespace stiffmsa::testing

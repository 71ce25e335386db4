// Frame3DD's examples written as stiffmsa models (tests/data/frame3dd/*.yaml, whose comments say
// what each is and what differs), against the joint displacements and reactions Frame3DD prints
// in its own output files (examples/*.out of the Frame3DD distribution), to the digits printed.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/stiffmsa.hpp"

using namespace stiffmsa;

namespace {

Model frame3dd_model(const std::string& name) {
  return load_model(std::string(STIFFMSA_SOURCE_DIR) + "/tests/data/frame3dd/" + name);
}

// The deflection of the joint at `point`: of the first link end there.
Vec6 joint_deflection(const Model& model, const Result& result, const std::string& point) {
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    if (model.links[l].from == point) return *result.links[l].from.deflection;
    if (model.links[l].to == point) return *result.links[l].to.deflection;
  }
  ADD_FAILURE() << "no link end at " << point;
  return Vec6::Zero();
}

// A printed value v with `decimals` digits after the point stands for [v − h, v + h], h half a
// unit of its last digit; the rounding of our own value adds nothing at that scale.
void expect_printed(double ours, double printed, int decimals, const std::string& what) {
  const double half_unit = 0.5 * std::pow(10.0, -decimals);
  EXPECT_NEAR(ours, printed, half_unit * (1 + 1e-9)) << what;
}

struct PrintedJoint {
  const char* point;
  std::array<double, 6> displacement;  // X, Y, Z (in), X, Y, Z rotations (rad)
};

TEST(Frame3DD, ExampleATrussWithSupportSettlement) {
  const Model model = frame3dd_model("exA-case1.yaml");
  const Result r = solve(model);
  // exA.out, load case 1: J O I N T   D I S P L A C E M E N T S (global), 6 decimals.
  const std::vector<PrintedJoint> printed = {
      {"n1", {0.0, 0.0, 0.0, 0.0, 0.0, -0.001345}},
      {"n2", {0.011745, -0.163879, 0.0, 0.0, 0.0, -0.001037}},
      {"n3", {0.036037, -0.284156, 0.0, 0.0, 0.0, -0.000577}},
      {"n4", {0.060329, -0.315889, 0.0, 0.0, 0.0, 0.000023}},
      {"n5", {0.084889, -0.279500, 0.0, 0.0, 0.0, 0.000541}},
      {"n6", {0.109449, -0.174012, 0.0, 0.0, 0.0, 0.001021}},
      {"n7", {0.125867, 0.0, 0.0, 0.0, 0.0, 0.001479}},
      {"n8", {0.100000, -0.147194, 0.0, 0.0, 0.0, -0.000921}},
      {"n9", {0.088255, -0.275880, 0.0, 0.0, 0.0, -0.000632}},
      {"n10", {0.059691, -0.315889, 0.0, 0.0, 0.0, 0.000006}},
      {"n11", {0.031127, -0.275362, 0.0, 0.0, 0.0, 0.000599}},
      {"n12", {0.014710, -0.157594, 0.0, 0.0, 0.0, 0.000928}},
  };
  for (const PrintedJoint& joint : printed) {
    const Vec6 ours = joint_deflection(model, r, joint.point);
    for (int k = 0; k < 6; ++k)
      expect_printed(ours(k), joint.displacement[static_cast<std::size_t>(k)], 6,
                     std::string(joint.point) + " component " + std::to_string(k));
  }
  // R E A C T I O N S (global), 3 decimals: the ground's force on the truss.
  expect_printed((*r.support("n1").reaction)(0), 11.941, 3, "n1 Fx");
  expect_printed((*r.support("n1").reaction)(1), 40.323, 3, "n1 Fy");
  expect_printed((*r.support("n7").reaction)(1), 39.677, 3, "n7 Fy");
  expect_printed((*r.support("n8").reaction)(0), -11.941, 3, "n8 Fx");
  for (const char* free_of_load : {"n2", "n3", "n4", "n5", "n6", "n9", "n10", "n11", "n12"})
    for (int k : {0, 1, 5})
      expect_printed((*r.support(free_of_load).reaction)(k), 0.0, 3, free_of_load);
  EXPECT_LT(r.report.equilibrium_error, 1e-12);
}

TEST(Frame3DD, SelfWeightAndUniformLoadCases) {
  const Model model = frame3dd_model("selfweight.yaml");
  const Result r = solve(model);
  ASSERT_EQ(r.load_cases.size(), 2u);
  // selfweight.out: both load cases print the same displacements and reactions.
  const std::vector<PrintedJoint> printed = {
      {"j2", {0.006063, 0.006063, -0.014975, -0.001355, 0.001355, 0.0}},
      {"j3", {0.088000, 0.088000, -0.185600, -0.003920, 0.003920, 0.0}},
      {"j4", {0.270400, 0.270400, -0.555200, -0.004960, 0.004960, 0.0}},
      {"j5", {0.370000, 0.370000, -0.755000, -0.005000, 0.005000, 0.0}},
  };
  for (const Result& c : r.load_cases) {
    SCOPED_TRACE(c.load_case);
    for (const PrintedJoint& joint : printed) {
      const Vec6 ours = joint_deflection(model, c, joint.point);
      for (int k = 0; k < 6; ++k)
        expect_printed(ours(k), joint.displacement[static_cast<std::size_t>(k)], 6,
                       std::string(joint.point) + " component " + std::to_string(k));
    }
    const Vec6 reaction = *c.support("j1").reaction;
    expect_printed(reaction(2), 173.205, 3, "Fz");
    expect_printed(reaction(3), 8660.254, 3, "Mxx");
    expect_printed(reaction(4), -8660.254, 3, "Myy");
    for (int k : {0, 1, 5}) expect_printed(reaction(k), 0.0, 3, "reaction");
    // F R A M E   E L E M E N T   E N D   F O R C E S (local): element 1 at joint 1, Nx
    // 100.000 in compression and Vz 141.421; our internal force at the element's start is the
    // wrench of the part beyond on the part before, N = −100 (compression).
    const InternalForces& start = c.link("e1").internal_forces.front();
    expect_printed(start.forces(0), -100.000, 3, "e1 N at j1");
    EXPECT_LT(c.report.equilibrium_error, 1e-12);
  }
}

}  // namespace

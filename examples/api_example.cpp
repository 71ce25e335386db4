// The planar 2R arm of examples/planar-2r.yaml, built through the C++ API instead of a file:
// the model is described with the same verbs a file uses (points, links, joints, supports,
// loads, end effectors), solved, and the Cartesian stiffness at the tool is printed.
//
//   cmake --build build -j2 --target api_example && build/api_example
//
// The numbers match `build/stiffmsa solve examples/planar-2r.yaml`.
#include <iostream>
#include <optional>
#include <stiffmsa/stiffmsa.hpp>

namespace {

stiffmsa::Model planar_2r_arm() {
  stiffmsa::Material aluminium;
  aluminium.E = 7.0e10;  // Pa
  aluminium.nu = 0.33;   // Poisson's ratio; the shear modulus follows from E and nu

  stiffmsa::Model model;
  model.name = "planar-2r";
  // Named as a model file names them under `materials:` and `sections:`. Box sections: width b
  // along the beam's local y (horizontal here), height h along local z.
  model.add_material("aluminium", aluminium);
  model.add_section("upper_box", stiffmsa::Section::rect_tube(0.06, 0.08, 0.004));
  model.add_section("fore_box", stiffmsa::Section::rect_tube(0.05, 0.06, 0.003));

  // Shoulder angle 36.87 deg, elbow +90 deg: a pose far from the stretched-out singularity.
  model.add_point("floor", {0, 0, -0.25});
  model.add_point("shoulder", {0, 0, 0});
  model.add_point("elbow", {0.48, 0.36, 0});
  model.add_point("tip", {0.21, 0.72, 0});

  model.add_rigid_link("pedestal", "floor", "shoulder");
  model.add_beam("upper_arm", "shoulder", "elbow", "aluminium", "upper_box");
  model.add_beam("forearm", "elbow", "tip", "aluminium", "fore_box");

  // Gearboxes seen from the arm: free to turn about the vertical against a torsional spring
  // (N·m/rad, a scalar for the one free direction), rigid in the other five directions.
  const auto turning = stiffmsa::Kinematics::revolute({0, 0, 1});
  model.add_joint("shoulder_joint", "shoulder", {"pedestal", "upper_arm"},
                  stiffmsa::Connection::elastic(turning, 2.0e5));
  model.add_joint("elbow_joint", "elbow", {"upper_arm", "forearm"},
                  stiffmsa::Connection::elastic(turning, 1.0e5));

  // The pedestal is bolted to the floor. An empty list of links means every link end at the
  // point.
  model.add_support("base", "floor", {}, stiffmsa::Connection::rigid());

  // [Fx, Fy, Fz, Mx, My, Mz] in N and N·m, global axes, moments about the tip. Only one link
  // end is at the tip, so the link need not be named.
  model.add_load("tip", std::nullopt, stiffmsa::Vec6(50, -200, 0, 0, 0, 0));
  model.add_end_effector("tool", "tip");
  return model;
}

void print_end_effector(const stiffmsa::EndEffectorResult& ee) {
  const Eigen::IOFormat matrix_format(4, 0, "  ", "\n", "    ", "");
  std::cout << "End effector '" << ee.name << "' at point '" << ee.point << "'\n";

  // The stiffness is absent where the end effector is held rigidly in some direction (the
  // stiffness there would be infinite); the compliance is always given.
  if (ee.stiffness) {
    std::cout << "  stiffness [N/m, N/rad; N·m/m, N·m/rad], rows Fx..Mz, columns dx..rz:\n"
              << ee.stiffness->format(matrix_format) << '\n';
  } else {
    std::cout << "  stiffness: unbounded (held rigidly in some direction)\n";
  }

  // Principal stiffness against a pure force and against a pure moment: how stiff the tool is
  // in its softest and stiffest directions.
  if (ee.compliance) {
    const stiffmsa::PrincipalStiffness principal = stiffmsa::principal_stiffness(*ee.compliance);
    std::cout << "  principal stiffness against a force  [N/m]:     "
              << principal.translational.transpose() << '\n'
              << "  principal stiffness against a moment [N·m/rad]: "
              << principal.rotational.transpose() << '\n';
  }
  if (ee.deflection) {
    std::cout << "  deflection under the load [m, rad]: " << ee.deflection->transpose() << '\n';
  }
}

}  // namespace

int main() {
  try {
    const stiffmsa::Result result = stiffmsa::solve(planar_2r_arm());
    // By name, as the model names it (result.end_effectors lists them all in model order).
    print_end_effector(result.end_effector("tool"));
    if (!result.report.usable()) std::cerr << "api_example: an accuracy check failed\n";
    for (const auto& note : result.report.notes) std::cout << "note: " << note << '\n';
    return 0;
  } catch (const stiffmsa::InputError& error) {
    // One line per defect of the model, naming the entity and key at fault.
    for (const auto& defect : error.diagnostics())
      std::cerr << "api_example: invalid model: " << defect.to_string() << '\n';
  } catch (const stiffmsa::Error& error) {
    // A mechanism, a singular model, or a misuse of the API.
    std::cerr << "api_example: " << error.what() << '\n';
  }
  return 1;
}

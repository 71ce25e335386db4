#pragma once
// Models and values that several test files build: written once here, so that a change of the
// API or of the file format is made in one place.
#include <functional>
#include <string>

#include "stiffmsa/stiffmsa.hpp"

namespace stiffmsa::testing {

// A wrench [Fx, Fy, Fz, Mx, My, Mz] (N, N·m).
inline Vec6 wrench(double fx, double fy, double fz, double mx = 0, double my = 0, double mz = 0) {
  return (Vec6() << fx, fy, fz, mx, my, mz).finished();
}

// A spatial arm: a beam column O-A on the support "base", a beam upper arm A-B and a rigid
// forearm B-E, the revolute joints "shoulder" (stiffness joint_stiffness) and "elbow" (half of
// it) about y, 200 N down at E, the end effector "tool" at E. elbow_x moves B and E: a pose.
inline Model two_joint_arm(double elbow_x, double joint_stiffness) {
  Model m;
  const Material steel{2.1e11, 0.3, std::nullopt};
  m.add_point("O", Vec3::Zero());
  m.add_point("A", Vec3(0, 0, 0.4));
  m.add_point("B", Vec3(elbow_x, 0.1, 0.5));
  m.add_point("E", Vec3(elbow_x + 0.3, 0.0, 0.3));
  m.add_beam("column", "O", "A", steel, Section::tube(0.1, 0.006));
  m.add_beam("upper", "A", "B", steel, Section::tube(0.08, 0.005));
  m.add_rigid_link("fore", "B", "E");
  m.add_support("base", "O", {}, Connection::rigid());
  m.add_joint("shoulder", "A", {"column", "upper"},
              Connection::elastic(Kinematics::revolute(Vec3::UnitY()), joint_stiffness));
  m.add_joint("elbow", "B", {"upper", "fore"},
              Connection::elastic(Kinematics::revolute(Vec3::UnitY()), 0.5 * joint_stiffness));
  m.add_load("E", std::nullopt, wrench(0, 0, -200));
  m.add_end_effector("tool", "E");
  return m;
}

// A chain of `segments` beams L1 … Ln through the points P0 … Pn (P_i at position(i)), clamped
// at P0 by the support "ground", with the end effector "tip" at Pn.
inline Model beam_chain(int segments, const std::function<Vec3(int)>& position,
                        const Material& material, const Section& section) {
  Model m;
  m.add_point("P0", position(0));
  for (int i = 1; i <= segments; ++i) {
    const std::string point = "P" + std::to_string(i);
    m.add_point(point, position(i));
    m.add_beam("L" + std::to_string(i), "P" + std::to_string(i - 1), point, material, section);
  }
  m.add_support("ground", "P0", {}, Connection::rigid());
  m.add_end_effector("tip", "P" + std::to_string(segments));
  return m;
}

// A model file: a steel rod of 1 m (D 50 mm) clamped at O, loaded by 100 N at its tip E.
inline constexpr const char* kCantileverYaml = R"(format: stiffmsa/1
name: cantilever
points:
  O: [0, 0, 0]
  E: [1, 0, 0]
links:
  L1:
    type: beam
    from: O
    to: E
    material: {E: 2.1e11, nu: 0.3}
    section: {shape: circle, D: 0.05}
supports:
  S1: {type: rigid, at: O, link: L1}
loads:
  - {at: E, link: L1, wrench: [0, -100, 0, 0, 0, 0]}
end_effectors:
  EE: {at: E, link: L1}
)";

}  // namespace stiffmsa::testing

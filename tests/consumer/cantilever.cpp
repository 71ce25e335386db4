// A cantilever of one beam, built and solved through stiffmsa::core alone: the tip's stiffness
// against a transverse force alone is 3·E·I/L³ (Euler–Bernoulli), which the solve gives to
// rounding.
#include <cmath>
#include <cstdio>
#include <stiffmsa/analysis.hpp>
#include <stiffmsa/model.hpp>

int main() {
  constexpr double length = 2.0, E = 2.1e11, nu = 0.3, b = 0.05, h = 0.08;
  stiffmsa::Material steel;
  steel.E = E;
  steel.nu = nu;
  stiffmsa::Model model;
  model.name = "cantilever";
  model.add_point("root", {0, 0, 0});
  model.add_point("tip", {length, 0, 0});
  model.add_beam("beam", "root", "tip", steel, stiffmsa::Section::rect(b, h));
  model.add_support("clamp", "root", {}, stiffmsa::Connection::rigid());
  model.add_end_effector("tip", "tip");

  const stiffmsa::Result result = stiffmsa::solve(model);
  const auto& compliance = result.end_effectors.at(0).compliance;
  if (!compliance) {
    std::fprintf(stderr, "cantilever: no compliance at the tip\n");
    return 1;
  }
  // Default axes: local y along global Y, so the force along Y bends about local z (I = h·b³/12).
  const double second_moment = h * b * b * b / 12;
  const double expected = 3 * E * second_moment / (length * length * length);
  // A force alone (the tip free to turn): 1 / C_yy. (K = C⁻¹ holds the turn, 12·E·I/L³.)
  const double got = 1 / (*compliance)(1, 1);
  const double relative = std::abs(got - expected) / expected;
  std::printf("tip stiffness along y: %.12g N/m (3EI/L^3 = %.12g N/m, relative difference %.1e)\n",
              got, expected, relative);
  constexpr double kRoundOff = 1e-9;
  return relative <= kRoundOff ? 0 : 1;
}

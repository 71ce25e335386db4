// The viewer's numbers and safety: the deformed shape between a beam's ends against the
// closed form of a cantilever, the HTML page's data block against hostile names, and the VTK
// file's layout. (The pages in a browser: tests/browser/test_viewer.py.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "stiffmsa/stiffmsa.hpp"

namespace {

using namespace stiffmsa;

// A steel rod clamped at the origin, along the diagonal e, loaded at its tip by a force across
// it (along n), an axial force and a torque: bending, stretching and twist at once.
constexpr double kLength = 1.5;
constexpr double kYoungs = 2.1e11;
constexpr double kPoisson = 0.3;
constexpr double kDiameter = 0.04;
constexpr double kTransverseForce = -250.0;
constexpr double kAxialForce = 4000.0;
constexpr double kTorque = 30.0;

struct Cantilever {
  Vec3 e = Vec3(1, 2, 2) / 3;
  Vec3 n = Vec3(2, 1, -2) / 3;  // across the rod: e·n = 0
  Model model;
  Result result;
  Cantilever() {
    model.add_point("O", Vec3::Zero());
    model.add_point("E", kLength * e);
    model.add_beam("rod", "O", "E", Material{kYoungs, kPoisson, std::nullopt, std::nullopt},
                   Section::circle(kDiameter));
    model.add_support("clamp", "O", {}, Connection::rigid());
    Vec6 wrench;
    wrench << kTransverseForce * n + kAxialForce * e, kTorque * e;
    model.add_load("E", std::nullopt, wrench);
    model.add_end_effector("tip", "E");
    result = solve(model);
  }
};

// Euler–Bernoulli: v(x) = P x²(3L − x)/(6EI), slope θ(x) = P x(2L − x)/(2EI); u(x) = N x/(EA);
// twist ψ(x) = T x/(GJ).
CentreLineMotion closed_form(const Cantilever& c, double x) {
  const double area = std::numbers::pi * kDiameter * kDiameter / 4;
  const double inertia = std::numbers::pi * std::pow(kDiameter, 4) / 64;
  const double polar = 2 * inertia;
  const double shear_modulus = kYoungs / (2 * (1 + kPoisson));
  const double v = kTransverseForce * x * x * (3 * kLength - x) / (6 * kYoungs * inertia);
  const double slope = kTransverseForce * x * (2 * kLength - x) / (2 * kYoungs * inertia);
  CentreLineMotion motion;
  motion.displacement = v * c.n + kAxialForce * x / (kYoungs * area) * c.e;
  // A slope along n turns e towards n: a rotation about e × n.
  motion.rotation = slope * c.e.cross(c.n) + kTorque * x / (shear_modulus * polar) * c.e;
  return motion;
}

TEST(DeformedShape, BeamFollowsTheCantileverClosedFormAlongItsLength) {
  const Cantilever c;
  const LinkResult& rod = c.result.links.at(0);
  ASSERT_TRUE(rod.from.deflection && rod.to.deflection);
  const CentreLineMotion tip = closed_form(c, kLength);
  for (const double xi : {0.0, 0.1, 0.3, 0.5, 0.77, 1.0}) {
    const CentreLineMotion drawn = centre_line_motion(true, Vec3::Zero(), kLength * c.e,
                                                      *rod.from.deflection, *rod.to.deflection, xi);
    const CentreLineMotion expected = closed_form(c, xi * kLength);
    EXPECT_LT((drawn.displacement - expected.displacement).norm(), 1e-9 * tip.displacement.norm())
        << "xi " << xi;
    EXPECT_LT((drawn.rotation - expected.rotation).norm(), 1e-9 * tip.rotation.norm())
        << "xi " << xi;
  }
}

TEST(DeformedShape, ChordIsTheLinearInterpolationOfTheEnds) {
  Vec6 from, to;
  from << 1, 2, 3, 0.1, 0.2, 0.3;
  to << -4, 5, 6, 0.4, -0.5, 0.6;
  const CentreLineMotion middle =
      centre_line_motion(false, Vec3::Zero(), Vec3(1, 0, 0), from, to, 0.25);
  EXPECT_EQ(middle.displacement, Vec3(-0.25, 2.75, 3.75));
  EXPECT_LT((middle.rotation - Vec3(0.175, 0.025, 0.375)).norm(), 1e-15);
}

TEST(DeformedShape, RigidMotionOfABeamStaysStraight) {
  // A beam carried rigidly (translation t, small rotation r about the origin) bends not at all.
  const Vec3 a(0.2, -0.1, 0.3), b(1.1, 0.4, -0.2), t(1e-3, -2e-3, 5e-4), r(2e-3, 1e-3, -3e-3);
  Vec6 from, to;
  from << t + r.cross(a), r;
  to << t + r.cross(b), r;
  for (const double xi : {0.2, 0.5, 0.9}) {
    const CentreLineMotion m = centre_line_motion(true, a, b, from, to, xi);
    EXPECT_LT((m.displacement - (t + r.cross(a + xi * (b - a)))).norm(), 1e-15);
    EXPECT_LT((m.rotation - r).norm(), 1e-15);
  }
}

TEST(PrincipalAxes, DiagonalisesTheBlockWithStiffnessItsInverse) {
  Mat3 block;
  block << 4, 1, 0, 1, 3, 0, 0, 0, 1e-30;  // z rigidly held
  const PrincipalAxes axes = principal_axes(block);
  for (int k = 0; k < 3; ++k)
    EXPECT_LT((block * axes.directions.col(k) - axes.compliance(k) * axes.directions.col(k)).norm(),
              1e-14);
  EXPECT_TRUE(std::isinf(axes.stiffness(0)));
  EXPECT_NEAR(axes.stiffness(1), 1 / (3.5 - std::sqrt(1.25)), 1e-15);
  EXPECT_NEAR(axes.stiffness(2), 1 / (3.5 + std::sqrt(1.25)), 1e-15);
}

// ---- the page ----------------------------------------------------------------------------

// The JSON inside <script type="application/json" id="stiffmsa-data">.
nlohmann::json page_data(const std::string& page) {
  const std::string start = "<script type=\"application/json\" id=\"stiffmsa-data\">";
  const auto begin = page.find(start);
  EXPECT_NE(begin, std::string::npos);
  const auto end = page.find("</script>", begin);
  return nlohmann::json::parse(page.substr(begin + start.size(), end - begin - start.size()));
}

TEST(ModelView, HostileNamesStayDataAndCloseNoScriptBlock) {
  const std::string link_name = "<img src=x onerror=alert(1)>";
  const std::string model_name = "</script><script>alert(2)</script><!--";
  Cantilever c;
  c.model.name = model_name;
  c.model.links[0].name = link_name;
  c.result.model = model_name;
  const std::string page = model_view_html(c.model, &c.result);
  EXPECT_EQ(page.find("<img"), std::string::npos);
  EXPECT_EQ(page.find("alert(2)</script>"), std::string::npos);
  EXPECT_NE(page.find("\\u003cimg src=x onerror=alert(1)\\u003e"), std::string::npos);
  // The data block and the three scripts, and no other script element.
  std::size_t opened = 0;
  for (auto at = page.find("<script"); at != std::string::npos; at = page.find("<script", at + 1))
    ++opened;
  EXPECT_EQ(opened, 4u);
  const nlohmann::json data = page_data(page);
  EXPECT_EQ(data["name"], model_name);
  EXPECT_EQ(data["links"]["names"][0], link_name);
  // Nothing may be fetched: the page's policy allows no source but its own inline scripts.
  EXPECT_NE(page.find("default-src 'none'"), std::string::npos);
}

TEST(ModelView, JsonForScriptBlockEscapesWhatCouldEndTheBlock) {
  EXPECT_EQ(json_for_script_block(R"({"a":"</script>&<!--"})"),
            R"({"a":"\u003c/script\u003e\u0026\u003c!--"})");
  EXPECT_EQ(nlohmann::json::parse(json_for_script_block(R"({"a":"</script>&<!--"})"))["a"],
            "</script>&<!--");
}

TEST(ModelView, AutomaticScaleDrawsTheLargestDisplacementAsATenthOfTheModel) {
  const Cantilever c;
  const nlohmann::json data = page_data(model_view_html(c.model, &c.result));
  const double largest =
      c.result.end_effectors[0].deflection->head<3>().norm();  // the tip moves most
  EXPECT_NEAR(data["deformed"]["largest_displacement"].get<double>(), largest,
              1e-6 * largest);  // stored as float
  EXPECT_NEAR(data["deformed"]["automatic_scale"].get<double>(), 0.1 * kLength / largest,
              1e-6 * kLength / largest);
  EXPECT_EQ(data["deformed"]["scale"], data["deformed"]["automatic_scale"]);
  ModelViewOptions chosen;
  chosen.scale = 250;
  EXPECT_EQ(page_data(model_view_html(c.model, &c.result, chosen))["deformed"]["scale"], 250.0);
  chosen.scale = -1;
  EXPECT_THROW(model_view_html(c.model, &c.result, chosen), UsageError);
}

TEST(ModelView, EllipsoidCarriesTheTranslationalComplianceAxes) {
  const Cantilever c;
  const nlohmann::json effector =
      page_data(model_view_html(c.model, &c.result))["end_effectors"][0];
  const Mat3 block = c.result.end_effectors[0].compliance->topLeftCorner<3, 3>();
  for (int k = 0; k < 3; ++k) {
    const double value = effector["compliance"][k];
    const Vec3 direction(effector["directions"][k][0], effector["directions"][k][1],
                         effector["directions"][k][2]);
    EXPECT_LT((block * direction - value * direction).norm(), 1e-12 * block.norm());
    EXPECT_NEAR(effector["stiffness"][k].get<double>(), 1 / value, 1e-12 / value);
  }
}

TEST(ModelView, ModelWithoutResultSaysWhy) {
  const Cantilever c;
  ModelViewOptions options;
  options.not_solved = "a mechanism";
  const nlohmann::json data = page_data(model_view_html(c.model, nullptr, options));
  EXPECT_FALSE(data["deformed"]["solved"]);
  EXPECT_EQ(data["deformed"]["message"], "a mechanism");
}

// ---- VTK ---------------------------------------------------------------------------------

TEST(VtkFile, BeamIsCutIntoLinesThatCarryItsDeflectedShape) {
  const Cantilever c;
  const std::string text = vtu_text(c.model, c.result, 4);
  EXPECT_NE(text.find("NumberOfPoints=\"5\" NumberOfCells=\"4\""), std::string::npos);
  for (const char* name : {"\"displacement\"", "\"rotation\"", "\"link_kind\"",
                           "\"end_wrench_from\"", "\"end_wrench_to\""})
    EXPECT_NE(text.find(name), std::string::npos) << name;
  const std::string pvd = pvd_text({{"a<b", "x&y.vtu"}});
  EXPECT_NE(pvd.find("name=\"a&lt;b\" file=\"x&amp;y.vtu\""), std::string::npos);
  EXPECT_THROW(write_vtk(c.model, c.result, "out.vtk"), UsageError);
}

}  // namespace

namespace {

// The little-endian 32-bit floats of a base64 text, as the pages read them.
std::vector<float> floats_of(const std::string& base64) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes;
  unsigned bits = 0, count = 0;
  for (const char c : base64) {
    if (c == '=') break;
    bits = (bits << 6) | static_cast<unsigned>(alphabet.find(c));
    count += 6;
    if (count >= 8) {
      count -= 8;
      bytes += static_cast<char>((bits >> count) & 0xff);
    }
  }
  std::vector<float> values(bytes.size() / 4);
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint32_t word = 0;
    for (int b = 0; b < 4; ++b)
      word |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[4 * i + b])) << (8 * b);
    std::memcpy(&values[i], &word, 4);
  }
  return values;
}

TEST(SweepView, CarriesEachPoseValuesAndEllipsoidsAndEscapesNames) {
  const ModelFamily family =
      load_model_family(std::string(STIFFMSA_SOURCE_DIR) + "/examples/planar-3rpr-parametric.yaml");
  SweepOptions options;
  options.keep_matrices = true;
  options.threads = 1;
  SweepResult sweep =
      stiffmsa::sweep(family, grid_poses({{"x", 0.4, 0.5, 2}, {"y", 0.3, 0.3, 1}}), options);
  sweep.model = "<img src=x onerror=alert(1)>";
  const std::string page = sweep_view_html(sweep);
  EXPECT_EQ(page.find("<img"), std::string::npos);
  const nlohmann::json data = page_data(page);
  EXPECT_EQ(data["model"], sweep.model);
  ASSERT_EQ(data["poses"], 2);
  const auto column = find_sweep_column(sweep, "platform.k_trans_min");
  ASSERT_TRUE(column);
  for (const auto& entry : data["columns"]) {
    if (entry["name"] != "platform.k_trans_min") continue;
    const std::vector<float> values = floats_of(entry["values"]);
    for (std::size_t pose = 0; pose < 2; ++pose)
      EXPECT_EQ(values.at(pose), static_cast<float>(column_value(sweep, *column, pose)));
  }
  const std::vector<float> axes = floats_of(data["ellipsoids"][0]);
  ASSERT_EQ(axes.size(), 24u);
  for (std::size_t pose = 0; pose < 2; ++pose) {
    const PrincipalAxes expected =
        principal_axes(sweep.results[pose].end_effectors[0].compliance->topLeftCorner<3, 3>());
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(axes[12 * pose + static_cast<std::size_t>(k)],
                static_cast<float>(expected.compliance(k)));
  }
}

}  // namespace

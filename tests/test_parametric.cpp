// Parametric model files: `parameters:`, `derived:` and expressions wherever a number goes.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "io/expressions.hpp"
#include "io/slot_bindings.hpp"
#include "model/model_numbers.hpp"
#include "stiffmsa/analysis.hpp"
#include "stiffmsa/io/model_file.hpp"

namespace stiffmsa {
namespace {

// A steel cantilever of length L along x, its section and load given by expressions.
const char* const kCantilever = R"(format: stiffmsa/1
name: parametric-cantilever
parameters:
  L: {default: 0.5, unit: m}
  D: 0.02
  F: 100
derived:
  half: "L / 2"
materials:
  steel: {E: 2.1e11, nu: 0.3}
points:
  base: [0, 0, 0]
  middle: [half, 0, 0]
  tip: [L, "0", 0]
links:
  inner: {type: beam, from: base, to: middle, material: steel, section: {shape: circle, D: D}}
  outer: {type: beam, from: middle, to: tip, material: steel, section: {shape: circle, D: "D"}}
supports:
  clamp: {type: rigid, at: base}
loads:
  - {at: tip, wrench: [0, "-F", 0, 0, 0, 0]}
end_effectors:
  tip: {at: tip}
)";

// The first diagnostic's message of a rejected file (fails the test if it is accepted).
std::string first_error(const std::string& text) {
  try {
    parse_model(text, "p.yaml");
  } catch (const InputError& e) {
    return e.diagnostics().front().key_path + ": " + e.diagnostics().front().message;
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return {};
}

// The exception of type E that `action` throws, or nothing if it returns; the caller asserts
// that there is one (`ASSERT_TRUE(e) << ...`), which ends the test as a FAIL() in place would.
// Exceptions of other types pass through.
template <class E, class F>
std::optional<E> thrown(F&& action) {
  try {
    action();
  } catch (const E& e) {
    return e;
  }
  return std::nullopt;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The cantilever text with one line replaced.
std::string with(const std::string& from, const std::string& to) {
  std::string text = kCantilever;
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

// The member for `values` as one writer writes it, a sweep's thread writing its poses in turn.
Model written(const Structure& structure, ModelFamily::ValueWriter& write,
              const std::vector<double>& values) {
  std::vector<double> slots(structure.value_count());
  std::vector<Diagnostic> warnings;
  write(values, slots, warnings);
  return structure.model_with(slots);
}

// Issue 22's numbers are numbers like any other: expressions in loads along links, gravity,
// densities, settlements and load cases follow each member's parameters.
TEST(ParametricFile, ExpressionsWorkInLinkLoadsGravityDensitiesSettlementsAndCases) {
  const std::string text = R"(format: stiffmsa/1
parameters: {q: 500, g: 9.81, rho: 7850, s: 0.001, a: 0.3}
materials: {steel: {E: 2.1e11, nu: 0.3, density: rho}}
points: {O: [0, 0, 0], E: [1, 0, 0]}
links: {beam: {type: beam, from: O, to: E, material: steel, section: {shape: circle, D: 0.02}}}
supports: {clamp: {type: rigid, at: O, displacement: [0, 0, "-s", 0, 0, 0]}}
gravity: [0, 0, "-g"]
loads:
  - {link: beam, distributed: [0, 0, "-q"]}
  - {link: beam, distributed: {from: [0, 0, "-2*q"], to: [0, 0, 0]}}
  - {link: beam, force: [0, 0, "-q"], moment: [0, "q/10", 0], position: a}
load_cases:
  heavy: {loads: [{at: E, wrench: [0, 0, "-q", 0, 0, 0]}], gravity: [0, 0, "-2*g"]}
  along: [{link: beam, force: [0, "q", 0], position: "1 - a"}]
end_effectors: {tip: {at: E}}
)";
  const ModelFamily family = parse_model_family(text, "p.yaml");
  const Structure structure = family.structure();
  auto write = family.make_writer(structure);
  const Model m = written(structure, write, {100, 10, 2700, 0.002, 0.25});
  EXPECT_EQ(std::get<BeamLink>(m.links[0].kind).material.density, 2700.0);
  EXPECT_EQ((*m.supports[0].displacement)(2), -0.002);
  EXPECT_EQ(*m.gravity, Vec3(0, 0, -10));
  const auto& uniform = std::get<DistributedLinkLoad>(m.link_loads[0].load);
  EXPECT_EQ(uniform.from, Vec3(0, 0, -100));
  EXPECT_EQ(uniform.to, Vec3(0, 0, -100));
  EXPECT_EQ(std::get<DistributedLinkLoad>(m.link_loads[1].load).from, Vec3(0, 0, -200));
  const auto& point = std::get<PointLinkLoad>(m.link_loads[2].load);
  EXPECT_EQ(point.force, Vec3(0, 0, -100));
  EXPECT_EQ(point.moment, Vec3(0, 10, 0));
  EXPECT_EQ(point.position, 0.25);
  EXPECT_EQ(m.load_cases[0].loads[0].wrench(2), -100.0);
  EXPECT_EQ(*m.load_cases[0].gravity, Vec3(0, 0, -20));
  EXPECT_EQ(std::get<PointLinkLoad>(m.load_cases[1].link_loads[0].load).force, Vec3(0, 100, 0));
  EXPECT_EQ(std::get<PointLinkLoad>(m.load_cases[1].link_loads[0].load).position, 0.75);
  EXPECT_TRUE(structure.find_slot("link_loads[2].position").has_value());
  EXPECT_TRUE(structure.find_slot("load_cases.along.link_loads[0].position").has_value());
}

// The loaded mode's load steps are a count, not a value of the model: a plain integer only.
TEST(ParametricFile, LoadStepsAreAPlainCount) {
  EXPECT_EQ(parse_model(with("supports:", "analysis: {mode: loaded, load_steps: 12}\nsupports:"),
                        "p.yaml")
                .options.load_steps,
            12);
  const std::string error =
      first_error(with("supports:", "analysis: {load_steps: \"2 * F\"}\nsupports:"));
  EXPECT_TRUE(contains(error,
                       "analysis.load_steps: load_steps is a whole number of load steps "
                       "(a positive integer, not an expression)"))
      << error;
}

TEST(ParametricFile, DefaultsGiveTheModel) {
  const Model m = parse_model(kCantilever, "p.yaml");
  EXPECT_EQ(m.points[1].position, Vec3(0.25, 0, 0));
  EXPECT_EQ(m.points[2].position, Vec3(0.5, 0, 0));
  EXPECT_EQ(m.loads[0].wrench(1), -100.0);
  EXPECT_EQ(std::get<BeamLink>(m.links[0].kind).section.D, 0.02);
}

TEST(ParametricFile, FamilyListsParametersWithUnitsAndLocations) {
  const ModelFamily family = parse_model_family(kCantilever, "p.yaml");
  ASSERT_EQ(family.parameters().size(), 3u);  // derived values are not parameters
  EXPECT_EQ(family.parameters()[0].name, "L");
  EXPECT_EQ(family.parameters()[0].unit, "m");
  EXPECT_EQ(family.parameters()[0].location.line, 4);
  EXPECT_EQ(family.parameters()[1].name, "D");
  EXPECT_EQ(family.parameters()[1].unit, "");
  EXPECT_EQ(family.default_values(), (std::vector<double>{0.5, 0.02, 100}));
  EXPECT_EQ(family.find_parameter("F"), 2u);
  EXPECT_FALSE(family.find_parameter("half").has_value());
  EXPECT_EQ(family.name(), "parametric-cantilever");
}

// The throwing lookup that sweeps and the Python binding use: its NameError names the family,
// the file it was read from (none for a family of a function), and the nearest parameter.
TEST(ParametricFile, ParameterIndexNamesTheFamilyAndItsFile) {
  const ModelFamily family = parse_model_family(kCantilever, "p.yaml");
  EXPECT_EQ(family.parameter_index("F"), 2u);
  const auto misspelt = thrown<NameError>([&] { family.parameter_index("LL"); });
  ASSERT_TRUE(misspelt) << "found a parameter 'LL'";
  EXPECT_EQ(std::string(misspelt->what()),
            "the model 'parametric-cantilever' (p.yaml) has no parameter 'LL'; did you mean 'L'?");
  EXPECT_EQ(misspelt->kind(), "parameter");
  EXPECT_EQ(misspelt->name(), "LL");
  EXPECT_EQ(misspelt->suggestion(), "L");
  const ModelFamily of_function(
      "arm", {{"reach", 1, "m", {}}},
      ModelFamily::MemberFunction([](std::span<const double>) { return Model{}; }));
  const auto unknown = thrown<NameError>([&] { of_function.parameter_index("height"); });
  ASSERT_TRUE(unknown) << "found a parameter 'height'";
  EXPECT_EQ(std::string(unknown->what()),
            "the model 'arm' has no parameter 'height'; its parameters are: reach");
  EXPECT_EQ(unknown->suggestion(), std::nullopt);
}

TEST(ParametricFile, MembersFollowTheirValuesAndSolveToTheClosedForm) {
  const ModelFamily family = parse_model_family(kCantilever, "p.yaml");
  const Structure structure = family.structure();
  auto write = family.make_writer(structure);
  for (double length : {0.3, 0.8, 1.7}) {
    const std::vector<double> values{length, 0.03, 250};
    const Model m = written(structure, write, values);
    EXPECT_EQ(m.points[1].position(0), length / 2);
    EXPECT_EQ(m.points[2].position(0), length);
    EXPECT_EQ(m.loads[0].wrench(1), -250.0);
    const Result r = solve(m);
    const double E = 2.1e11, I = M_PI * std::pow(0.03, 4) / 64;
    const double expected =
        -250 * std::pow(length, 3) / (3 * E * I);  // Euler–Bernoulli tip deflection
    EXPECT_NEAR((*r.end_effectors[0].deflection)(1), expected, 1e-9 * std::abs(expected)) << length;
  }
}

TEST(ParametricFile, WriterLeavesNoNumberOfAnEarlierMember) {
  const ModelFamily family = parse_model_family(kCantilever, "p.yaml");
  const Structure structure = family.structure();
  auto write = family.make_writer(structure);
  const Model first = written(structure, write, {0.4, 0.02, 100});
  written(structure, write, {2.0, 0.05, 7});
  const Model again = written(structure, write, {0.4, 0.02, 100});
  EXPECT_EQ(first.points[2].position, again.points[2].position);
  EXPECT_EQ(first.loads[0].wrench, again.loads[0].wrench);
}

TEST(ParametricFile, SettingsReplaceTheDefaultsTheFamilyIsCheckedAt) {
  const std::string invalid_defaults = with("  D: 0.02", "  D: -0.02");
  EXPECT_THROW(parse_model_family(invalid_defaults, "p.yaml"), InputError);
  const ModelFamily family =
      parse_model_family(invalid_defaults, "p.yaml", {}, {{"D", 0.03}, {"F", 7}});
  EXPECT_EQ(family.default_values(), (std::vector<double>{0.5, 0.03, 7}));
  EXPECT_EQ(family.build(family.default_values()).loads[0].wrench(1), -7.0);
  const auto negative_root = thrown<InputError>([&] {
    parse_model_family(with("half: \"L / 2\"", "half: \"sqrt(L - 0.1)\""), "p.yaml", {},
                       {{"L", 0.05}});
  });
  ASSERT_TRUE(negative_root) << "accepted a negative square root";
  // the values checked, not the file's
  EXPECT_TRUE(contains(negative_root->what(), "for L = 0.05")) << negative_root->what();
  const auto misspelt = thrown<UsageError>([&] {
    parse_model_family(kCantilever, "p.yaml", {}, {{"LL", 1}});
  });
  ASSERT_TRUE(misspelt) << "accepted a setting of no parameter";
  EXPECT_EQ(std::string(misspelt->what()),
            "the model 'parametric-cantilever' (p.yaml) has no parameter 'LL'; did you mean 'L'?");
  EXPECT_THROW(load_model_family(std::string(STIFFMSA_SOURCE_DIR) + "/examples/cantilever.yaml", {},
                                 {{"x", 1}}),
               UsageError);
}

TEST(ParametricFile, WithDefaultsChangesWhatUnsweptParametersKeep) {
  const ModelFamily family = parse_model_family(kCantilever, "p.yaml");
  const ModelFamily longer = family.with_defaults(std::vector<double>{1.0, 0.02, 100});
  EXPECT_EQ(longer.default_values()[0], 1.0);
  EXPECT_EQ(longer.build(longer.default_values()).points[2].position(0), 1.0);
  EXPECT_THROW(family.with_defaults(std::vector<double>{1.0}), UsageError);
  EXPECT_THROW(family.build(std::vector<double>{1.0}), UsageError);
}

TEST(ParametricFile, ExpressionsUseMuparserFunctionsAndConstants) {
  const Model m =
      parse_model(with("middle: [half, 0, 0]",
                       "middle: [\"sqrt(L^2 - 0.3^2)\", \"sin(_pi/6)\", \"L > 0.4 ? 1 : 2\"]"),
                  "p.yaml");
  EXPECT_NEAR(m.points[1].position(0), 0.4, 1e-15);
  EXPECT_NEAR(m.points[1].position(1), 0.5, 2e-16);
  EXPECT_EQ(m.points[1].position(2), 1.0);
}

TEST(ParametricFile, PiAndEHaveEveryDigit) {
  const Model m =
      parse_model(with("middle: [half, 0, 0]", "middle: [_pi, _e, \"cos(_pi/3)\"]"), "p.yaml");
  EXPECT_EQ(m.points[1].position(0), M_PI);
  EXPECT_EQ(m.points[1].position(1), M_E);
  EXPECT_NEAR(m.points[1].position(2), 0.5, 2e-16);
}

TEST(ParametricFile, PlainNumbersStayExact) {
  // Read as numbers, not through the expression library's own number parser.
  const Model m = parse_model(with("E: 2.1e11", "E: 2.0000000000000004e11"), "p.yaml");
  EXPECT_EQ(std::get<BeamLink>(m.links[0].kind).material.E, 2.0000000000000004e11);
}

TEST(ParametricFile, UnknownParameterIsNamedWithASuggestion) {
  const std::string e = first_error(with("tip: [L, \"0\", 0]", "tip: [Lx, 0, 0]"));
  EXPECT_TRUE(contains(e, "points.tip[0]")) << e;
  EXPECT_TRUE(contains(e, "unknown parameter 'Lx'")) << e;
  EXPECT_TRUE(contains(e, "did you mean 'L'")) << e;
}

TEST(ParametricFile, SyntaxErrorNamesTheKeyAndTheExpression) {
  const std::string e = first_error(with("\"-F\"", "\"-F +* 2\""));
  EXPECT_TRUE(contains(e, "loads[0].wrench[1]")) << e;
  EXPECT_TRUE(contains(e, "'-F +* 2'")) << e;
}

TEST(ParametricFile, NotANumberNamesTheParameterValues) {
  const std::string e = first_error(with("half: \"L / 2\"", "half: \"sqrt(D - L)\""));
  EXPECT_TRUE(contains(e, "derived.half")) << e;
  EXPECT_TRUE(contains(e, "gives nan for L = 0.5, D = 0.02")) << e;
}

TEST(ParametricFile, DivisionByZeroIsNotAFiniteNumber) {
  const std::string e = first_error(
      with("section: {shape: circle, D: \"D\"}", "section: {shape: circle, D: \"D / (L - 0.5)\"}"));
  EXPECT_TRUE(contains(e, "links.outer.section.D")) << e;
  EXPECT_TRUE(contains(e, "not a finite number")) << e;
}

TEST(ParametricFile, SeveralValuesInOneNumberAreRefused) {
  const std::string e = first_error(with("\"-F\"", "\"-F, 2\""));
  EXPECT_TRUE(contains(e, "several values")) << e;
}

TEST(ParametricFile, DerivedValuesAreComputedInFileOrder) {
  const std::string e =
      first_error(with("  half: \"L / 2\"", "  half: \"quarter * 2\"\n  quarter: \"L / 4\""));
  EXPECT_TRUE(contains(e, "derived.half")) << e;
  EXPECT_TRUE(contains(e, "'quarter', which is derived later")) << e;
  const std::string self = first_error(with("  half: \"L / 2\"", "  half: \"half + 1\""));
  EXPECT_TRUE(contains(self, "this derived value itself")) << self;
}

TEST(ParametricFile, DerivedNameMayNotRepeatAParameter) {
  const std::string e = first_error(with("  half: \"L / 2\"", "  half: \"L / 2\"\n  D: \"2\""));
  EXPECT_TRUE(contains(e, "'D' is a parameter already")) << e;
}

TEST(ParametricFile, BadParameterNamesAreRefused) {
  EXPECT_TRUE(contains(first_error(with("  F: 100", "  F: 100\n  2x: 1")), "starts with a letter"));
  EXPECT_TRUE(contains(first_error(with("  F: 100", "  F: 100\n  sin: 1")), "it is a function"));
  EXPECT_TRUE(
      contains(first_error(with("  F: 100", "  F: 100\n  _pi: 1")), "starts with a letter"));
}

TEST(ParametricFile, ParameterDefaultsAreNumbers) {
  const std::string e = first_error(with("  F: 100", "  F: \"2*L\""));
  EXPECT_TRUE(contains(e, "parameters.F")) << e;
  EXPECT_TRUE(contains(first_error(with("  F: 100", "  F: {unit: N}")), "missing key 'default'"));
  EXPECT_TRUE(contains(first_error(with("  F: 100", "  F: {default: 1, units: N}")),
                       "did you mean 'unit'"));
}

TEST(ParametricFile, WithoutParametersAnExpressionIsStillAnError) {
  const char* const plain = R"(format: stiffmsa/1
points:
  a: [0, 0, 0]
  b: ["1 + 1", 0, 0]
links:
  l: {type: rigid, from: a, to: b}
supports:
  s: {type: rigid, at: a}
end_effectors:
  e: {at: b}
)";
  const std::string e = first_error(plain);
  EXPECT_TRUE(contains(e, "points.b[0]")) << e;
  EXPECT_TRUE(contains(e, "expected a number")) << e;
  EXPECT_TRUE(contains(e, "needs the file's `parameters:`")) << e;
}

TEST(ParametricFile, FileWithoutParametersIsAFamilyOfOne) {
  const ModelFamily family =
      load_model_family(std::string(STIFFMSA_SOURCE_DIR) + "/examples/cantilever.yaml");
  EXPECT_TRUE(family.parameters().empty());
  const Model m = family.build({});
  EXPECT_EQ(m.name,
            load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/cantilever.yaml").name);
}

TEST(ParametricFile, InvalidMemberThrowsWithTheKey) {
  const ModelFamily family = parse_model_family(kCantilever, "p.yaml");
  // zero-length links
  const auto e = thrown<InputError>([&] { family.build(std::vector<double>{0.0, 0.02, 100}); });
  ASSERT_TRUE(e) << "accepted a zero-length cantilever";
  EXPECT_TRUE(contains(e->diagnostics().front().key_path, "links.")) << e->what();
}

TEST(ParametricFile, MessagesOfAMemberGiveTheLineOfTheKey) {
  const ModelFamily family =
      parse_model_family(with("half: \"L / 2\"", "half: \"sqrt(L - 0.1)\""), "p.yaml");
  const auto e = thrown<InputError>([&] { family.build(std::vector<double>{0.05, 0.02, 100}); });
  ASSERT_TRUE(e) << "accepted the square root of a negative number";
  const Diagnostic& d = e->diagnostics().front();
  EXPECT_EQ(d.key_path, "derived.half");
  EXPECT_EQ(d.location.file, "p.yaml");
  EXPECT_EQ(d.location.line, 8);  // where `half:` is, not the top of the file
  EXPECT_EQ(d.location.column, 9);
  EXPECT_TRUE(contains(d.message, "for L = 0.05")) << d.message;
}

TEST(ParametricFile, AssignmentIsNotAnExpression) {
  // muparser would assign x here, changing it for every expression after this one.
  const std::string e = first_error(with("\"-F\"", "\"F = 3\""));
  EXPECT_TRUE(contains(e, "loads[0].wrench[1]")) << e;
  EXPECT_TRUE(contains(e, "assigns a value")) << e;
  const Model m = parse_model(with("\"-F\"", "\"F == 100 ? -1 : 1\""), "p.yaml");
  EXPECT_EQ(m.loads[0].wrench(1), -1.0);
  EXPECT_EQ(parse_model(with("\"-F\"", "\"F >= 100\""), "p.yaml").loads[0].wrench(1), 1.0);
}

TEST(ParametricFile, ParameterDefaultMessageSaysWhereComputedValuesGo) {
  const std::string e = first_error(with("  F: 100", "  F: \"2*L\""));
  EXPECT_TRUE(contains(e, "plain finite number")) << e;
  EXPECT_TRUE(contains(e, "`derived:`")) << e;
}

TEST(Expressions, ManyDistinctExpressionsStayCorrectBeyondTheKeptParsers) {
  detail::ExpressionEvaluator evaluator({"x"}, {});
  const int count = 20'100;  // more than the evaluator keeps compiled
  for (double x : {1.0, 2.5}) {
    evaluator.set_values(std::vector<double>{x});
    for (int i = 0; i < count; i += (i < 19'990 ? 97 : 1)) {
      const auto outcome = evaluator.evaluate("x * 2 + " + std::to_string(i));
      ASSERT_TRUE(outcome.error.empty()) << outcome.error;
      EXPECT_EQ(outcome.value, x * 2 + i) << i;
    }
  }
  for (int i = 0; i < count; ++i) evaluator.evaluate("x + " + std::to_string(i));
  EXPECT_EQ(evaluator.evaluate("x + 20099").value, 2.5 + 20099);
  EXPECT_EQ(evaluator.evaluate("x + 5").value, 7.5);
  EXPECT_FALSE(evaluator.evaluate("x +* 5").error.empty());
}

// The file with its parameters' defaults replaced by `values`: read by the loader from scratch,
// it is the member a builder must make without reading the file again.
std::string with_defaults(const std::string& text, const ModelFamily& family,
                          const std::vector<double>& values) {
  std::istringstream in(text);
  std::string out, line;
  bool in_parameters = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != ' ' && line[0] != '#')
      in_parameters = line.starts_with("parameters:");
    for (std::size_t k = 0; in_parameters && k < values.size(); ++k) {
      const std::string key = "  " + family.parameters()[k].name + ":";
      if (line.starts_with(key)) {
        std::ostringstream value;
        value.precision(17);
        value << values[k];
        line = key + " " + value.str();
      }
    }
    out += line + "\n";
  }
  return out;
}

std::vector<double> numbers_of(Model model) {
  std::vector<double> numbers;
  detail::for_each_number(model, [&](double& v) { numbers.push_back(v); });
  return numbers;
}

TEST(ParametricFile, MembersEqualTheFileReadAtTheirValues) {
  std::mt19937 random(20261121);
  std::uniform_real_distribution<double> nudge(-0.05, 0.05);
  const auto read_text = [](const std::string& file) {
    std::ifstream in(std::string(STIFFMSA_SOURCE_DIR) + "/examples/" + file);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  };
  // The last holds a number of about 1e301, where a search for marker values in the model
  // (the binding before expressions were bound as the file is read) could not tell.
  for (const std::string& text :
       {std::string(kCantilever), read_text("planar-3rpr-parametric.yaml"),
        read_text("tripteron-parametric.yaml"), with("E: 2.1e11", "E: 2.1e301")}) {
    const ModelFamily family = parse_model_family(text, "p.yaml");
    const Structure structure = family.structure();
    auto write = family.make_writer(structure);
    for (int pose = 0; pose < 5; ++pose) {
      std::vector<double> values = family.default_values();
      for (double& v : values) v *= 1 + nudge(random);
      const Model member = written(structure, write, values);
      const Model read = parse_model(with_defaults(text, family, values), "p.yaml");
      EXPECT_EQ(numbers_of(member), numbers_of(read)) << family.name() << " pose " << pose;
      ASSERT_EQ(member.points.size(), read.points.size());
      for (std::size_t i = 0; i < member.points.size(); ++i)
        EXPECT_EQ(member.points[i].name, read.points[i].name);
      EXPECT_EQ(numbers_of(member).size(),
                numbers_of(family.build(family.default_values())).size());
    }
  }
}

// A file with an expression wherever the reader puts a number in other places than its key:
// a named material and section for several beams, springs as a scalar, a diagonal and a
// matrix, a scalar preload, uniform loads along links, loads in the lists of cases.
const char* const kEveryForm = R"yaml(format: stiffmsa/1
name: every-form
parameters: {a: 0.5, k: 2000, E: 2.1e11, q: 300, f: 20}
derived: {b: "a / 2"}
materials: {steel: {E: E, nu: "0.3", density: "7850 + a"}}
sections: {bar: {shape: tube, D: "0.02 + a / 100", t: "0.002"}}
points:
  O: [0, 0, 0]
  A: [a, 0, 0]
  B: [a, b, 0]
  C: [a, b, "a"]
  D: [a, b, "a + 0.3"]
  E: ["a + 0.2", b, "a + 0.3"]
links:
  OA: {type: beam, from: O, to: A, material: steel, section: bar}
  AB: {type: beam, from: A, to: B, material: steel, section: bar, zref: [0, 0, "1 + a"]}
  BC: {type: beam, from: B, to: C, material: {E: "E / 3", G: "E / 8"}, section: bar}
  CD: {type: compliance, from: C, to: D, frame: local, zref: [1, 0, "a"],
       C: [["1e-6 * (1 + a)", 0, 0, 0, 0, 0], [0, 1e-6, 0, 0, 0, 0], [0, 0, 1e-6, 0, 0, 0],
           [0, 0, 0, 1e-4, 0, 0], [0, 0, 0, 0, 1e-4, 0], [0, 0, 0, 0, 0, "1e-4 * (1 + b)"]]}
  DE: {type: beam, from: D, to: E, material: steel, section: {shape: rect, b: "0.01", h: 0.02}}
joints:
  A1: {type: revolute, at: A, links: [OA, AB], axis: [0, 0, 1], stiffness: "k",
       preload: "f"}
  B1: {type: universal, at: B, links: [AB, BC], axes: [[1, 0, 0], [0, 1, "a / 10"]],
       stiffness: ["k", "2 * k"], preload: [0, "f / 2"]}
  C1: {type: custom, at: C, links: [BC, CD], free: [[0, 0, 0, 0, 0, 1]], stiffness: [["k"]]}
  D1: {type: cylindrical, at: D, links: [CD, DE], axis: [0, 1, 0],
       stiffness: [["k", "k / 10"], ["k / 10", "3 * k"]]}
supports:
  S: {type: planar, at: O, link: OA, normal: [0, 0, "1"], stiffness: "10 * k",
      displacement: [0, 0, "-a / 1000", 0, 0, 0]}
gravity: [0, 0, "-9.81 * (1 + a)"]
loads:
  - {at: E, wrench: ["f", 0, "-q", 0, 0, "f / 10"]}
  - {link: OA, distributed: [0, "q / 10", "-q"]}
  - {link: AB, distributed: {from: [0, 0, "-2 * q"], to: ["b", 0, 0]}}
  - {link: BC, force: [0, 0, "-f"], moment: ["f", 0, 0], position: "b"}
load_cases:
  listed: [{at: E, wrench: [0, "q", 0, 0, 0, 0]}, {link: DE, distributed: ["f", 0, 0]}]
  mapped: {loads: [{link: OA, force: ["q", 0, 0], position: a}], gravity: ["a", 0, -9.81]}
end_effectors: {tip: {at: E}}
)yaml";

TEST(ParametricFile, EveryExpressionIsBoundToTheSlotsItFillsAsTheFileIsRead) {
  const auto bindings = detail::expression_bindings(kEveryForm, "p.yaml");
  ASSERT_TRUE(bindings.has_value());
  const auto bound = [&](const std::string& slot) -> std::string {
    for (const auto& b : *bindings)
      if (b.slot == slot) return b.expression + " @ " + b.key;
    return "(none)";
  };
  EXPECT_EQ(bound("links.OA.material.E"), "E @ materials.steel.E");
  EXPECT_EQ(bound("links.DE.material.density"), "7850 + a @ materials.steel.density");
  EXPECT_EQ(bound("links.AB.section.D"), "0.02 + a / 100 @ sections.bar.D");
  EXPECT_EQ(bound("links.BC.material.G"), "E / 8 @ links.BC.material.G");
  EXPECT_EQ(bound("links.CD.C[5][5]"), "1e-4 * (1 + b) @ links.CD.C[5][5]");
  EXPECT_EQ(bound("joints.A1.stiffness[0][0]"), "k @ joints.A1.stiffness");
  EXPECT_EQ(bound("joints.A1.preload[0]"), "f @ joints.A1.preload");
  EXPECT_EQ(bound("joints.B1.stiffness[1][1]"), "2 * k @ joints.B1.stiffness[1]");
  EXPECT_EQ(bound("joints.B1.stiffness[0][1]"), "(none)");
  EXPECT_EQ(bound("joints.B1.axes[1][2]"), "a / 10 @ joints.B1.axes[1][2]");
  EXPECT_EQ(bound("joints.D1.stiffness[1][0]"), "k / 10 @ joints.D1.stiffness[1][0]");
  EXPECT_EQ(bound("supports.S.stiffness[2][2]"), "10 * k @ supports.S.stiffness");
  EXPECT_EQ(bound("link_loads[0].distributed.to[1]"), "q / 10 @ loads[1].distributed[1]");
  EXPECT_EQ(bound("link_loads[1].distributed.to[0]"), "b @ loads[2].distributed.to[0]");
  EXPECT_EQ(bound("link_loads[2].position"), "b @ loads[3].position");
  EXPECT_EQ(bound("load_cases.listed.link_loads[0].distributed.from[0]"),
            "f @ load_cases.listed[1].distributed[0]");
  EXPECT_EQ(bound("load_cases.mapped.link_loads[0].force[0]"),
            "q @ load_cases.mapped.loads[0].force[0]");
  // Each member's numbers are those of the file read with its parameter values as defaults.
  const ModelFamily family = parse_model_family(kEveryForm, "p.yaml");
  const Structure structure = family.structure();
  auto write = family.make_writer(structure);
  for (const std::vector<double>& values : {std::vector<double>{0.7, 3500, 7e10, 120, 45},
                                            std::vector<double>{0.3, 900, 2e11, 500, -5}}) {
    std::string text = kEveryForm;
    const std::string defaults = "{a: 0.5, k: 2000, E: 2.1e11, q: 300, f: 20}";
    std::ostringstream given;
    given.precision(17);
    given << "{a: " << values[0] << ", k: " << values[1] << ", E: " << values[2]
          << ", q: " << values[3] << ", f: " << values[4] << "}";
    text.replace(text.find(defaults), defaults.size(), given.str());
    EXPECT_EQ(numbers_of(written(structure, write, values)),
              numbers_of(parse_model(text, "p.yaml")));
  }
}

// A robot block's springs and flexible links bind as the file is read too: a default joint's
// stiffness to each joint it springs, a flexible link's material and section to both beams of
// the link split at its centre of mass. Every parametric example binds so.
TEST(ParametricFile, RobotSpringsAndFlexibleLinksAndEveryExampleBindAsTheFileIsRead) {
  const std::string examples = std::string(STIFFMSA_SOURCE_DIR) + "/examples/";
  const std::string defaults = "{k: 2.0e6, E: 7e10, q2: 0.3}";
  const std::string text = "format: stiffmsa/1\nparameters: " + defaults +
                           "\nrobot:\n  urdf: " + examples + "robots/six-axis.urdf\n" + R"(
  positions: {joint_2: q2, joint_3: 0.4, joint_5: 0.9}
  default_joint: {stiffness: "k / 4"}
  joints: {joint_1: {stiffness: k}, joint_2: {stiffness: "1.5 * k"}}
  links: {link_3: {material: {E: E, nu: 0.33}, section: {shape: rect, b: 0.05, h: "E / 1e12"}}}
  gravity: [0, 0, -9.81]
end_effectors:
  tcp: {frame: tool0, offset: [0, 0, 0.15]}
)";
  const auto bindings = detail::expression_bindings(text, "robot.yaml");
  ASSERT_TRUE(bindings.has_value());
  std::vector<std::string> listed;
  for (const auto& b : *bindings) listed.push_back(b.slot + " <- " + b.expression);
  EXPECT_EQ(
      listed,
      (std::vector<std::string>{
          "links.link_3.material.E <- E", "links.link_3.section.h <- E / 1e12",
          "links.link_3.distal.material.E <- E", "links.link_3.distal.section.h <- E / 1e12",
          "joints.joint_1.stiffness[0][0] <- k", "joints.joint_2.stiffness[0][0] <- 1.5 * k",
          "joints.joint_3.stiffness[0][0] <- k / 4", "joints.joint_4.stiffness[0][0] <- k / 4",
          "joints.joint_5.stiffness[0][0] <- k / 4", "joints.joint_6.stiffness[0][0] <- k / 4"}));
  const ModelFamily family = parse_model_family(text, "robot.yaml");
  const Structure structure = family.structure();
  auto write = family.make_writer(structure);
  const std::vector<double> values{3.1e6, 2e11, -0.4};
  std::string at_values = text;
  at_values.replace(at_values.find(defaults), defaults.size(), "{k: 3.1e6, E: 2e11, q2: -0.4}");
  EXPECT_EQ(numbers_of(written(structure, write, values)),
            numbers_of(parse_model(at_values, "robot.yaml")));

  // A compliance is held inverted: the family with an expression in one is read per member,
  // with the same numbers as the file read at the member's values.
  const std::string compliant_text = [&] {
    std::string changed = text;
    const std::string from = R"(default_joint: {stiffness: "k / 4"})";
    changed.replace(changed.find(from), from.size(),
                    "default_joint: {compliance: [[\"1e-7 * 2e6 / k\", 0, 0, 0, 0, 0], "
                    "[0, 1e-7, 0, 0, 0, 0], [0, 0, 1e-7, 0, 0, 0], [0, 0, 0, 1e-6, 0, 0], "
                    "[0, 0, 0, 0, 1e-6, 0], [0, 0, 0, 0, 0, 1e-6]]}");
    return changed;
  }();
  EXPECT_FALSE(detail::expression_bindings(compliant_text, "robot.yaml").has_value());
  const ModelFamily compliant = parse_model_family(compliant_text, "robot.yaml");
  const Structure compliant_structure = compliant.structure();
  auto write_compliant = compliant.make_writer(compliant_structure);
  std::string compliant_at_values = compliant_text;
  compliant_at_values.replace(compliant_at_values.find(defaults), defaults.size(),
                              "{k: 3.1e6, E: 2e11, q2: -0.4}");
  EXPECT_EQ(numbers_of(written(compliant_structure, write_compliant, values)),
            numbers_of(parse_model(compliant_at_values, "robot.yaml")));

  for (const char* file :
       {"planar-3rpr-parametric.yaml", "tripteron-parametric.yaml", "delta-parametric.yaml",
        "delta-us-parametric.yaml", "robots/six-axis.yaml"}) {
    std::ifstream in(examples + file);
    std::ostringstream example;
    example << in.rdbuf();
    EXPECT_TRUE(detail::expression_bindings(example.str(), examples + file).has_value()) << file;
  }
}

// A writer writes every slot of a member: a member written after another, or after a failed
// one, is the member built on its own, with the structure's names and source locations.
TEST(ParametricFile, AWriterWritesEveryValueOfAMember) {
  const ModelFamily family = parse_model_family(kCantilever, "p.yaml");
  const std::vector<double> long_one{1.5, 0.04, 30}, short_one{0.3, 0.01, 900};
  const Model expected_long = family.build(long_one), expected_short = family.build(short_one);
  const auto expect_member = [](const Model& member, const Model& expected) {
    EXPECT_EQ(numbers_of(member), numbers_of(expected));
    ASSERT_EQ(member.links.size(), expected.links.size());
    for (std::size_t i = 0; i < member.links.size(); ++i) {
      EXPECT_EQ(member.links[i].name, expected.links[i].name);
      EXPECT_EQ(member.links[i].from, expected.links[i].from);
      EXPECT_EQ(member.links[i].origin.of("section").line,
                expected.links[i].origin.of("section").line);
    }
    EXPECT_EQ(member.loads.size(), expected.loads.size());
  };
  const Structure structure = family.structure();
  auto write = family.make_writer(structure);
  expect_member(written(structure, write, long_one), expected_long);
  expect_member(written(structure, write, short_one), expected_short);
  // Zero-length links: the values are written, and their checks refuse them.
  const std::vector<double> zero{0.0, 0.02, 100};
  EXPECT_FALSE(
      structure.find_value_defects(structure.values_of(written(structure, write, zero))).empty());
  EXPECT_THROW(family.build(zero), InputError);
  expect_member(written(structure, write, long_one), expected_long);
}

TEST(ParametricFile, ExpressionFailureOfAMemberNamesItsKey) {
  const ModelFamily family = parse_model_family(kCantilever, "p.yaml");
  const auto negative = thrown<InputError>([&] {
    family.build(std::vector<double>{0.5, -0.02, 100});
  });
  ASSERT_TRUE(negative) << "accepted a negative diameter";
  EXPECT_TRUE(contains(negative->diagnostics().front().key_path, "section.D")) << negative->what();
  const ModelFamily divided =
      parse_model_family(with("tip: [L, \"0\", 0]", "tip: [L, \"1 / (F - 50)\", 0]"), "p.yaml");
  const auto by_zero = thrown<InputError>([&] {
    divided.build(std::vector<double>{0.5, 0.02, 50});
  });
  ASSERT_TRUE(by_zero) << "accepted a division by zero";
  const Diagnostic& d = by_zero->diagnostics().front();
  EXPECT_EQ(d.key_path, "points.tip[1]");
  EXPECT_EQ(d.location.line, 14);
  EXPECT_TRUE(contains(d.message, "gives inf for F = 50")) << d.message;
}

TEST(ParametricExamples, DefaultsReproduceTheFixedExamples) {
  // The parametric 3-RPR at its defaults is the fixed example up to the 4-digit rounding of
  // that file's coordinates.
  const std::string dir = std::string(STIFFMSA_SOURCE_DIR) + "/examples/";
  const Result fixed = solve(load_model(dir + "planar-3rpr.yaml"));
  const Result parametric = solve(load_model(dir + "planar-3rpr-parametric.yaml"));
  const Mat6 a = *fixed.end_effectors[0].compliance, b = *parametric.end_effectors[0].compliance;
  EXPECT_LT((a - b).norm(), 1e-2 * a.norm());
}

}  // namespace
}  // namespace stiffmsa

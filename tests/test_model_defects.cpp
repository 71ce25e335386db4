// Defective models, from files and from the API: every defect is reported, each with its key
// path, its place in the file and a message saying what is wrong and what would be valid.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "model/link_ends.hpp"
#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/structure.hpp"
#include "stiffmsa/validate.hpp"

namespace stiffmsa {
namespace {

std::vector<Diagnostic> defects_of(const std::string& text, const std::string& file = "bad.yaml") {
  try {
    parse_model(text, file);
  } catch (const InputError& e) {
    return e.diagnostics();
  }
  ADD_FAILURE() << "the model was accepted:\n" << text;
  return {};
}

std::string listing(const std::vector<Diagnostic>& defects) {
  std::string text;
  for (const auto& d : defects) text += "  " + d.to_string() + "\n";
  return text;
}

// There is a defect at `path` whose message holds every one of `words`, at line:column when
// those are given (0: not checked).
::testing::AssertionResult has_defect(const std::vector<Diagnostic>& defects,
                                      const std::string& path,
                                      const std::vector<std::string>& words, int line = 0,
                                      int column = 0) {
  for (const auto& d : defects) {
    if (d.key_path != path) continue;
    bool all_words = true;
    for (const auto& w : words) all_words = all_words && d.message.find(w) != std::string::npos;
    if (!all_words) continue;
    if (line && (d.location.line != line || d.location.column != column))
      return ::testing::AssertionFailure()
             << path << " is reported at " << d.location.line << ":" << d.location.column
             << ", expected " << line << ":" << column << "\n"
             << listing(defects);
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "no defect at " << path << " with the words given in:\n"
                                       << listing(defects);
}

std::size_t count_at(const std::vector<Diagnostic>& defects, const std::string& path) {
  std::size_t n = 0;
  for (const auto& d : defects) n += d.key_path == path;
  return n;
}

// ---- keys --------------------------------------------------------------------------------

TEST(ModelDefects, UnknownKeyIsRejectedWithTheNearestValidKey) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B}
joints:
  J3: {type: revolute, at: A, links: [L1, L2], axis: [0, 0, 1], stifness: 100}
)");
  ASSERT_EQ(defects.size(), 1u) << listing(defects);
  EXPECT_TRUE(has_defect(defects, "joints.J3.stifness",
                         {"unknown key 'stifness'", "did you mean 'stiffness'?"}, 7, 65));
  EXPECT_EQ(defects[0].to_string(),
            "bad.yaml:7:65: joints.J3.stifness: unknown key 'stifness'; did you mean 'stiffness'?");
}

TEST(ModelDefects, UnknownKeyFarFromAnyListsTheValidKeys) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0]}
links: {L: {type: rigid, from: O, to: A}}
end_effectors: {tool: {at: A, colour: red}}
)");
  EXPECT_TRUE(has_defect(defects, "end_effectors.tool.colour",
                         {"unknown key 'colour'", "valid keys are: at, link"}, 4, 31));
}

TEST(ModelDefects, MisspelledTopLevelKeyIsRejected) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0]}
links: {L: {type: rigid, from: O, to: A}}
joint: {}
)");
  EXPECT_TRUE(
      has_defect(defects, "joint", {"unknown key 'joint'", "did you mean 'joints'?"}, 4, 1));
}

TEST(ModelDefects, KeyOfAnotherTypeIsRejected) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B, K: [[1]]}
joints:
  J1: {type: spherical, at: A, links: [L1, L2], axis: [0, 0, 1]}
supports:
  S: {type: rigid, at: O, stiffness: 5}
)");
  EXPECT_TRUE(has_defect(defects, "joints.J1.axis",
                         {"'axis' does not apply to a spherical joint",
                          "valid keys are: type, at, links, stiffness, preload, actuated"},
                         7, 49));
  EXPECT_TRUE(has_defect(defects, "links.L2.K", {"'K' does not apply to a rigid link"}, 5, 37));
  EXPECT_TRUE(has_defect(defects, "supports.S.stiffness",
                         {"'stiffness' does not apply to a rigid support"}, 9, 27));
  EXPECT_EQ(defects.size(), 3u) << listing(defects);
}

TEST(ModelDefects, KeyOfAnotherShapeIsRejected) {
  const auto defects = defects_of(R"(format: stiffmsa/1
sections:
  s: {shape: circle, D: 0.02, t: 0.001}
  q: {shape: sqare, b: 0.01}
)");
  EXPECT_TRUE(has_defect(
      defects, "sections.s.t",
      {"'t' does not apply to a circle section", "valid keys are: shape, D, Asy, Asz"}, 3, 31));
  EXPECT_TRUE(has_defect(defects, "sections.q.shape",
                         {"unknown section shape 'sqare'", "valid values are: circle, tube, rect"},
                         4, 14));
}

TEST(ModelDefects, TypesNamesAndRequiredKeysAreChecked) {
  const auto defects = defects_of(R"(format: stiffmsa/1
materials: {steel: {E: 2.0e11, nu: 0.3}}
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0]}
links:
  L1: {type: bem, from: O, to: A}
  L2: {from: A, to: B}
  L3: {type: beam, from: O, to: B, material: stel, section: {shape: circle, D: 0.01}}
  L4: {type: compliance, from: O, to: B, zref: [0, 0, 1],
       C: [[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 1]]}
joints:
  J1: {type: hinge, at: A, links: [L1, L2]}
  J2: {type: rigid, at: O, link: L1}
)");
  EXPECT_TRUE(has_defect(defects, "links.L1.type",
                         {"unknown link type 'bem'", "did you mean 'beam'?"}, 5, 14));
  EXPECT_TRUE(has_defect(defects, "links.L2.type", {"missing key 'type'"}, 6, 7));
  EXPECT_TRUE(has_defect(defects, "links.L3.material",
                         {"no material named 'stel' under materials", "did you mean 'steel'?"}, 7,
                         46));
  EXPECT_TRUE(has_defect(defects, "links.L4.zref", {"zref applies only with frame: local"}, 8, 42));
  EXPECT_TRUE(has_defect(defects, "joints.J1.type",
                         {"unknown joint type 'hinge'",
                          "valid values are: rigid, revolute, prismatic, cylindrical, universal, "
                          "spherical, planar, custom"},
                         11, 14));
  EXPECT_TRUE(has_defect(defects, "joints.J2.link", {"unknown key 'link'", "did you mean 'links'?"},
                         12, 28));
  EXPECT_TRUE(has_defect(defects, "joints.J2.links", {"missing key 'links'"}, 12, 7));
  // What stands in for the unreadable parts raises nothing more.
  EXPECT_EQ(defects.size(), 7u) << listing(defects);
}

TEST(ModelDefects, DuplicateKeysAreRejected) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points:
  O: [0, 0, 0]
  A: [1, 0, 0]
  A: [2, 0, 0]
links:
  L: {type: rigid, from: O, to: A, from: A}
)");
  EXPECT_TRUE(
      has_defect(defects, "points.A", {"duplicate key 'A'", "first given at line 4"}, 5, 3));
  EXPECT_TRUE(has_defect(defects, "links.L.from", {"duplicate key 'from'", "line 7"}, 7, 36));
  EXPECT_EQ(defects.size(), 2u) << listing(defects);
}

TEST(ModelDefects, FormatMustBeStiffmsa1) {
  const char* body = R"(points: {O: [0, 0, 0], A: [1, 0, 0]}
links: {L: {type: rigid, from: O, to: A}}
)";
  const auto missing = defects_of(body);
  EXPECT_TRUE(has_defect(missing, "format", {"missing key 'format'", "format: stiffmsa/1"}));
  const auto wrong = defects_of(std::string("format: stiffmsa/2\n") + body);
  EXPECT_TRUE(
      has_defect(wrong, "format", {"unsupported format 'stiffmsa/2'", "format: stiffmsa/1"}, 1, 9));
}

TEST(ModelDefects, YamlSyntaxErrorIsOneDiagnosticAtTheParsersPosition) {
  const auto defects = defects_of("format: stiffmsa/1\npoints: {O: [0, 0, 0]\nlinks: {}\n");
  ASSERT_EQ(defects.size(), 1u) << listing(defects);
  EXPECT_EQ(defects[0].location.file, "bad.yaml");
  EXPECT_EQ(defects[0].location.line, 3);
  EXPECT_EQ(defects[0].location.column, 1);
  EXPECT_NE(defects[0].message.find("YAML syntax error"), std::string::npos);
}

TEST(ModelDefects, EmptyFileIsRejected) {
  const auto defects = defects_of("");
  ASSERT_EQ(defects.size(), 1u) << listing(defects);
  EXPECT_NE(defects[0].message.find("the file is empty"), std::string::npos);
}

// ---- numbers, vectors, matrices, booleans ------------------------------------------------

TEST(ModelDefects, NumbersMustBeFiniteNumbers) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points:
  O: [0, 0, .nan]
  A: [1, .inf, 0]
  B: [2, "1.0", 0]
  C: [3, one, 0]
  D: [1, 2]
  E: [4, +-1, 0]
links: {L: {type: rigid, from: O, to: A}}
loads:
  - {at: A, wrench: [0, 0, nan, 0, 0, 0, 0]}
)");
  EXPECT_TRUE(has_defect(defects, "points.O[2]", {"expected a finite number", "'.nan'"}, 3, 13));
  EXPECT_TRUE(has_defect(defects, "points.A[1]", {"expected a finite number", "'.inf'"}, 4, 10));
  EXPECT_TRUE(
      has_defect(defects, "points.B[1]", {"expected a number", "quoted text '1.0'"}, 5, 10));
  EXPECT_TRUE(has_defect(defects, "points.C[1]", {"expected a number", "'one'"}, 6, 10));
  EXPECT_TRUE(has_defect(defects, "points.D", {"expected 3 numbers [x, y, z], got 2"}, 7, 6));
  EXPECT_TRUE(has_defect(defects, "points.E[1]", {"expected a number", "'+-1'"}, 8, 10));
  EXPECT_TRUE(has_defect(defects, "loads[0].wrench", {"expected 6 numbers", "got 7"}, 11, 21));
  EXPECT_TRUE(has_defect(defects, "loads[0].wrench[2]", {"expected a finite number", "'nan'"}));
  // The unreadable positions are not also reported as non-finite by validation.
  EXPECT_EQ(defects.size(), 8u) << listing(defects);
}

TEST(ModelDefects, MatricesMustHaveTheirSize) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0]}
links:
  C: {type: compliance, from: O, to: A, C: [[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0]]}
  K: {type: matrix, from: A, to: B, K: [[1, 2], [3]]}
)");
  EXPECT_TRUE(has_defect(defects, "links.C.C", {"expected a 6×6 matrix, got 2×6"}, 4, 44));
  EXPECT_TRUE(has_defect(defects, "links.K.K[1]", {"row 1 has 1 values, row 0 has 2"}, 5, 49));
  // The zeros left in place of C are not also reported as not positive definite.
  EXPECT_EQ(defects.size(), 2u) << listing(defects);
}

TEST(ModelDefects, BooleansMustBeTrueOrFalse) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0]}
links:
  L1: {type: beam, from: O, to: A, material: {E: 2.0e11, nu: 0.3}, section: {shape: circle, D: 0.01}, shear: yes}
  L2: {type: rigid, from: A, to: B}
joints:
  J: {type: revolute, at: A, links: [L1, L2], axis: [0, 0, 1], actuated: "true"}
)");
  EXPECT_TRUE(has_defect(defects, "links.L1.shear", {"expected true or false", "'yes'"}, 4, 110));
  EXPECT_TRUE(has_defect(defects, "joints.J.actuated",
                         {"expected true or false", "quoted text 'true'"}, 7, 74));
}

TEST(ModelDefects, StiffnessAndPreloadMustHaveTheJointsSize) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0], C: [3, 0, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B}
  L3: {type: rigid, from: B, to: C}
joints:
  J1: {type: universal, at: A, links: [L1, L2], axes: [[1, 0, 0], [0, 1, 0]], stiffness: [1, 2, 3], preload: 4}
  J2: {type: spherical, at: B, links: [L2, L3], stiffness: [[1, 0], [0, 1]]}
)");
  EXPECT_TRUE(has_defect(defects, "joints.J1.stiffness",
                         {"expected 2 numbers", "p = 2 for a universal joint", "got 3"}, 8, 90));
  EXPECT_TRUE(has_defect(defects, "joints.J1.preload",
                         {"expected a list of 2 numbers", "p = 2 for a universal joint"}, 8, 110));
  EXPECT_TRUE(has_defect(defects, "joints.J2.stiffness",
                         {"p×p stiffness matrix", "p = 3 for a spherical joint", "got 2×2"}));
}

// ---- materials and sections --------------------------------------------------------------

TEST(ModelDefects, MaterialNeedsEAndExactlyOneOfNuOrG) {
  const auto defects = defects_of(R"(format: stiffmsa/1
materials:
  both:    {E: 2.0e11, nu: 0.3, G: 8.0e10}
  neither: {E: 2.0e11}
  no_E:    {nu: 0.3}
  weak:    {E: -1, nu: 0.5}
  soft:    {E: 1.0e9, G: 0}
)");
  EXPECT_TRUE(has_defect(defects, "materials.both", {"exactly one of nu or G", "not both"}, 3, 3));
  EXPECT_TRUE(
      has_defect(defects, "materials.neither", {"exactly one of nu or G", "neither"}, 4, 3));
  EXPECT_TRUE(has_defect(defects, "materials.no_E.E", {"missing key 'E'"}, 5, 12));
  EXPECT_TRUE(
      has_defect(defects, "materials.weak.E", {"E must be a positive number", "got -1"}, 6, 13));
  EXPECT_TRUE(
      has_defect(defects, "materials.weak.nu", {"nu must lie in (-1, 0.5)", "got 0.5"}, 6, 20));
  EXPECT_TRUE(
      has_defect(defects, "materials.soft.G", {"G must be a positive number", "got 0"}, 7, 23));
}

TEST(ModelDefects, NamedMaterialDefectIsReportedOnceAtItsDefinition) {
  const auto defects = defects_of(R"(format: stiffmsa/1
materials:
  steel: {E: 0, nu: 0.3}
sections:
  rod: {shape: circle, D: -0.01}
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0]}
links:
  L1: {type: beam, from: O, to: A, material: steel, section: rod}
  L2: {type: beam, from: A, to: B, material: steel, section: rod}
)");
  EXPECT_TRUE(
      has_defect(defects, "materials.steel.E", {"E must be a positive number", "got 0"}, 3, 11));
  EXPECT_TRUE(
      has_defect(defects, "sections.rod.D", {"D must be a positive number", "got -0.01"}, 5, 24));
  EXPECT_EQ(defects.size(), 2u) << listing(defects);
}

TEST(ModelDefects, SectionDimensionsAndWalls) {
  const auto defects = defects_of(R"(format: stiffmsa/1
materials: {steel: {E: 2.0e11, nu: 0.3}}
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0], C: [3, 0, 0], D: [4, 0, 0]}
links:
  L1: {type: beam, from: O, to: A, material: steel, section: {shape: tube, D: 0.04, t: 0.02}}
  L2: {type: beam, from: A, to: B, material: steel, section: {shape: rect_tube, b: 0.1, h: 0.04, t: 0.025}}
  L3: {type: beam, from: B, to: C, material: steel, section: {shape: rect, b: 0.1}}
  L4: {type: beam, from: C, to: D, material: steel, section: {A: 1.0e-4, Iy: 0, Iz: 1.0e-9, J: 2.0e-9}}
)");
  EXPECT_TRUE(has_defect(defects, "links.L1.section.t",
                         {"wall thickness t = 0.02 must be less than D/2 = 0.02"}, 5, 85));
  EXPECT_TRUE(has_defect(defects, "links.L2.section.t",
                         {"wall thickness t = 0.025 must be less than min(b, h)/2 = 0.02"}, 6, 98));
  EXPECT_TRUE(has_defect(defects, "links.L3.section.h", {"missing key 'h'"}));
  EXPECT_TRUE(
      has_defect(defects, "links.L4.section.Iy", {"Iy must be a positive number", "got 0"}, 8, 74));
  EXPECT_EQ(defects.size(), 4u) << listing(defects);
}

TEST(ModelDefects, ShearNeedsShearAreas) {
  const auto defects = defects_of(R"(format: stiffmsa/1
materials: {steel: {E: 2.0e11, nu: 0.3}}
sections:
  generic: {A: 1.0e-4, Iy: 1.0e-9, Iz: 1.0e-9, J: 2.0e-9}
  half:    {A: 1.0e-4, Iy: 1.0e-9, Iz: 1.0e-9, J: 2.0e-9, Asy: 8.0e-5}
  given:   {A: 1.0e-4, Iy: 1.0e-9, Iz: 1.0e-9, J: 2.0e-9, Asy: 8.0e-5, Asz: 8.0e-5}
  round:   {shape: circle, D: 0.01}
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0], C: [3, 0, 0], D: [4, 0, 0]}
links:
  L1: {type: beam, from: O, to: A, material: steel, section: generic, shear: true}
  L2: {type: beam, from: A, to: B, material: steel, section: half, shear: true}
  L3: {type: beam, from: B, to: C, material: steel, section: given, shear: true}
  L4: {type: beam, from: C, to: D, material: steel, section: round, shear: true}
)");
  EXPECT_TRUE(has_defect(defects, "links.L1.shear", {"needs the shear areas Asy and Asz"}, 10, 71));
  EXPECT_TRUE(has_defect(defects, "links.L2.shear", {"needs the shear areas Asy and Asz"}, 11, 68));
  EXPECT_EQ(defects.size(), 2u) << listing(defects);
}

// ---- geometry ----------------------------------------------------------------------------

TEST(ModelDefects, ZeroLengthIsAnErrorForBeamsMatricesAndLocalCompliances) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], P: [0, 0, 0], A: [1, 0, 0]}
links:
  beam:    {type: beam, from: O, to: P, material: {E: 2.0e11, nu: 0.3}, section: {shape: circle, D: 0.01}}
  matrix:  {type: matrix, from: O, to: P, K: [[0,0,0,0,0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0,0,0,0,0]]}
  local:   {type: compliance, from: O, to: P, frame: local, C: [[1,0,0,0,0,0],[0,1,0,0,0,0],[0,0,1,0,0,0],[0,0,0,1,0,0],[0,0,0,0,1,0],[0,0,0,0,0,1]]}
  bushing: {type: compliance, from: O, to: P, C: [[1,0,0,0,0,0],[0,1,0,0,0,0],[0,0,1,0,0,0],[0,0,0,1,0,0],[0,0,0,0,1,0],[0,0,0,0,0,1]]}
  rigid:   {type: rigid, from: P, to: O}
  arm:     {type: rigid, from: O, to: A}
)");
  EXPECT_TRUE(has_defect(defects, "links.beam", {"zero length", "a beam needs a length"}, 4, 3));
  EXPECT_TRUE(
      has_defect(defects, "links.matrix", {"zero length", "a matrix link needs a length"}, 5, 3));
  EXPECT_TRUE(has_defect(defects, "links.local", {"zero length", "frame: local"}, 6, 3));
  EXPECT_EQ(count_at(defects, "links.bushing"), 0u);
  EXPECT_EQ(count_at(defects, "links.rigid"), 0u);
  EXPECT_EQ(defects.size(), 3u) << listing(defects);
}

TEST(ModelDefects, ZrefMustNotBeZeroOrAlongTheLink) {
  const auto defects = defects_of(R"(format: stiffmsa/1
materials: {steel: {E: 2.0e11, nu: 0.3}}
points: {O: [0, 0, 0], A: [0, 0, 1], B: [1, 0, 1]}
links:
  L1: {type: beam, from: O, to: A, material: steel, section: {shape: circle, D: 0.01}, zref: [0, 0, -2]}
  L2: {type: beam, from: A, to: B, material: steel, section: {shape: circle, D: 0.01}, zref: [0, 0, 0]}
)");
  EXPECT_TRUE(has_defect(defects, "links.L1.zref", {"parallel to the link"}, 5, 88));
  EXPECT_TRUE(has_defect(defects, "links.L2.zref", {"zero vector"}, 6, 88));
}

TEST(ModelDefects, JointAxesMustBeUsable) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0], C: [3, 0, 0], D: [4, 0, 0], E: [5, 0, 0], F: [6, 0, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B}
  L3: {type: rigid, from: B, to: C}
  L4: {type: rigid, from: C, to: D}
  L5: {type: rigid, from: D, to: E}
  L6: {type: rigid, from: E, to: F}
joints:
  J1: {type: revolute, at: A, links: [L1, L2], axis: [0, 0, 0]}
  J2: {type: universal, at: B, links: [L2, L3], axes: [[0, 0, 1], [0, 0, -3]]}
  J3: {type: planar, at: C, links: [L3, L4], normal: [0, 0, 0]}
  J4: {type: custom, at: D, links: [L4, L5], free: [[1, 0, 0, 0, 0, 0], [2, 0, 0, 0, 0, 0]]}
  J5: {type: custom, at: E, links: [L5, L6], free: [[0, 0, 0, 0, 0, 1], [0, 0, 0, 0, 0, 0]]}
)");
  EXPECT_TRUE(has_defect(defects, "joints.J1.axis", {"zero vector"}, 11, 48));
  EXPECT_TRUE(has_defect(defects, "joints.J2.axes", {"must not be parallel"}, 12, 49));
  EXPECT_TRUE(has_defect(defects, "joints.J3.normal", {"zero vector"}, 13, 46));
  EXPECT_TRUE(has_defect(defects, "joints.J4.free", {"linearly dependent"}, 14, 46));
  EXPECT_TRUE(has_defect(defects, "joints.J5.free[1]", {"row 1 of free is zero"}, 15, 73));
  EXPECT_EQ(defects.size(), 5u) << listing(defects);
}

TEST(ModelDefects, JointParametersMustHaveTheirShape) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B}
joints:
  J1: {type: universal, at: A, links: [L1, L2], axes: [[1, 0, 0]], stiffness: 5}
supports:
  S: {type: custom, at: O, free: [[1, 0, 0], [0, 0, 0, 0, 0, 1]], preload: [1, 2]}
)");
  EXPECT_TRUE(has_defect(defects, "joints.J1.axes", {"expected two axes", "got 1"}, 7, 55));
  EXPECT_TRUE(has_defect(defects, "supports.S.free[0]",
                         {"expected 6 numbers [dx, dy, dz, rx, ry, rz], got 3"}, 9, 35));
  // Without their free directions the springs cannot be sized, so nothing is said of them.
  EXPECT_EQ(defects.size(), 2u) << listing(defects);
}

TEST(ModelDefects, CustomJointRowsAreCountedFromOneToSix) {
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("A", Vec3(1, 0, 0));
  m.add_point("B", Vec3(2, 0, 0));
  m.add_rigid_link("L1", "O", "A");
  m.add_rigid_link("L2", "A", "B");
  m.add_joint("none", "A", {"L1", "L2"}, Connection::passive(Kinematics::custom({})));
  std::vector<Vec6> seven(7, Vec6::Unit(0));
  m.add_support("seven", "O", {}, Connection::passive(Kinematics::custom(seven)));
  const auto defects = find_defects(m);
  EXPECT_TRUE(has_defect(defects, "joints.none.free", {"at least one free direction"}));
  EXPECT_TRUE(has_defect(defects, "supports.seven.free", {"at most 6 free directions", "got 7"}));
  EXPECT_EQ(defects.size(), 2u) << listing(defects);
}

// ---- springs and preloads ----------------------------------------------------------------

TEST(ModelDefects, StiffnessMustBeSymmetricPositiveDefinite) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0], C: [3, 0, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B}
  L3: {type: rigid, from: B, to: C}
joints:
  J1: {type: cylindrical, at: A, links: [L1, L2], axis: [1, 0, 0], stiffness: [[4, 1], [2, 3]]}
  J2: {type: cylindrical, at: B, links: [L2, L3], axis: [1, 0, 0], stiffness: [[1, 2], [2, 1]]}
supports:
  S: {type: spherical, at: O, stiffness: [1, 0, 2]}
)");
  EXPECT_TRUE(has_defect(defects, "joints.J1.stiffness",
                         {"must be symmetric", "stiffness[1][0] = 2", "stiffness[0][1] = 1"}, 8,
                         68));
  EXPECT_TRUE(has_defect(defects, "joints.J2.stiffness",
                         {"must be positive definite", "smallest eigenvalue is -1"}, 9, 68));
  EXPECT_TRUE(has_defect(defects, "supports.S.stiffness",
                         {"must be positive definite", "smallest eigenvalue is 0"}, 11, 31));
  EXPECT_EQ(defects.size(), 3u) << listing(defects);
}

TEST(ModelDefects, PreloadOnALockedActuatorIsAnError) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B}
joints:
  J1: {type: revolute, at: A, links: [L1, L2], axis: [0, 0, 1], actuated: true, preload: 5}
supports:
  S: {type: revolute, at: O, axis: [0, 0, 1], actuated: true, stiffness: 1.0e4, preload: 5}
)");
  EXPECT_TRUE(
      has_defect(defects, "joints.J1.preload", {"locked actuator", "has no effect"}, 7, 81));
  EXPECT_EQ(defects.size(), 1u) << listing(defects);
}

TEST(ModelDefects, ApiSpringsMustMatchTheFreeDirections) {
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("A", Vec3(1, 0, 0));
  m.add_point("B", Vec3(2, 0, 0));
  m.add_rigid_link("L1", "O", "A");
  m.add_rigid_link("L2", "A", "B");
  const Connection sized =
      Connection::elastic(Kinematics::spherical(), MatX::Identity(2, 2)).preloaded(VecX::Ones(4));
  m.add_joint("J", "A", {"L1", "L2"}, sized);
  // Past the factories, which take a stiffness for a rigid connection as they are told.
  const Connection rigid = Connection::elastic(Kinematics::rigid(), MatX::Identity(1, 1));
  m.add_support("S", "O", {"L1"}, rigid);
  const auto defects = find_defects(m);
  EXPECT_TRUE(has_defect(defects, "joints.J.stiffness",
                         {"must be p×p", "p = 3 for a spherical joint", "got 2×2"}));
  EXPECT_TRUE(has_defect(defects, "joints.J.preload", {"p values", "got 4"}));
  EXPECT_TRUE(has_defect(defects, "supports.S.stiffness", {"no free directions"}));
  EXPECT_EQ(defects.size(), 3u) << listing(defects);
  // A model built in code has no file to point into.
  EXPECT_EQ(defects[0].location.file, "");
  EXPECT_EQ(defects[0].location.line, 0);
}

// ---- connections -------------------------------------------------------------------------

TEST(ModelDefects, ElasticJointConnectsExactlyTwoLinkEnds) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0], C: [1, 1, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B}
  L3: {type: rigid, from: A, to: C}
joints:
  J: {type: revolute, at: A, links: [L1, L2, L3], axis: [0, 0, 1], stiffness: 100}
)");
  EXPECT_TRUE(has_defect(defects, "joints.J.links",
                         {"elastic or preloaded joint connects exactly two link ends", "got 3"}, 8,
                         30));
  EXPECT_EQ(defects.size(), 1u) << listing(defects);
}

TEST(ModelDefects, JointLinksMustExistAndEndAtTheJoint) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B}
  L3: {type: rigid, from: O, to: B}
joints:
  J1: {type: revolute, at: A, links: [L1], axis: [0, 0, 1]}
  J2: {type: rigid, at: A, links: [L2, L3, Lx]}
  J3: {type: rigid, at: Q, links: [L1, L2]}
)");
  EXPECT_TRUE(has_defect(defects, "joints.J1.links", {"at least two link ends", "got 1"}, 8, 31));
  EXPECT_TRUE(
      has_defect(defects, "joints.J2.links[1]", {"link 'L3' has no end at point 'A'"}, 9, 40));
  EXPECT_TRUE(has_defect(defects, "joints.J2.links[2]",
                         {"no link named 'Lx'", "did you mean 'L1'?"}, 9, 44));
  EXPECT_TRUE(
      has_defect(defects, "joints.J3.at", {"no point named 'Q'", "points are: O, A, B"}, 10, 21));
}

TEST(ModelDefects, ALinkEndTakesPartInOneJointOrSupportOnly) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B}
joints:
  J1: {type: revolute, at: A, links: [L1, L2], axis: [0, 0, 1]}
  J2: {type: rigid, at: A, links: [L2, L1, L1]}
supports:
  S1: {type: rigid, at: O}
  S2: {type: rigid, at: O, link: L1}
)");
  EXPECT_TRUE(has_defect(
      defects, "joints.J2.links[0]",
      {"link end L2.from is already in joint 'J1'", "at most one joint or support"}, 8, 36));
  EXPECT_TRUE(has_defect(defects, "joints.J2.links[2]", {"link 'L1' is listed twice"}, 8, 44));
  // A support's single `link:` is reported under that key.
  EXPECT_TRUE(has_defect(defects, "supports.S2.link",
                         {"link end L1.from is already in support 'S1'"}, 11, 28));
}

TEST(ModelDefects, PointWithSomeEndsNamedAndOthersNotIsAnError) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0], C: [1, 1, 0], D: [1, -1, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B}
  L3: {type: rigid, from: C, to: A}
  L4: {type: rigid, from: A, to: D}
joints:
  J: {type: revolute, at: A, links: [L1, L2], axis: [0, 0, 1]}
)");
  ASSERT_EQ(defects.size(), 1u) << listing(defects);
  EXPECT_TRUE(has_defect(defects, "points.A",
                         {"at point 'A'", "L3.to, L4.from", "in no joint or support"}, 2, 24));
}

TEST(ModelDefects, SupportNeedsALinkEndAtItsPoint) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], F: [5, 5, 5]}
links: {L: {type: rigid, from: O, to: A}}
supports:
  S1: {type: rigid, at: F}
  S2: {type: rigid, at: O, link: L, links: [L]}
)");
  EXPECT_TRUE(has_defect(defects, "supports.S1.at", {"no link end is at point 'F'"}, 5, 21));
  EXPECT_TRUE(has_defect(defects, "supports.S2.link", {"either link or links, not both"}, 6, 28));
}

TEST(ModelDefects, LoadsAndEndEffectorsMustMeanOneLinkEnd) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B}
  L3: {type: rigid, from: B, to: B}
loads:
  - {at: A, wrench: [1, 0, 0, 0, 0, 0]}
  - {at: Bx, wrench: [1, 0, 0, 0, 0, 0]}
  - {at: B, link: L4, wrench: [1, 0, 0, 0, 0, 0]}
end_effectors:
  E1: {at: B, link: L3}
  E2: {at: O, link: L2}
  E3: {at: O}
)");
  EXPECT_TRUE(has_defect(defects, "loads[0].at",
                         {"several link ends are at point 'A'", "name one with `link:`"}, 8, 6));
  EXPECT_TRUE(
      has_defect(defects, "loads[1].at", {"no point named 'Bx'", "did you mean 'B'?"}, 9, 6));
  EXPECT_TRUE(has_defect(defects, "loads[2].link", {"no link named 'L4'", "did you mean"}, 10, 13));
  EXPECT_TRUE(has_defect(defects, "end_effectors.E1.link", {"both ends at point 'B'"}, 12, 15));
  EXPECT_TRUE(
      has_defect(defects, "end_effectors.E2.link", {"link 'L2' has no end at point 'O'"}, 13, 15));
  EXPECT_EQ(count_at(defects, "end_effectors.E3"), 0u);
}

TEST(ModelDefects, ApiNamesMustBeUniqueAndNonEmptyAndWrenchesFinite) {
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("A", Vec3(1, 0, 0));
  m.add_point("", Vec3(2, 0, 0));
  m.add_rigid_link("L", "O", "A");
  m.add_rigid_link("L", "O", "A");
  Vec6 wrench = Vec6::Zero();
  wrench(4) = std::numeric_limits<double>::quiet_NaN();
  m.add_load("A", std::string("L"), wrench);
  m.add_end_effector("tip", "A");
  m.add_end_effector("tip", "O");
  const auto defects = find_defects(m);
  EXPECT_TRUE(has_defect(defects, "points[2]", {"needs a non-empty name"}));
  EXPECT_TRUE(has_defect(defects, "links.L", {"another link is named 'L'", "unique"}));
  EXPECT_TRUE(has_defect(defects, "loads[0].wrench", {"finite"}));
  EXPECT_TRUE(has_defect(defects, "end_effectors.tip", {"another end effector is named 'tip'"}));
}

// Long lists are checked for repeats through a table, short ones by a scan: both say the same.
TEST(ModelDefects, RepeatsAreFoundInLongListsToo) {
  Model m;
  m.add_point("O", Vec3::Zero());
  std::vector<std::string> links;
  for (int i = 0; i < 20; ++i) {
    const std::string name = "L" + std::to_string(i);
    m.add_point("P" + std::to_string(i), Vec3(1, i, 0));
    m.add_rigid_link(name, "O", "P" + std::to_string(i));
    links.push_back(name);
  }
  links.push_back("L7");
  m.add_support("base", "O", links, Connection::rigid());
  for (int i = 0; i < 20; ++i)
    m.add_end_effector(i == 17 ? "E3" : "E" + std::to_string(i), "P" + std::to_string(i));
  const auto defects = find_defects(m);
  EXPECT_TRUE(has_defect(defects, "supports.base.links[20]", {"link 'L7' is listed twice"}))
      << listing(defects);
  EXPECT_TRUE(has_defect(defects, "end_effectors.E3", {"another end effector is named 'E3'"}))
      << listing(defects);
  EXPECT_EQ(defects.size(), 2u) << listing(defects);
}

// ---- matrix and compliance links ---------------------------------------------------------

// A 12×12 free-free axial spring along local x between the link's ends.
Mat12 axial_spring(double k) {
  Mat12 K = Mat12::Zero();
  K(0, 0) = K(6, 6) = k;
  K(0, 6) = K(6, 0) = -k;
  return K;
}

Model two_point_model(const Vec3& to) {
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("A", to);
  return m;
}

TEST(ModelDefects, MatrixLinkMustBeSymmetricSemiDefiniteAndFreeFree) {
  Model m = two_point_model(Vec3(0, 2, 0));
  Mat12 asymmetric = axial_spring(1e6);
  asymmetric(0, 6) = -0.9e6;
  m.add_matrix_link("asymmetric", "O", "A", asymmetric);
  m.add_matrix_link("indefinite", "O", "A", -axial_spring(1e6), LinkFrame::local);
  m.add_matrix_link("grounded", "O", "A", 1e6 * Mat12::Identity());
  // Along local x the spring is free-free whatever the link's direction...
  m.add_matrix_link("local", "O", "A", axial_spring(1e6), LinkFrame::local);
  // ...but read as global, it pulls along x across a link that lies along y.
  m.add_matrix_link("global", "O", "A", axial_spring(1e6), LinkFrame::global);
  const auto defects = find_defects(m);
  EXPECT_TRUE(has_defect(defects, "links.asymmetric.K", {"must be symmetric", "K[6][0] = -1e+06"}));
  EXPECT_TRUE(has_defect(defects, "links.indefinite.K", {"positive semi-definite", "-2e+06"}));
  EXPECT_TRUE(
      has_defect(defects, "links.grounded.K", {"not free-free", "tie the link to the ground"}));
  EXPECT_TRUE(has_defect(defects, "links.global.K", {"not free-free"}));
  EXPECT_EQ(count_at(defects, "links.local.K"), 0u);
  EXPECT_EQ(defects.size(), 4u) << listing(defects);
}

TEST(ModelDefects, FreeFreeCheckUsesTheLinksGeometry) {
  // A beam-like bending block between the ends of a link along x is free-free only with its
  // coupling terms, which depend on the length.
  const double L = 3.0, k = 12.0;
  Mat12 K = Mat12::Zero();
  // Transverse y and rotation z of a clamped-clamped beam, EI = 1.
  const int v1 = 1, t1 = 5, v2 = 7, t2 = 11;
  const double a = k / (L * L * L), b = 6 / (L * L), c = 4 / L, d = 2 / L;
  K(v1, v1) = K(v2, v2) = a;
  K(v1, v2) = K(v2, v1) = -a;
  K(v1, t1) = K(t1, v1) = K(v1, t2) = K(t2, v1) = b;
  K(v2, t1) = K(t1, v2) = K(v2, t2) = K(t2, v2) = -b;
  K(t1, t1) = K(t2, t2) = c;
  K(t1, t2) = K(t2, t1) = d;
  Model right = two_point_model(Vec3(L, 0, 0));
  right.add_matrix_link("M", "O", "A", K);
  EXPECT_TRUE(find_defects(right).empty()) << listing(find_defects(right));
  Model wrong = two_point_model(Vec3(2 * L, 0, 0));
  wrong.add_matrix_link("M", "O", "A", K);
  EXPECT_TRUE(has_defect(find_defects(wrong), "links.M.K", {"not free-free"}));
}

TEST(ModelDefects, ComplianceMustBeSymmetricPositiveDefinite) {
  Model m = two_point_model(Vec3(1, 0, 0));
  Mat6 singular = Mat6::Identity();
  singular(3, 3) = 0;
  m.add_compliance_link("singular", "O", "A", singular);
  Mat6 asymmetric = Mat6::Identity();
  asymmetric(0, 1) = 0.5;
  m.add_compliance_link("asymmetric", "O", "A", asymmetric, LinkFrame::local);
  m.add_compliance_link("good", "O", "A", 1e-6 * Mat6::Identity());
  const auto defects = find_defects(m);
  EXPECT_TRUE(
      has_defect(defects, "links.singular.C", {"positive definite", "smallest eigenvalue is 0"}));
  EXPECT_TRUE(has_defect(defects, "links.asymmetric.C", {"must be symmetric"}));
  EXPECT_EQ(defects.size(), 2u) << listing(defects);
}

// ---- the model as a whole ----------------------------------------------------------------

TEST(ModelDefects, ModelWithoutLinksIsAnError) {
  const auto defects = defects_of("format: stiffmsa/1\npoints: {O: [0, 0, 0]}\n");
  ASSERT_EQ(defects.size(), 1u) << listing(defects);
  EXPECT_EQ(defects[0].key_path, "links");
  EXPECT_EQ(defects[0].location.file, "bad.yaml");
  EXPECT_NE(defects[0].message.find("no links"), std::string::npos);
}

TEST(ModelDefects, EveryDefectIsReportedInFileOrder) {
  const auto defects = defects_of(R"(format: stiffmsa/1
materials: {steel: {E: 2.0e11, nu: 0.7}}
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0]}
links:
  L1: {type: beam, from: O, to: A, material: steel, section: {shape: circle, D: 0.01}, zref: [0, 0]}
  L2: {type: rigid, from: A, to: Bx}
joints:
  J: {type: spherical, at: A, links: [L1, L2], axis: [1, 0, 0]}
end_effectors:
  tip: {at: B}
)");
  ASSERT_EQ(defects.size(), 5u) << listing(defects);
  EXPECT_EQ(defects[0].key_path, "materials.steel.nu");
  EXPECT_EQ(defects[1].key_path, "links.L1.zref");
  EXPECT_EQ(defects[2].key_path, "links.L2.to");
  EXPECT_EQ(defects[3].key_path, "joints.J.axis");
  EXPECT_EQ(defects[4].key_path, "end_effectors.tip.at");
  EXPECT_NE(defects[4].message.find("no link end is at point 'B'"), std::string::npos);
  // The exception's text lists them all.
  try {
    parse_model(
        "format: stiffmsa/1\npoints: {O: [0, 0, 0]}\nlinks: {L: {type: rigid, from: O, to: Q}}\n"
        "end_effectors: {E: {at: Z}}\n",
        "m.yaml");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2 defects"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("m.yaml:3:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("m.yaml:4:"), std::string::npos) << e.what();
  }
}

TEST(ModelDefects, ValidModelsHaveNoDefects) {
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("A", Vec3(0.5, 0, 0));
  m.add_point("E", Vec3(1.0, 0, 0));
  m.add_beam("L1", "O", "A", Material{2.1e11, 0.3, std::nullopt, std::nullopt},
             Section::tube(0.08, 0.005));
  m.add_rigid_link("L2", "A", "E");
  m.add_joint("J1", "A", {"L1", "L2"},
              Connection::actuated(Kinematics::revolute(Vec3(0, 0, 1)), 1e4).preloaded(2.0));
  m.add_support("S1", "O", {}, Connection::rigid());
  m.add_load("E", std::nullopt, Vec6::Unit(1));
  m.add_end_effector("EE", "E");
  EXPECT_TRUE(find_defects(m).empty()) << listing(find_defects(m));
  EXPECT_NO_THROW(validate(m));

  m.links[0].name = "";
  EXPECT_THROW(validate(m), InputError);
}

TEST(ModelDefects, ModelWithoutEndEffectorsIsValid) {
  EXPECT_NO_THROW(parse_model(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0]}
links: {L: {type: rigid, from: O, to: A}}
supports: {S: {type: rigid, at: O}}
)",
                              "m.yaml"));
}

// ---- issue 22: loads along links, gravity, load cases, settlements, analysis -------------

const std::string kFrameHead = R"(format: stiffmsa/1
materials: {steel: {E: 2.1e11, nu: 0.3, density: 7850}}
points: {O: [0, 0, 0], A: [1, 0, 0], E: [2, 0, 0]}
links:
  beam1: {type: beam, from: O, to: A, material: steel, section: {shape: circle, D: 0.05}}
  cad: {type: compliance, from: A, to: E, C: [[1e-6, 0, 0, 0, 0, 0], [0, 1e-6, 0, 0, 0, 0], [0, 0, 1e-6, 0, 0, 0], [0, 0, 0, 1e-5, 0, 0], [0, 0, 0, 0, 1e-5, 0], [0, 0, 0, 0, 0, 1e-5]]}
supports:
  base: {type: rigid, at: O}
)";

TEST(ModelDefects, ALoadMixingPointAndLinkKeysNamesTheKeys) {
  const auto defects = defects_of(kFrameHead + R"(loads:
  - {at: A, link: beam1, wrench: [0, 0, 1, 0, 0, 0], force: [0, 0, 1], position: 0.5}
)");
  ASSERT_EQ(defects.size(), 1u) << listing(defects);
  EXPECT_TRUE(has_defect(defects, "loads[0]",
                         {"a load is either on a point", "along a link",
                          "this one gives at, wrench with force, position"},
                         10, 5));
}

TEST(ModelDefects, LinkLoadKeysAreChecked) {
  const auto defects = defects_of(kFrameHead + R"(loads:
  - {link: beam1, distributed: [0, 0]}
  - {link: beam1, distributed: {from: [0, 0, 1]}}
  - {link: beam1, distributed: {from: [0, 0, 1], to: [0, 0, 1], middle: [0, 0, 1]}}
  - {link: beam1, distributed: 5}
  - {link: beam1, distributed: [0, 0, 1], position: 0.5}
  - {link: beam1, force: [0, 0, 1]}
  - {link: beam1, force: [0, 0, 1], position: 0.5, momnet: [0, 0, 1]}
  - {force: [0, 0, 1], position: 0.5}
  - {link: beam1, force: [0, 0, 1, 0], position: half}
)");
  EXPECT_TRUE(has_defect(defects, "loads[0].distributed",
                         {"expected 3 numbers [qx, qy, qz]", "got 2"}, 10, 32));
  EXPECT_TRUE(has_defect(defects, "loads[1].distributed.to", {"missing key 'to'"}));
  EXPECT_TRUE(has_defect(defects, "loads[2].distributed.middle", {"unknown key 'middle'"}));
  EXPECT_TRUE(has_defect(defects, "loads[3].distributed",
                         {"expected [qx, qy, qz] (uniform, N/m) or {from:", "got '5'"}));
  EXPECT_TRUE(has_defect(defects, "loads[4].position",
                         {"key 'position' does not apply to a distributed load along a link",
                          "valid keys are: link, distributed"}));
  EXPECT_TRUE(has_defect(defects, "loads[5].position", {"missing key 'position'"}));
  EXPECT_TRUE(
      has_defect(defects, "loads[6].momnet", {"unknown key 'momnet'", "did you mean 'moment'?"}));
  EXPECT_TRUE(has_defect(defects, "loads[7].link", {"missing key 'link'"}));
  EXPECT_TRUE(has_defect(defects, "loads[8].force", {"expected 3 numbers [Fx, Fy, Fz]", "got 4"}));
  EXPECT_TRUE(has_defect(defects, "loads[8].position", {"expected a number", "'half'"}));
}

TEST(ModelDefects, NewTopLevelKeysAreChecked) {
  const auto defects = defects_of(kFrameHead + R"(gravity: [0, -9.81]
analysis: {mode: loded, load_steps: 2.5, steps: 3}
load_cases:
  a: 5
  b: {loads: [], gravty: [0, 0, -9.81]}
  c: {gravity: [0, 0, x]}
  d: [{frame: tool, wrench: [0, 0, 1, 0, 0, 0]}]
)");
  EXPECT_TRUE(has_defect(defects, "gravity", {"expected 3 numbers [gx, gy, gz]", "got 2"}, 9, 10));
  EXPECT_TRUE(has_defect(defects, "analysis.mode",
                         {"unknown analysis mode 'loded'", "did you mean 'loaded'?"}, 10, 18));
  EXPECT_TRUE(has_defect(defects, "analysis.load_steps",
                         {"load_steps is a whole number of load steps", "got '2.5'"}));
  EXPECT_TRUE(has_defect(defects, "analysis.steps", {"unknown key 'steps'"}));
  EXPECT_TRUE(
      has_defect(defects, "load_cases.a",
                 {"expected a list of loads or {loads: [...], gravity: [gx, gy, gz]}", "got '5'"}));
  EXPECT_TRUE(has_defect(defects, "load_cases.b.gravty",
                         {"unknown key 'gravty'", "did you mean 'gravity'?"}));
  EXPECT_TRUE(has_defect(defects, "load_cases.c.gravity[2]", {"expected a number", "'x'"}));
  EXPECT_TRUE(has_defect(defects, "load_cases.d[0].frame",
                         {"a load on a robot frame stands in the top-level `loads:` only"}));
}

TEST(ModelDefects, DensityAndDisplacementKeysAreChecked) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0]}
links:
  L: {type: beam, from: O, to: A, material: {E: 2.1e11, nu: 0.3, density: heavy}, section: {shape: circle, D: 0.05}}
joints: {}
supports:
  S: {type: rigid, at: O, displacement: [0, 0, 1]}
)");
  EXPECT_TRUE(has_defect(defects, "links.L.material.density", {"expected a number", "'heavy'"}));
  EXPECT_TRUE(has_defect(defects, "supports.S.displacement",
                         {"expected 6 numbers [dx, dy, dz, rx, ry, rz]", "got 3"}, 7, 41));
}

TEST(ModelDefects, LinkLoadsNeedAnExistingNonCadLinkAndAPositionOnIt) {
  const auto defects = defects_of(kFrameHead + R"(loads:
  - {link: beam, distributed: [0, 0, -1]}
  - {link: cad, force: [0, 0, -1], position: 0.5}
  - {link: beam1, force: [0, 0, -1], position: 1.5}
  - {link: beam1, force: [0, 0, -1], position: -0.1}
  - {at: E, wrench: [0, 0, -1, 0, 0, 0]}
)");
  ASSERT_EQ(defects.size(), 4u) << listing(defects);
  // The file's key paths, though the model keeps link loads in a list of their own.
  EXPECT_TRUE(
      has_defect(defects, "loads[0].link", {"no link named 'beam'", "did you mean 'beam1'?"}));
  EXPECT_TRUE(has_defect(defects, "loads[1].link",
                         {"link 'cad' is a compliance link (from CAD)",
                          "give a load along it as loads at the link's ends"},
                         11, 6));
  EXPECT_TRUE(has_defect(defects, "loads[2].position",
                         {"position is a fraction of the link's length", "in [0, 1]", "got 1.5"},
                         12, 38));
  EXPECT_TRUE(has_defect(defects, "loads[3].position", {"in [0, 1]", "got -0.1"}));
}

TEST(ModelDefects, GravityWithoutAnyDensityIsAnError) {
  const std::string no_density = R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0]}
links: {L: {type: beam, from: O, to: A, material: {E: 2.1e11, nu: 0.3}, section: {shape: circle, D: 0.05}}}
supports: {S: {type: rigid, at: O}}
gravity: [0, 0, -9.81]
load_cases:
  heavy: {gravity: [0, 0, -9.81]}
)";
  const auto defects = defects_of(no_density);
  ASSERT_EQ(defects.size(), 2u) << listing(defects);
  EXPECT_TRUE(has_defect(defects, "gravity",
                         {"gravity is given but no beam's material has a density: nothing weighs",
                          "give the materials of the beams that weigh a density (kg/m³)"},
                         5, 1));
  EXPECT_TRUE(
      has_defect(defects, "load_cases.heavy.gravity", {"no beam's material has a density"}, 7, 11));
}

TEST(ModelDefects, DensityMustBePositive) {
  const auto defects = defects_of(R"(format: stiffmsa/1
materials: {steel: {E: 2.1e11, nu: 0.3, density: -7850}}
points: {O: [0, 0, 0], A: [1, 0, 0]}
links:
  L: {type: beam, from: O, to: A, material: steel, section: {shape: circle, D: 0.05}}
  M: {type: beam, from: O, to: A, material: {E: 2.1e11, nu: 0.3, density: 0}, section: {shape: circle, D: 0.05}}
)");
  EXPECT_TRUE(has_defect(defects, "materials.steel.density",
                         {"density must be a positive number", "got -7850"}, 2, 41));
  EXPECT_TRUE(
      has_defect(defects, "links.M.material.density", {"density must be a positive number"}));
}

TEST(ModelDefects, LoadsInCasesObeyTheTopLevelRules) {
  const auto defects = defects_of(kFrameHead + R"(load_cases:
  first: [{at: Q, wrench: [0, 0, -1, 0, 0, 0]}, {link: cad, distributed: [0, 0, -1]}]
  second: {loads: [{at: A, wrench: [0, 0, -1, 0, 0, 0]}, {link: beam1, force: [0, 0, 1], position: 2}]}
)");
  ASSERT_EQ(defects.size(), 4u) << listing(defects);
  EXPECT_TRUE(has_defect(defects, "load_cases.first[0].at",
                         {"no point named 'Q'", "points are: O, A, E"}, 10, 12));
  EXPECT_TRUE(has_defect(defects, "load_cases.first[1].link", {"is a compliance link"}));
  EXPECT_TRUE(has_defect(defects, "load_cases.second.loads[0].at",
                         {"several link ends are at point \'A\'", "name one with `link:`"}));
  EXPECT_TRUE(has_defect(defects, "load_cases.second.loads[1].position", {"got 2"}));
}

TEST(ModelDefects, ApiLoadCasesNeedUniqueNonEmptyNamesAndFiniteValues) {
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("A", Vec3(1, 0, 0));
  Material steel{2.1e11, 0.3, std::nullopt, std::numeric_limits<double>::infinity()};
  m.add_beam("L", "O", "A", steel, Section::circle(0.05));
  m.add_support("S", "O", {}, Connection::rigid());
  m.add_link_load("L", DistributedLinkLoad{Vec3(0, 0, std::nan("")), Vec3::Zero()});
  m.add_link_load("M", PointLinkLoad{Vec3::Zero(), Vec3::Zero(), 0.5});
  m.gravity = Vec3(0, 0, std::numeric_limits<double>::infinity());
  LoadCase a;
  a.name = "a";
  m.add_load_case(a);
  m.add_load_case(a);
  m.add_load_case(LoadCase{});
  m.options.load_steps = 0;
  const auto defects = find_defects(m);
  EXPECT_TRUE(has_defect(defects, "links.L.material.density", {"positive"}));
  EXPECT_TRUE(has_defect(defects, "link_loads[0].distributed.from", {"finite"}));
  EXPECT_TRUE(has_defect(defects, "link_loads[1].link", {"no link named 'M'"}));
  EXPECT_TRUE(has_defect(defects, "gravity", {"finite"}));
  EXPECT_TRUE(has_defect(defects, "load_cases.a", {"another load case is named 'a'", "unique"}));
  EXPECT_TRUE(has_defect(defects, "load_cases[2]", {"a load case needs a non-empty name"}));
  EXPECT_TRUE(has_defect(defects, "analysis.load_steps",
                         {"load_steps must be a positive number of load steps", "got 0"}));
}

TEST(ModelDefects, SettlementAlongAFreeDirectionIsAnError) {
  const auto defects = defects_of(R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [0, 1, 0], C: [0, 0, 1]}
links:
  L: {type: rigid, from: O, to: A}
  M: {type: rigid, from: B, to: A}
  N: {type: rigid, from: C, to: A}
joints: {J: {type: rigid, at: A, links: [L, M, N]}}
supports:
  pin: {type: revolute, at: O, axis: [0, 0, 2], displacement: [0, 0, -0.001, 0, 0, 0.01]}
  ball: {type: spherical, at: B, displacement: [0.001, 0, 0, 0, 0.02, 0]}
  slide: {type: prismatic, at: C, axis: [1, 1, 0], displacement: [0, 0, 0.001, 0, 0, 0]}
)");
  ASSERT_EQ(defects.size(), 2u) << listing(defects);
  EXPECT_TRUE(has_defect(defects, "supports.pin.displacement",
                         {"support 'pin' leaves the rotation about its axis [0, 0, 2] free",
                          "moves it that way by 0.01", "make that component zero"},
                         9, 49));
  EXPECT_TRUE(has_defect(defects, "supports.ball.displacement",
                         {"support 'ball' leaves the ry free", "by 0.02"}));
  EXPECT_EQ(count_at(defects, "supports.slide.displacement"), 0u);  // across its axis: held
}

TEST(ModelDefects, SettlementsAreCheckedPerPose) {
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("A", Vec3(1, 0, 0));
  m.add_rigid_link("L", "O", "A");
  const auto pin =
      m.add_support("pin", "O", {}, Connection::passive(Kinematics::revolute({0, 0, 1})));
  Vec6 settlement = Vec6::Zero();
  settlement(0) = 0.001;
  m.support(pin).displacement = settlement;
  EXPECT_TRUE(find_defects(m).empty()) << listing(find_defects(m));
  const Structure structure(m);
  std::vector<double> values = structure.default_values();
  values[*structure.find_slot("supports.pin.displacement[5]")] = 0.1;
  values[*structure.find_slot("supports.pin.axis[2]")] = 1;
  EXPECT_TRUE(has_defect(structure.find_value_defects(values), "supports.pin.displacement",
                         {"leaves the rotation about its axis [0, 0, 1] free"}));
}

}  // namespace
}  // namespace stiffmsa

TEST(NameTable, FindsTheFirstBearerOfEveryNameAndGrowsPastItsReservation) {
  std::vector<std::string> names;
  for (int i = 0; i < 1000; ++i)
    names.push_back("n" + std::to_string(i % 700));  // the last 300 repeat
  stiffmsa::detail::NameTable table(10);             // reserved for far fewer names: it must grow
  for (std::size_t i = 0; i < names.size(); ++i)
    EXPECT_EQ(table.add(names[i]), static_cast<int>(i % 700));
  for (int i = 0; i < 700; ++i) EXPECT_EQ(table.find("n" + std::to_string(i)), i);
  EXPECT_EQ(table.find("n700"), -1);
  EXPECT_EQ(table.find(""), -1);
}

#pragma once
// The model: plain data describing a manipulator exactly as the user named it. It holds no
// index maps, matrices or results; those live in a Workspace (analysis.hpp). A model is
// checked with validate() (validate.hpp) before it is solved.
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "stiffmsa/errors.hpp"
#include "stiffmsa/types.hpp"

namespace stiffmsa {

// Where one key of an entity sits in the entity's file.
struct KeyLocation {
  std::string key;  // e.g. "axis", "section.D", "links[1]"
  int line = 0;     // 1-based
  int column = 0;   // 1-based
};

// Where an entity and each of its keys came from in a model file (empty for API models). The
// keys are in the file of `location`: one file name per entity, not one per key.
struct Origin {
  SourceLocation location;                 // the entity's own mapping
  std::vector<KeyLocation> key_locations;  // in the order read; a later entry of a key wins

  // The location of `key` if recorded, else the entity's own location.
  SourceLocation of(std::string_view key) const;
  // The entry of `key`, or null.
  const KeyLocation* find(std::string_view key) const;
  // Records `key` at `at` (whose file is the entity's).
  void record(std::string key, const SourceLocation& at);
};

struct Point {
  std::string name;
  Vec3 position = Vec3::Zero();
  Origin origin;
};

// ---- links -------------------------------------------------------------------------------

struct Material {
  double E = 0;
  std::optional<double> nu;  // exactly one of nu or G
  std::optional<double> G;
  // kg/m³: a beam of this material weighs density·A·g per metre under a load case's gravity.
  std::optional<double> density;
};

enum class SectionShape { circle, tube, rect, rect_tube, generic };

// Dimensions by shape (sections.md): circle{D}, tube{D,t}, rect{b,h}, rect_tube{b,h,t},
// generic{A,Iy,Iz,J}. Asy/Asz override the shape's shear areas.
struct Section {
  SectionShape shape = SectionShape::generic;
  double D = 0, t = 0, b = 0, h = 0;
  double A = 0, Iy = 0, Iz = 0, J = 0;
  std::optional<double> Asy, Asz;

  static Section circle(double D);
  static Section tube(double D, double t);
  static Section rect(double b, double h);
  static Section rect_tube(double b, double h, double t);
  static Section generic(double A, double Iy, double Iz, double J);
};

// Properties of a section as the beam element uses them.
struct SectionProperties {
  double A = 0, Iy = 0, Iz = 0, J = 0;
  std::optional<double> Asy, Asz;  // absent where neither the shape nor the user gives one
};

enum class LinkFrame { global, local };

struct BeamLink {
  Material material;
  Section section;
  bool shear = false;  // Timoshenko
  std::optional<Vec3> zref;
};
struct RigidLink {};
// CAD-based link: 12×12 free-free stiffness over [Δt_from; Δt_to].
struct MatrixLink {
  Mat12 K = Mat12::Zero();
  LinkFrame frame = LinkFrame::global;
  std::optional<Vec3> zref;
};
// CAD-based link: 6×6 compliance of end `to` with end `from` clamped.
struct ComplianceLink {
  Mat6 C = Mat6::Zero();
  LinkFrame frame = LinkFrame::global;
  std::optional<Vec3> zref;
};

using LinkKind = std::variant<BeamLink, RigidLink, MatrixLink, ComplianceLink>;

struct Link {
  std::string name;
  std::string from, to;  // point names
  LinkKind kind;
  Origin origin;
};

// ---- joints and supports -----------------------------------------------------------------

enum class JointType {
  rigid,
  revolute,
  prismatic,
  cylindrical,
  universal,
  spherical,
  planar,
  custom
};

// The free directions of a joint or support (model-format.md, "free directions").
struct Kinematics {
  JointType type = JointType::rigid;
  Vec3 axis = Vec3::Zero();     // revolute, prismatic, cylindrical
  Vec3 axis_b = Vec3::Zero();   // universal: axes [axis, axis_b]
  Vec3 normal = Vec3::Zero();   // planar
  std::vector<Vec6> free_rows;  // custom, as given

  static Kinematics rigid();
  static Kinematics revolute(const Vec3& axis);
  static Kinematics prismatic(const Vec3& axis);
  static Kinematics cylindrical(const Vec3& axis);
  static Kinematics universal(const Vec3& a, const Vec3& b);
  static Kinematics spherical();
  static Kinematics planar(const Vec3& normal);
  static Kinematics custom(std::vector<Vec6> rows);
};

// Number of free directions p of a joint type (custom: its row count).
int free_direction_count(const Kinematics& k);

// What a joint or support does along its free directions. Built by its factories, which say
// what it is: Connection::rigid(), passive(k), elastic(k, K), actuated(k), actuated(k, K), and
// .preloaded(f) on any of them (model-format.md, "Passive, elastic, preloaded and actuated
// joints"). A spring along a single free direction is a scalar:
// elastic(Kinematics::revolute(z), 1e4).
struct Connection {
  Kinematics kinematics;
  std::optional<MatX> stiffness;  // p×p, symmetric positive definite: elastic
  std::optional<VecX> preload;    // p: generalised force at zero relative deflection
  bool is_actuated = false;       // without stiffness: locked (rigid), effort reported

  Connection() = default;  // rigid; not an aggregate, so that no positional list builds one

  // A weld: no free direction.
  static Connection rigid();
  // Free along the kinematics' directions, neither resisted nor driven.
  static Connection passive(Kinematics kinematics);
  // A spring on the free directions: p×p stiffness, or a scalar where p = 1 (UsageError else).
  static Connection elastic(Kinematics kinematics, MatX stiffness);
  static Connection elastic(Kinematics kinematics, double stiffness);
  // A drive: locked along the free directions, its effort reported; with a stiffness (p×p, or
  // a scalar where p = 1), a drive that yields as a spring.
  static Connection actuated(Kinematics kinematics);
  static Connection actuated(Kinematics kinematics, MatX stiffness);
  static Connection actuated(Kinematics kinematics, double stiffness);
  // The same connection with a preload: p values, or a scalar where p = 1 (UsageError else).
  Connection preloaded(VecX preload) const;
  Connection preloaded(double preload) const;
};

struct Joint {
  std::string name;
  std::string at;                  // point
  std::vector<std::string> links;  // m >= 2 link ends at `at`, first is "end 1"
  Connection connection;
  Origin origin;
};

struct Support {
  std::string name;
  std::string at;
  std::vector<std::string> links;  // empty: every link end at the point
  Connection connection;
  Origin origin;
  // A settlement: the ground moves by [dx, dy, dz, rx, ry, rz] (global axes; rotations as a
  // rotation vector) along the directions the support holds; zero along its free directions.
  // It acts in every load case, as a load does (the reactions follow from it).
  std::optional<Vec6> displacement;
};

// ---- loads and end effectors -------------------------------------------------------------

struct Load {
  std::string at;
  std::optional<std::string> link;  // may be left out where one link end is at the point
  Vec6 wrench = Vec6::Zero();       // [F; M] global, moment about `at`
  // A robot link's weight (docs/urdf.md): the result also gives the end effectors' deflection
  // under these loads alone.
  bool self_weight = false;
  Origin origin;
};

// A dead load along a link, global axes: a force per metre of undeformed length, varying
// linearly from `from` at the link's `from` end to `to` at its `to` end (equal: uniform).
struct DistributedLinkLoad {
  Vec3 from = Vec3::Zero();
  Vec3 to = Vec3::Zero();
};
// A force and a moment (global axes) at `position`, a fraction of the link's length from its
// `from` end.
struct PointLinkLoad {
  Vec3 force = Vec3::Zero();
  Vec3 moment = Vec3::Zero();
  double position = 0;
};
struct LinkLoad {
  std::string link;
  std::variant<DistributedLinkLoad, PointLinkLoad> load;
  Origin origin;
};

// A named set of loads (model file `load_cases:`). Every case is solved with one factorisation;
// the model's own `loads`, `link_loads` and `gravity` are the unnamed case.
struct LoadCase {
  std::string name;
  std::vector<Load> loads;
  std::vector<LinkLoad> link_loads;
  // m/s², global axes: the self-weight of every beam whose material has a density.
  std::optional<Vec3> gravity;
  Origin origin;
};

struct EndEffector {
  std::string name;
  std::string at;
  std::optional<std::string> link;
  // Results in these axes too (columns: the axes in world axes), e.g. a robot frame's.
  std::optional<Mat3> axes;
  Origin origin;
};

// ---- the model ---------------------------------------------------------------------------

enum class LinkEnd { from = 0, to = 1 };

// The linear analysis answers at the unloaded pose; the loaded mode finds each load case's
// equilibrium in the deformed geometry and the tangent stiffness there (docs/theory.md).
enum class AnalysisMode { linear, loaded };
const char* to_string(AnalysisMode mode);
std::optional<AnalysisMode> analysis_mode_from_string(std::string_view name);

// Settings a model file may carry for its own analysis (top-level `options:`).
struct ModelOptions {
  // Solve despite free motions that move no end effector (the spin of an S-P-S leg about its
  // own axis): the end-effector results do not depend on them.
  bool accept_idle_motions = false;
  // Top-level `analysis: {mode: loaded}`; SolveOptions::mode overrides it.
  AnalysisMode mode = AnalysisMode::linear;
  // `analysis: {load_steps: N}`: the loaded mode's number of load steps (positive); unset, the
  // analysis chooses.
  std::optional<int> load_steps;
};

// A parameter of a parametric model (parametric.hpp) at the value a model was built for.
struct ParameterValue {
  std::string name;
  double value = 0;
  std::string unit;  // as the file gives it; may be empty
  bool set = false;  // given by the user (`--set`), not the file's default
};

// Where an add_* verb put its entity: its position in the model's list of that kind (model
// order, as results list them). Unlike a reference into the list, a later add_* leaves it
// valid. Read or change the entity through Model's accessors: model.link(beam).origin = ….
template <class Entity>
struct EntityIndex {
  std::size_t value = 0;
  friend bool operator==(EntityIndex, EntityIndex) = default;
};
using PointIndex = EntityIndex<Point>;
using LinkIndex = EntityIndex<Link>;
using JointIndex = EntityIndex<Joint>;
using SupportIndex = EntityIndex<Support>;
using LoadIndex = EntityIndex<Load>;
using LinkLoadIndex = EntityIndex<LinkLoad>;
using LoadCaseIndex = EntityIndex<LoadCase>;
using EndEffectorIndex = EntityIndex<EndEffector>;

struct Model {
  std::string name = "model";
  // A model file's `parameters:` at the values this model was built for (the defaults, or
  // the settings of load_model_family); empty for a file without parameters and API models.
  // For the record only: the numbers they gave are already in the model.
  std::vector<ParameterValue> parameters;
  ModelOptions options;
  std::string source_file;  // empty for API models
  // Named materials and sections, as a model file's `materials:` and `sections:`, for the
  // add_beam that takes names. A beam holds a copy of the values it was built with.
  std::map<std::string, Material, std::less<>> materials;
  std::map<std::string, Section, std::less<>> sections;
  std::vector<Point> points;
  std::vector<Link> links;
  std::vector<Joint> joints;
  std::vector<Support> supports;
  // The unnamed load case: `loads:`, loads along links and `gravity:` at the top level.
  std::vector<Load> loads;
  std::vector<LinkLoad> link_loads;
  std::optional<Vec3> gravity;  // m/s², global axes (self-weight of beams with a density)
  // Named load cases (`load_cases:`). The top-level results are the unnamed case's where the
  // model has one (any load, link load or gravity above) or no named case; else the first's.
  std::vector<LoadCase> load_cases;
  std::vector<EndEffector> end_effectors;
  // What the reader noticed that does not make the model invalid (a robot's joint position
  // outside its limits); a solve reports them among its warnings.
  std::vector<Diagnostic> warnings;

  // Verbs for building a model in code; each returns the new entity's index. Names are checked
  // by validate() (all defects at once), except the material and section names add_beam
  // looks up at once (NameError) and a name given twice to add_material or add_section
  // (UsageError).
  void add_material(std::string name, const Material& material);
  void add_section(std::string name, const Section& section);
  PointIndex add_point(std::string name, const Vec3& position);
  LinkIndex add_beam(std::string name, std::string from, std::string to, const Material& material,
                     const Section& section);
  LinkIndex add_beam(std::string name, std::string from, std::string to, std::string_view material,
                     std::string_view section);
  LinkIndex add_rigid_link(std::string name, std::string from, std::string to);
  LinkIndex add_matrix_link(std::string name, std::string from, std::string to, const Mat12& K,
                            LinkFrame frame = LinkFrame::global);
  LinkIndex add_compliance_link(std::string name, std::string from, std::string to, const Mat6& C,
                                LinkFrame frame = LinkFrame::global);
  JointIndex add_joint(std::string name, std::string at, std::vector<std::string> links,
                       Connection connection);
  SupportIndex add_support(std::string name, std::string at, std::vector<std::string> links,
                           Connection connection);
  LoadIndex add_load(std::string at, std::optional<std::string> link, const Vec6& wrench);
  LinkLoadIndex add_link_load(std::string link, const DistributedLinkLoad& load);
  LinkLoadIndex add_link_load(std::string link, const PointLinkLoad& load);
  LoadCaseIndex add_load_case(LoadCase load_case);
  EndEffectorIndex add_end_effector(std::string name, std::string at,
                                    std::optional<std::string> link = std::nullopt);

  // The entity an add_* verb returned the index of (std::out_of_range past the end).
  Point& point(PointIndex i) { return points.at(i.value); }
  const Point& point(PointIndex i) const { return points.at(i.value); }
  Link& link(LinkIndex i) { return links.at(i.value); }
  const Link& link(LinkIndex i) const { return links.at(i.value); }
  Joint& joint(JointIndex i) { return joints.at(i.value); }
  const Joint& joint(JointIndex i) const { return joints.at(i.value); }
  Support& support(SupportIndex i) { return supports.at(i.value); }
  const Support& support(SupportIndex i) const { return supports.at(i.value); }
  Load& load(LoadIndex i) { return loads.at(i.value); }
  const Load& load(LoadIndex i) const { return loads.at(i.value); }
  LinkLoad& link_load(LinkLoadIndex i) { return link_loads.at(i.value); }
  const LinkLoad& link_load(LinkLoadIndex i) const { return link_loads.at(i.value); }
  LoadCase& load_case(LoadCaseIndex i) { return load_cases.at(i.value); }
  const LoadCase& load_case(LoadCaseIndex i) const { return load_cases.at(i.value); }
  EndEffector& end_effector(EndEffectorIndex i) { return end_effectors.at(i.value); }
  const EndEffector& end_effector(EndEffectorIndex i) const { return end_effectors.at(i.value); }

  // A named material or section; NameError (with the nearest name) when there is none.
  const Material& material(std::string_view name) const;
  const Section& section(std::string_view name) const;

  // Lookups by name (nullptr when absent).
  const Point* find_point(const std::string& name) const;
  const Link* find_link(const std::string& name) const;
};

// Shear modulus of a material: G, or E/(2(1+nu)).
double shear_modulus(const Material& m);

// A, Iy, Iz, J and shear areas of a section (sections.md).
SectionProperties section_properties(const Section& s);

// Enum <-> string pairs for every name a user can write.
const char* to_string(JointType t);
std::optional<JointType> joint_type_from_string(const std::string& s);
const char* to_string(SectionShape s);
std::optional<SectionShape> section_shape_from_string(const std::string& s);
const char* to_string(LinkEnd e);

}  // namespace stiffmsa

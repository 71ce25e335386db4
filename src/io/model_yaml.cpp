// Model files (model-format.md) read into a YAML tree (io/yaml_tree.hpp, parsed by libfyaml);
// JSON is read by the same parser, since YAML is a superset of it. The loader checks what only
// the file shows (syntax, keys, types, sizes) and leaves every check that an API-built model
// needs too to find_defects().
#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>

#include "io/expressions.hpp"
#include "io/plain_number.hpp"
#include "io/robot_model.hpp"
#include "io/slot_bindings.hpp"
#include "io/urdf_tree.hpp"
#include "io/yaml_tree.hpp"
#include "model/model_numbers.hpp"
#include "model/name_errors.hpp"
#include "model/suggest.hpp"
#include "model/value_checks.hpp"
#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/number_text.hpp"
#include "stiffmsa/parametric.hpp"
#include "stiffmsa/structure.hpp"
#include "stiffmsa/validate.hpp"

namespace stiffmsa {
namespace {

using KeyList = std::vector<std::string>;
using detail::YamlNode;

constexpr const char* kFormat = "stiffmsa/1";

const KeyList kTopKeys{"format",        "name",      "parameters", "derived", "options",
                       "analysis",      "materials", "sections",   "points",  "links",
                       "joints",        "supports",  "loads",      "gravity", "load_cases",
                       "end_effectors", "robot"};
const KeyList kParameterKeys{"default", "unit"};
const KeyList kOptionKeys{"accept_idle_motions"};
const KeyList kMaterialKeys{"E", "nu", "G", "density"};
const KeyList kAnalysisKeys{"mode", "load_steps"};
const KeyList kAnalysisModes{"linear", "loaded"};
const KeyList kSectionKeys{"shape", "D", "t", "b", "h", "A", "Iy", "Iz", "J", "Asy", "Asz"};
const KeyList kLinkTypes{"beam", "rigid", "matrix", "compliance"};
const KeyList kLinkKeys{"type",  "from", "to", "material", "section",
                        "shear", "zref", "K",  "C",        "frame"};
const KeyList kFrames{"global", "local"};
const KeyList kSpringKeys{"stiffness", "preload", "actuated"};
const KeyList kLoadKeys{"at", "link", "wrench", "self_weight"};
// Loads along a link (`link` is shared with point loads): a key of these makes a load one.
const KeyList kLinkLoadOnlyKeys{"distributed", "force", "moment", "position"};
const KeyList kDistributedLoadKeys{"link", "distributed"};
const KeyList kPointLinkLoadKeys{"link", "force", "moment", "position"};
const KeyList kLinkLoadKeys{"link", "distributed", "force", "moment", "position"};
const KeyList kDistributedEndKeys{"from", "to"};
const KeyList kLoadCaseKeys{"loads", "gravity"};
const KeyList kEndEffectorKeys{"at", "link"};
// The robot block (docs/urdf.md) and what refers to its frames.
const KeyList kRobotKeys{"urdf",          "base",  "positions", "joints",
                         "default_joint", "links", "gravity"};
const KeyList kRobotJointKeys{"stiffness", "compliance"};
const KeyList kRobotLinkKeys{"material", "section", "shear"};
const KeyList kFrameLoadKeys{"frame", "wrench", "offset", "axes"};
const KeyList kFrameEndEffectorKeys{"frame", "offset", "axes"};
const KeyList kFrameAxes{"world", "frame"};
// A 6×6 joint compliance is symmetric to this relative tolerance (a file's rounding).
constexpr double kComplianceSymmetryTolerance = 1e-9;

KeyList operator+(KeyList a, const KeyList& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

bool contains(const KeyList& list, const std::string& key) {
  return std::find(list.begin(), list.end(), key) != list.end();
}

const KeyList& link_keys(const std::string& type) {
  static const KeyList rigid{"type", "from", "to"};
  static const KeyList beam = rigid + KeyList{"material", "section", "shear", "zref"};
  static const KeyList matrix = rigid + KeyList{"K", "frame", "zref"};
  static const KeyList compliance = rigid + KeyList{"C", "frame", "zref"};
  if (type == "beam") return beam;
  if (type == "matrix") return matrix;
  if (type == "compliance") return compliance;
  return rigid;
}

// The keys that give a joint type its free directions.
KeyList parameter_keys(JointType type) {
  switch (type) {
    case JointType::revolute:
    case JointType::prismatic:
    case JointType::cylindrical: return {"axis"};
    case JointType::universal: return {"axes"};
    case JointType::planar: return {"normal"};
    case JointType::custom: return {"free"};
    case JointType::rigid:
    case JointType::spherical: return {};
  }
  return {};
}

KeyList joint_type_names() {
  KeyList names;
  for (auto t :
       {JointType::rigid, JointType::revolute, JointType::prismatic, JointType::cylindrical,
        JointType::universal, JointType::spherical, JointType::planar, JointType::custom})
    names.push_back(to_string(t));
  return names;
}

KeyList section_shape_names() {
  KeyList names;
  for (auto s : {SectionShape::circle, SectionShape::tube, SectionShape::rect,
                 SectionShape::rect_tube, SectionShape::generic})
    names.push_back(to_string(s));
  return names;
}

// Where a node is in the file being read. Values and keys carry only this while they are read:
// a SourceLocation would copy the file's name for each of the million keys of a large model.
struct Position {
  int line = 0;
  int column = 0;
};

Position position_of(const YamlNode& node) { return {node.line(), node.column()}; }

std::string describe(const YamlNode& node) {
  switch (node.kind()) {
    case YamlNode::Kind::sequence: return "a list";
    case YamlNode::Kind::mapping: return "a mapping";
    case YamlNode::Kind::scalar:
      return (node.quoted() ? "the quoted text '" : "'") + node.text() + "'";
    case YamlNode::Kind::null: return "nothing";
  }
  return "nothing";
}

// A key path in the loader's table of them (Loader::paths_): a value's key or index under the
// value it lies in. Made into text ("links.L1.K[2]") only where a message, a binding or a
// check of validation's findings needs it: a large model has a million keys and reads few.
using PathId = std::uint32_t;
constexpr PathId kWholeFile = 0;  // "", the key path of the file's root

struct PathPart {
  PathId parent = kWholeFile;
  std::uint32_t index = 0;  // within a list, where `key` is empty
  std::string_view key;     // within a mapping: the text of the key's node in the tree
};

// A value in the file with what a message about it needs: its key path and where it is.
struct Value {
  const YamlNode* node;
  PathId path;
  Position at;
};

// One `key: value` of a mapping.
struct Entry {
  std::string key;
  Position key_at;
  Value value;
};

const Entry* find(const std::vector<Entry>& entries, std::string_view key) {
  for (const auto& e : entries)
    if (e.key == key) return &e;
  return nullptr;
}

// An expression of the file, where it stands: what a message about its value needs.
struct ExpressionSite {
  std::string text;
  std::string path;
  SourceLocation at;
};

// A number of the model that an expression of the file fills: the value slot named as the
// structure names it (`links.upper.material.E`, Structure::slot_names()), and the expression
// (an index into the loader's sites()).
struct Binding {
  std::string slot;
  std::size_t site;
};

// Whether key path `path` is `prefix` or lies under it (`prefix.key`, `prefix[i]`).
bool within(const std::string& path, const std::string& prefix) {
  return path.starts_with(prefix) &&
         (path.size() == prefix.size() || path[prefix.size()] == '.' || path[prefix.size()] == '[');
}

// The bindings with each slot that lies within `from` moved to lie within each of `to` (one
// number of the file that fills several slots), the others as they are.
std::vector<Binding> moved(std::span<const Binding> bindings, const std::string& from,
                           const std::vector<std::string>& to) {
  std::vector<Binding> out;
  for (const Binding& b : bindings) {
    if (!within(b.slot, from)) {
      out.push_back(b);
      continue;
    }
    for (const std::string& target : to)
      out.push_back({target + b.slot.substr(from.size()), b.site});
  }
  return out;
}

// `path[i][j]`, an entry of the matrix at `path` as slot names give it.
std::string matrix_entry(const std::string& path, int i, int j) {
  return path + "[" + std::to_string(i) + "][" + std::to_string(j) + "]";
}

// A material or section defined by name, for beams to refer to.
template <class T>
struct Definition {
  T value;
  Origin origin;  // location of the name, key_locations per key
  // The expressions among its numbers, their slots under `materials.NAME` or `sections.NAME`:
  // each beam that names it binds them to its own slots.
  std::vector<Binding> bindings;
};

class Loader {
 public:
  // `expressions` evaluates the file's expressions with `values` (one per parameter), or
  // with the parameters' defaults where `values` is empty; a loader without one makes its own.
  explicit Loader(std::string file, detail::ExpressionEvaluator* expressions = nullptr,
                  std::span<const double> values = {})
      : file_(std::move(file)), expressions_(expressions), values_(values) {}

  Model read(const YamlNode& root);
  const std::vector<Parameter>& parameters() const { return parameters_; }
  const std::vector<std::string>& derived_names() const { return derived_names_; }
  const std::vector<ExpressionSite>& derived_sites() const { return derived_sites_; }

  // A robot block's positions, one per URDF joint: a number, or an expression a builder
  // evaluates for each member before it poses the robot.
  struct RobotPosition {
    double value = 0;
    std::optional<ExpressionSite> expression;
  };
  std::shared_ptr<const detail::RobotLayout> robot() const { return robot_; }
  const std::vector<RobotPosition>& robot_positions() const { return robot_positions_; }

  // Values that replace the file's parameter defaults; names that are no parameter are kept in
  // unknown_settings().
  void set_defaults(const ParameterSettings* settings) { settings_ = settings; }
  const std::vector<std::string>& unknown_settings() const { return unknown_settings_; }

  // Every expression read where a number goes, in reading order, and the value slots of the
  // model that they fill (slot names as Structure::slot_names() gives them): one reading binds
  // a family's expressions. A robot block's joint positions are not among them
  // (robot_positions()).
  const std::vector<ExpressionSite>& sites() const { return sites_; }
  const std::vector<Binding>& bindings() const { return bindings_; }
  // The first expression whose value the reader transforms on its way into the model (a robot
  // joint's compliance is inverted; a robot's gravity, a load or an offset on a robot frame are
  // turned with the pose): no slot holds it, and each member must be read from the file.
  const std::optional<ExpressionSite>& transformed() const { return transformed_; }

  // Adds find_defects()'s diagnostics to the loader's own, leaving out those about values the
  // loader already found wrong or could not read, and returns them all in file order.
  std::vector<Diagnostic> merge(std::vector<Diagnostic> defects);

 private:
  // ---- reporting -------------------------------------------------------------------------

  void fail(const Position& at, const std::string& path, std::string message) {
    diagnostics_.push_back({located(at), path, std::move(message)});
  }
  // A value that could not be read: the model holds a default in its place.
  void fail(const Value& v, std::string message) {
    fail(v.at, path_of(v), std::move(message));
    spoil(v);
  }

  // Marks a part of the model that holds defaults in place of what the file could not give,
  // so validation's findings about those defaults are not reported.
  void spoil(const std::string& path) { spoiled_.insert(path); }
  // The same for a value of the file, whose path is made only if validation finds anything.
  void spoil(const Value& v) { spoiled_values_.push_back(v.path); }

  Position where(const YamlNode& node) const { return position_of(node); }
  SourceLocation located(const Position& at) const { return {file_, at.line, at.column}; }

  PathId add_path(PathPart part) {
    paths_.push_back(part);
    return static_cast<PathId>(paths_.size() - 1);
  }
  std::string path_of(PathId id) const;
  std::string path_of(const Value& v) const { return path_of(v.path); }
  // `key` under the value's path, as text.
  std::string path_of(const Value& v, std::string_view key) const {
    std::string path = path_of(v);
    if (!path.empty()) path += '.';
    path += key;
    return path;
  }

  Value item(const Value& list, std::size_t i) {
    const YamlNode* node = list.node->items()[i];
    return {node, add_path({list.path, static_cast<std::uint32_t>(i), {}}), where(*node)};
  }

  // ---- mappings and keys -----------------------------------------------------------------

  std::optional<std::vector<Entry>> mapping(const Value& v, bool notes_allowed);
  std::vector<Entry> fixed_mapping(const Value& v);
  std::vector<Entry> named_mapping(const Entry& top);
  // `what` names the owner in a message: text, or a function that makes it (made only for one).
  template <class What>
  void check_keys(const std::vector<Entry>& entries, const Value& owner, const KeyList& valid,
                  const KeyList& known, const What& what);
  const Entry* required(const std::vector<Entry>& entries, const Value& owner,
                        std::string_view key);
  void record(Origin& origin, const std::vector<Entry>& entries, const std::string& prefix) const;
  void record_items(Origin& origin, const std::string& key, const Value& list) const;

  // ---- scalars, vectors and matrices -----------------------------------------------------

  std::optional<double> number(const Value& v);
  double given_number(const Value& v);
  // The bindings recorded since `first` (an index into bindings_) that lie within `from` lie
  // within each of `to` instead: where the reader puts the number read at `from`.
  void rebind(std::size_t first, const std::string& from, const std::vector<std::string>& to);
  // The expressions read since `first` feed numbers the reader transforms (transformed()).
  void transformed_since(std::size_t first);
  std::optional<bool> boolean(const Value& v);
  std::optional<std::string> text(const Value& v);
  std::optional<std::string> choice(const Value& v, const KeyList& choices, std::string_view what);
  std::optional<VecX> list(const Value& v);
  std::optional<MatX> matrix(const Value& v);
  std::optional<VecX> vector(const Value& v, int n, std::string_view shape);
  template <int N>
  std::optional<Eigen::Matrix<double, N, 1>> fixed_vector(const Value& v, std::string_view shape);
  template <int N>
  std::optional<std::vector<Eigen::Matrix<double, N, 1>>> vector_list(const Entry& entry,
                                                                      Origin& origin,
                                                                      std::string_view shape);
  template <int N>
  std::optional<Eigen::Matrix<double, N, N>> square_matrix(const Value& v);

  // Checks the values of every named material and section once, where it is defined, used or
  // not; the beams that use one are not checked again.
  void check_definitions();

  // ---- model parts -----------------------------------------------------------------------

  void read_format(const std::vector<Entry>& top, const Value& root);
  void read_name(const std::vector<Entry>& top);
  void read_parameters(const Entry* parameters, const Entry* derived);
  double parameter_default(const Value& v);
  std::optional<double> expression(const Value& v);
  void read_options(const Entry& section);
  void read_materials(const Entry& section);
  void read_sections(const Entry& section);
  void read_points(const Entry& section);
  void read_links(const Entry& section);
  void read_joints(const Entry& section);
  void read_supports(const Entry& section);
  void read_loads(const Entry& section);
  void read_gravity(const Entry& section);
  void read_load_cases(const Entry& section);
  void read_analysis(const Entry& section);
  // Where a list of loads goes: the model's own (the unnamed case) or a named case's.
  struct LoadTarget {
    std::vector<Load>& loads;
    std::vector<LinkLoad>& link_loads;
    std::string model_path;  // the key path validation gives the target: "" or "load_cases.C."
    bool robot_frames;       // whether loads on a robot's frames may stand here
  };
  void read_load_list(const Value& v, const LoadTarget& target);
  void read_point_load(const std::vector<Entry>& e, const Value& entry, const LoadTarget& target);
  void read_link_load(const std::vector<Entry>& e, const Value& entry, const LoadTarget& target);
  std::optional<DistributedLinkLoad> read_distributed(const Entry& entry, Origin& origin);
  void read_end_effectors(const Entry& section);
  void read_robot(const Entry& section);
  std::optional<detail::JointSpring> read_joint_spring(const Value& v);
  std::optional<int> robot_frame(const Entry& frame);
  std::optional<double> robot_position(const Value& v, ExpressionSite& site);

  Material read_material(const Value& v, Origin& origin, const std::string& prefix);
  Section read_section(const Value& v, Origin& origin, const std::string& prefix);
  Link read_link(const Entry& named);
  LinkKind read_link_kind(const std::string& type, const std::vector<Entry>& e, const Value& v,
                          Link& link);
  BeamLink read_beam(const std::vector<Entry>& e, const Value& v, Link& link);
  template <class Kind>
  void read_frame(const std::vector<Entry>& e, Kind& kind);
  template <class T>
  using ReadInline = T (Loader::*)(const Value&, Origin&, const std::string&);
  template <class T>
  T named_or_inline(const Entry& entry, const std::map<std::string, Definition<T>>& named,
                    const std::string& plural, Link& link, ReadInline<T> read_inline);

  struct Site {
    std::string at;
    std::vector<std::string> links;
    Connection connection;
    Origin origin;
    std::optional<Vec6> displacement;  // supports only
  };
  Site read_site(const Entry& named, bool is_support);
  std::optional<JointType> read_site_type(const std::vector<Entry>& e, const Value& v,
                                          const std::string& noun, bool is_support);
  std::vector<std::string> read_site_links(const std::vector<Entry>& e, const Value& v,
                                           bool is_support, Origin& origin);
  std::optional<Kinematics> read_kinematics(JointType type, const std::vector<Entry>& e,
                                            const Value& owner, Origin& origin);
  void read_springs(const std::vector<Entry>& e, int p, const std::string& what, Connection& c);
  std::optional<MatX> read_stiffness(const Value& v, int p, const std::string& what);
  std::optional<VecX> read_preload(const Value& v, int p, const std::string& what);
  std::vector<std::string> read_link_names(const Entry& entry, Origin& origin);
  void read_link_end(const std::vector<Entry>& e, const Value& v, std::string& at,
                     std::optional<std::string>& link);

  std::string file_;
  detail::ExpressionEvaluator* expressions_;
  std::unique_ptr<detail::ExpressionEvaluator> own_expressions_;
  std::span<const double> values_;
  // Whether the file has `parameters:`: only then is text in place of a number an expression.
  bool parametric_ = false;
  std::vector<Parameter> parameters_;
  std::vector<std::string> derived_names_;
  std::vector<ExpressionSite> derived_sites_;
  std::vector<ExpressionSite> sites_;
  std::vector<Binding> bindings_;
  std::optional<ExpressionSite> transformed_;
  const ParameterSettings* settings_ = nullptr;
  std::vector<std::string> unknown_settings_;
  Model model_;
  std::vector<Diagnostic> diagnostics_;
  std::vector<PathPart> paths_{PathPart{}};  // kWholeFile first
  std::set<std::string> spoiled_;
  std::vector<PathId> spoiled_values_;  // joins spoiled_ when validation's findings are merged
  std::map<std::string, Definition<Material>> materials_;
  std::map<std::string, Definition<Section>> sections_;
  // Key paths that validation sees but the file spells differently: a support's single `link`
  // is "supports.S1.links[0]" in the model. Model path → file path.
  std::map<std::string, std::string> aliases_;
  std::vector<Diagnostic> definition_defects_;
  std::shared_ptr<detail::RobotLayout> robot_;
  std::vector<RobotPosition> robot_positions_;
  Position robot_at_;
  bool find_robot_block_ = false;  // the model has `robot:`, read or not
  // Where the keys of the model itself are (`gravity`, `analysis.load_steps`), for validation's
  // messages about them: the Model keeps no origin of its own.
  std::map<std::string, SourceLocation> model_key_locations_;
};

// ---- mappings and keys -------------------------------------------------------------------

std::optional<std::vector<Entry>> Loader::mapping(const Value& v, bool notes_allowed) {
  if (!v.node->is_mapping()) {
    fail(v, "expected a mapping of key: value, got " + describe(*v.node));
    return std::nullopt;
  }
  std::vector<Entry> entries;
  entries.reserve(v.node->size());
  // The line of each key's first appearance. The points or links of a large model are one
  // mapping of 100 000 keys: a scan of the keys before each one would take minutes; a few keys
  // are scanned, without a map of their own.
  constexpr std::size_t kKeysScanned = 16;
  const bool scanned = v.node->size() <= kKeysScanned;
  std::unordered_map<std::string, int> first_lines;
  for (const auto& [key, value] : v.node->entries()) {
    const Position key_at = where(*key);
    if (!key->is_scalar() || key->text().empty()) {
      fail(key_at, path_of(v), "a key must be a non-empty name, got " + describe(*key));
      continue;
    }
    const std::string& name = key->text();
    if (notes_allowed && name.rfind("x-", 0) == 0) continue;
    std::optional<int> first_line;  // where the key is a duplicate
    if (scanned) {
      const auto first = std::find_if(entries.begin(), entries.end(),
                                      [&](const Entry& e) { return e.key == name; });
      if (first != entries.end()) first_line = first->key_at.line;
    } else if (const auto [first, is_new] = first_lines.try_emplace(name, key_at.line); !is_new) {
      first_line = first->second;
    }
    if (first_line) {
      fail(key_at, path_of(v, name),
           "duplicate key '" + name + "' (first given at line " + std::to_string(*first_line) +
               "); give each key once");
      continue;
    }
    // A key with nothing after it has a value placed on the following line; the key is where
    // the user looks.
    const PathId path = add_path({v.path, 0, name});
    entries.push_back({name, key_at, {value, path, value->is_null() ? key_at : where(*value)}});
  }
  return entries;
}

// A mapping whose keys the format fixes: `x-` keys are the user's notes.
std::vector<Entry> Loader::fixed_mapping(const Value& v) {
  return mapping(v, true).value_or(std::vector<Entry>{});
}

// A top-level mapping of user-chosen names (points, links, ...); left out or empty is none.
std::vector<Entry> Loader::named_mapping(const Entry& top) {
  if (top.value.node->is_null()) return {};
  return mapping(top.value, false).value_or(std::vector<Entry>{});
}

template <class What>
void Loader::check_keys(const std::vector<Entry>& entries, const Value& owner, const KeyList& valid,
                        const KeyList& known, const What& what) {
  for (const auto& e : entries) {
    if (contains(valid, e.key)) continue;
    const std::string key_path = path_of(owner, e.key);
    std::string owner_name;
    if constexpr (std::is_invocable_v<What>)
      owner_name = what();
    else
      owner_name = what;
    if (contains(known, e.key))
      fail(e.key_at, key_path,
           "key '" + e.key + "' does not apply to " + owner_name +
               "; valid keys are: " + detail::comma_list(valid));
    else
      fail(e.key_at, key_path,
           "unknown key '" + e.key + "'" + detail::suggestion(e.key, valid, "valid keys are"));
  }
}

const Entry* Loader::required(const std::vector<Entry>& entries, const Value& owner,
                              std::string_view key) {
  if (const Entry* e = find(entries, key)) return e;
  const std::string path = path_of(owner, key);
  fail(owner.at, path, "missing key '" + std::string(key) + "'");
  spoil(path);
  return nullptr;
}

std::string Loader::path_of(PathId id) const {
  std::vector<PathId> chain;  // from the value up to the whole file, which has no text
  for (; id != kWholeFile; id = paths_[id].parent) chain.push_back(id);
  std::string path;
  for (auto part = chain.rbegin(); part != chain.rend(); ++part) {
    const PathPart& p = paths_[*part];
    if (p.key.empty()) {
      path += '[';
      path += std::to_string(p.index);
      path += ']';
    } else {
      if (!path.empty()) path += '.';
      path += p.key;
    }
  }
  return path;
}

void Loader::record(Origin& origin, const std::vector<Entry>& entries,
                    const std::string& prefix) const {
  origin.key_locations.reserve(origin.key_locations.size() + entries.size());
  for (const auto& e : entries)
    origin.key_locations.push_back({prefix + e.key, e.key_at.line, e.key_at.column});
}

void Loader::record_items(Origin& origin, const std::string& key, const Value& list) const {
  if (!list.node->is_sequence()) return;
  for (std::size_t i = 0; i < list.node->size(); ++i)
    origin.record(key + "[" + std::to_string(i) + "]", located(where(*list.node->items()[i])));
}

// ---- scalars, vectors and matrices -------------------------------------------------------

std::optional<double> Loader::number(const Value& v) {
  if (parametric_ && v.node->is_scalar()) return expression(v);
  // A quoted "2e11" is text: accepting it would hide a value meant as something else.
  if (!v.node->is_scalar() || v.node->quoted()) {
    std::string hint;
    if (v.node->is_scalar())
      hint = "; a number written as an expression needs the file's `parameters:`";
    fail(v, "expected a number, got " + describe(*v.node) + hint);
    return std::nullopt;
  }
  const std::string& text = v.node->text();
  const char* begin = text.data() + (text.rfind('+', 0) == 0 ? 1 : 0);
  const char* end = text.data() + text.size();
  double value = 0;
  const auto [stop, error] = std::from_chars(begin, end, value);
  const bool read_whole = error == std::errc() && stop == end;
  const bool sign_after_plus = begin != text.data() && begin != end && *begin == '-';
  if (read_whole && std::isfinite(value) && !sign_after_plus) return value;
  // YAML spells them .nan and .inf; from_chars reads nan and inf.
  const bool yaml_special =
      text.find(".nan") != std::string::npos || text.find(".NaN") != std::string::npos ||
      text.find(".NAN") != std::string::npos || text.find(".inf") != std::string::npos ||
      text.find(".Inf") != std::string::npos || text.find(".INF") != std::string::npos;
  if (yaml_special || (read_whole && !std::isfinite(value))) {
    fail(v, "expected a finite number, got '" + text + "'");
    return std::nullopt;
  }
  if (error == std::errc::result_out_of_range) {
    fail(v, "the number '" + text + "' is out of range");
    return std::nullopt;
  }
  if (error != std::errc() || stop != end || sign_after_plus) {
    fail(v, "expected a number, got " + describe(*v.node) +
                "; a number written as an expression needs the file's `parameters:`");
    return std::nullopt;
  }
  return value;
}

// A number of a parametric file: a plain number is read as one, anything else is an expression
// of the parameters (a plain number is an expression too, but reading it directly keeps
// `2e11` exactly what it says).
std::optional<double> Loader::expression(const Value& v) {
  const std::string& text = v.node->text();
  if (const auto value = detail::plain_number(text)) return value;
  // The key path is the name of the slot the number fills; where the reader puts it elsewhere
  // or in several slots (a named material, a load, a scalar spring), it rebinds it.
  bindings_.push_back({path_of(v), sites_.size()});
  sites_.push_back({text, path_of(v), located(v.at)});
  const auto outcome = expressions_->evaluate(text);
  if (outcome.follows_earlier_error) {
    spoil(v);  // the derived value it uses is reported where it is defined
    return std::nullopt;
  }
  if (!outcome.error.empty()) {
    fail(v, outcome.error);
    return std::nullopt;
  }
  return outcome.value;
}

void Loader::rebind(std::size_t first, const std::string& from,
                    const std::vector<std::string>& to) {
  if (first == bindings_.size()) return;
  std::vector<Binding> rebound = moved(std::span(bindings_).subspan(first), from, to);
  bindings_.resize(first);
  bindings_.insert(bindings_.end(), std::make_move_iterator(rebound.begin()),
                   std::make_move_iterator(rebound.end()));
}

void Loader::transformed_since(std::size_t first) {
  if (first == bindings_.size()) return;
  if (!transformed_) transformed_ = sites_[bindings_[first].site];
  bindings_.resize(first);
}

// A number whose key is given: NaN where it cannot be read, so that the model shows the key
// was there (an unreadable nu is still "nu given", not "neither nu nor G").
double Loader::given_number(const Value& v) {
  return number(v).value_or(std::numeric_limits<double>::quiet_NaN());
}

std::optional<bool> Loader::boolean(const Value& v) {
  if (v.node->is_scalar() && !v.node->quoted()) {
    const std::string& s = v.node->text();
    if (s == "true" || s == "True" || s == "TRUE") return true;
    if (s == "false" || s == "False" || s == "FALSE") return false;
  }
  fail(v, "expected true or false, got " + describe(*v.node));
  return std::nullopt;
}

std::optional<std::string> Loader::text(const Value& v) {
  if (v.node->is_scalar() && !v.node->text().empty()) return v.node->text();
  fail(v, "expected a name, got " + describe(*v.node));
  return std::nullopt;
}

std::optional<std::string> Loader::choice(const Value& v, const KeyList& choices,
                                          std::string_view what) {
  const auto chosen = text(v);
  if (!chosen) return std::nullopt;
  if (contains(choices, *chosen)) return chosen;
  fail(v, "unknown " + std::string(what) + " '" + *chosen + "'" +
              detail::suggestion(*chosen, choices, "valid values are"));
  return std::nullopt;
}

// A list of numbers of any length; every bad entry is reported.
std::optional<VecX> Loader::list(const Value& v) {
  if (!v.node->is_sequence()) {
    fail(v, "expected a list of numbers, got " + describe(*v.node));
    return std::nullopt;
  }
  VecX values(static_cast<Eigen::Index>(v.node->size()));
  bool all_read = true;
  for (std::size_t i = 0; i < v.node->size(); ++i) {
    const auto x = number(item(v, i));
    if (x) values(static_cast<Eigen::Index>(i)) = *x;
    all_read = all_read && x.has_value();
  }
  if (!all_read) {
    spoil(v);
    return std::nullopt;
  }
  return values;
}

// A list of rows of numbers, all of one length.
std::optional<MatX> Loader::matrix(const Value& v) {
  if (!v.node->is_sequence() || v.node->size() == 0 || !v.node->items()[0]->is_sequence()) {
    fail(v, "expected a matrix (a list of rows, each a list of numbers), got " + describe(*v.node));
    return std::nullopt;
  }
  const auto rows = static_cast<Eigen::Index>(v.node->size());
  const auto cols = static_cast<Eigen::Index>(v.node->items()[0]->size());
  MatX m(rows, cols);
  bool all_read = true;
  for (Eigen::Index i = 0; i < rows; ++i) {
    const Value row_value = item(v, static_cast<std::size_t>(i));
    const auto row = list(row_value);
    if (row && row->size() != cols) {
      fail(row_value, "row " + std::to_string(i) + " has " + std::to_string(row->size()) +
                          " values, row 0 has " + std::to_string(cols));
      all_read = false;
    } else if (row) {
      m.row(i) = row->transpose();
    }
    all_read = all_read && row.has_value();
  }
  if (!all_read) {
    spoil(v);
    return std::nullopt;
  }
  return m;
}

// `shape` says in a message what the n values are, e.g. "[x, y, z]".
std::optional<VecX> Loader::vector(const Value& v, int n, std::string_view shape) {
  if (!v.node->is_sequence()) {
    fail(v, "expected a list of " + counted(static_cast<std::size_t>(n), "number") + " " +
                std::string(shape) + ", got " + describe(*v.node));
    return std::nullopt;
  }
  if (v.node->size() != static_cast<std::size_t>(n)) {
    fail(v, "expected " + counted(static_cast<std::size_t>(n), "number") + " " +
                std::string(shape) + ", got " + std::to_string(v.node->size()));
    list(v);  // its entries may be wrong too
    return std::nullopt;
  }
  return list(v);
}

template <int N>
std::optional<Eigen::Matrix<double, N, 1>> Loader::fixed_vector(const Value& v,
                                                                std::string_view shape) {
  if (auto values = vector(v, N, shape)) return Eigen::Matrix<double, N, 1>(*values);
  return std::nullopt;
}

// A list of N-vectors, such as a universal joint's axes; the origin gets each one's location
// under the list's key.
template <int N>
std::optional<std::vector<Eigen::Matrix<double, N, 1>>> Loader::vector_list(
    const Entry& entry, Origin& origin, std::string_view shape) {
  const Value& v = entry.value;
  if (!v.node->is_sequence()) {
    fail(v, "expected a list of vectors " + std::string(shape) + ", got " + describe(*v.node));
    return std::nullopt;
  }
  record_items(origin, entry.key, v);
  std::vector<Eigen::Matrix<double, N, 1>> vectors;
  for (std::size_t i = 0; i < v.node->size(); ++i)
    if (auto x = fixed_vector<N>(item(v, i), shape)) vectors.push_back(*x);
  if (vectors.size() != v.node->size()) return std::nullopt;
  return vectors;
}

template <int N>
std::optional<Eigen::Matrix<double, N, N>> Loader::square_matrix(const Value& v) {
  auto m = matrix(v);
  if (!m) return std::nullopt;
  if (m->rows() != N || m->cols() != N) {
    fail(v, "expected a " + std::to_string(N) + "×" + std::to_string(N) + " matrix, got " +
                std::to_string(m->rows()) + "×" + std::to_string(m->cols()));
    return std::nullopt;
  }
  return Eigen::Matrix<double, N, N>(*m);
}

// ---- the model ---------------------------------------------------------------------------

Model Loader::read(const YamlNode& root) {
  model_.source_file = file_;
  const Value whole{&root, kWholeFile, where(root)};
  if (!root.is_mapping()) {
    const std::string start =
        std::string("a model file is a mapping that starts with `format: ") + kFormat + "`";
    if (root.is_null())
      fail(Position{1, 1}, "", "the file is empty; " + start);
    else
      fail(whole, start + "; got " + describe(root));
    spoil("");
    return std::move(model_);
  }
  const auto top = fixed_mapping(whole);
  check_keys(top, whole, kTopKeys, {}, "a model");
  read_format(top, whole);
  read_name(top);
  const Entry* parameters = find(top, "parameters");
  const Entry* derived = find(top, "derived");
  find_robot_block_ = find(top, "robot") != nullptr;
  if (parameters || derived) read_parameters(parameters, derived);
  // Materials and sections first: links refer to them wherever they stand in the file.
  using Part = void (Loader::*)(const Entry&);
  const std::pair<const char*, Part> parts[] = {{"options", &Loader::read_options},
                                                {"analysis", &Loader::read_analysis},
                                                {"materials", &Loader::read_materials},
                                                {"sections", &Loader::read_sections},
                                                {"robot", &Loader::read_robot},
                                                {"points", &Loader::read_points},
                                                {"links", &Loader::read_links},
                                                {"joints", &Loader::read_joints},
                                                {"supports", &Loader::read_supports},
                                                {"loads", &Loader::read_loads},
                                                {"gravity", &Loader::read_gravity},
                                                {"load_cases", &Loader::read_load_cases},
                                                {"end_effectors", &Loader::read_end_effectors}};
  for (const auto& [key, read_part] : parts)
    if (const Entry* e = find(top, key)) (this->*read_part)(*e);
  if (robot_) {
    robot_->fold_tool_links(model_);
    std::vector<double> positions;
    for (const auto& p : robot_positions_) positions.push_back(p.value);
    robot_->pose(positions, model_);
  }
  check_definitions();
  return std::move(model_);
}

void Loader::read_format(const std::vector<Entry>& top, const Value& root) {
  const Entry* e = find(top, "format");
  if (!e) {
    fail(root.at, "format",
         std::string("missing key 'format'; a model file declares `format: ") + kFormat + "`");
    return;
  }
  const auto format = text(e->value);
  if (format && *format != kFormat)
    fail(e->value,
         "unsupported format '" + *format + "'; this version reads `format: " + kFormat + "`");
}

void Loader::read_name(const std::vector<Entry>& top) {
  if (const Entry* e = find(top, "name")) {
    if (auto name = text(e->value)) model_.name = *name;
    return;
  }
  const std::string stem = std::filesystem::path(file_).stem().string();
  if (!stem.empty()) model_.name = stem;
}

// A parameter's default: a plain number (the file's other numbers may be expressions).
double Loader::parameter_default(const Value& v) {
  if (v.node->is_scalar())
    if (const auto value = detail::plain_number(v.node->text())) return *value;
  fail(v, "a parameter's default is a plain finite number, got " + describe(*v.node) +
              "; a value computed from parameters belongs in `derived:`");
  return 0;
}

// Parameters are read before anything that may use them. Their defaults are plain numbers:
// an expression here would make the file's meaning depend on the order of its keys.
void Loader::read_parameters(const Entry* parameters, const Entry* derived) {
  std::vector<std::string> names;
  std::vector<double> defaults;
  const std::vector<Entry> parameter_entries =
      parameters ? named_mapping(*parameters) : std::vector<Entry>{};
  for (const auto& named : parameter_entries) {
    Parameter parameter{named.key, 0, {}, located(named.key_at)};
    if (auto problem = detail::parameter_name_problem(named.key)) {
      fail(named.key_at, path_of(named.value), *problem);
      continue;
    }
    if (named.value.node->is_mapping()) {
      const auto e = fixed_mapping(named.value);
      check_keys(e, named.value, kParameterKeys, {}, "a parameter");
      if (const Entry* d = required(e, named.value, "default"))
        parameter.default_value = parameter_default(d->value);
      if (const Entry* unit = find(e, "unit")) parameter.unit = text(unit->value).value_or("");
    } else if (named.value.node->is_scalar()) {
      parameter.default_value = parameter_default(named.value);
    } else {
      fail(named.value, "expected a number or {default: number, unit: text}, got " +
                            describe(*named.value.node));
    }
    names.push_back(parameter.name);
    defaults.push_back(parameter.default_value);
    parameters_.push_back(std::move(parameter));
  }
  parametric_ = true;
  if (settings_) {
    for (const auto& [name, value] : *settings_) {
      const auto found = std::find(names.begin(), names.end(), name);
      if (found == names.end()) {
        unknown_settings_.push_back(name);
        continue;
      }
      const auto index = static_cast<std::size_t>(found - names.begin());
      defaults[index] = value;
      parameters_[index].default_value = value;
      parameters_[index].set = true;
    }
  }
  for (const Parameter& p : parameters_)
    model_.parameters.push_back({p.name, p.default_value, p.unit, p.set});
  std::vector<Entry> derived_entries;
  for (auto& named : derived ? named_mapping(*derived) : std::vector<Entry>{}) {
    if (auto problem = detail::parameter_name_problem(named.key)) {
      fail(named.key_at, path_of(named.value), *problem);
    } else if (std::find(names.begin(), names.end(), named.key) != names.end()) {
      fail(named.key_at, path_of(named.value),
           "'" + named.key + "' is a parameter already; give the derived value another name");
    } else if (!named.value.node->is_scalar()) {
      fail(named.value,
           "expected an expression of the parameters, got " + describe(*named.value.node));
    } else {
      derived_names_.push_back(named.key);
      derived_sites_.push_back(
          {named.value.node->text(), path_of(named.value), located(named.value.at)});
      derived_entries.push_back(std::move(named));
    }
  }
  if (!expressions_) {
    own_expressions_ = std::make_unique<detail::ExpressionEvaluator>(names, derived_names_);
    expressions_ = own_expressions_.get();
  }
  expressions_->set_values(values_.empty() ? std::span<const double>(defaults) : values_);
  for (std::size_t i = 0; i < derived_entries.size(); ++i) {
    const auto outcome = expressions_->evaluate_derived(i, derived_entries[i].value.node->text());
    if (outcome.follows_earlier_error)
      spoil(derived_entries[i].value);
    else if (!outcome.error.empty())
      fail(derived_entries[i].value, outcome.error);
  }
}

void Loader::read_options(const Entry& section) {
  if (section.value.node->is_null()) return;  // `options:` alone sets nothing
  const auto e = fixed_mapping(section.value);
  check_keys(e, section.value, kOptionKeys, {}, "options");
  if (const Entry* idle = find(e, "accept_idle_motions"))
    model_.options.accept_idle_motions = boolean(idle->value).value_or(false);
}

// ---- materials and sections --------------------------------------------------------------

Material Loader::read_material(const Value& v, Origin& origin, const std::string& prefix) {
  Material m;
  const auto e = fixed_mapping(v);
  check_keys(e, v, kMaterialKeys, {}, "a material");
  record(origin, e, prefix);
  if (const Entry* E = required(e, v, "E")) m.E = given_number(E->value);
  if (const Entry* nu = find(e, "nu")) m.nu = given_number(nu->value);
  if (const Entry* G = find(e, "G")) m.G = given_number(G->value);
  if (const Entry* density = find(e, "density")) m.density = given_number(density->value);
  return m;
}

Section Loader::read_section(const Value& v, Origin& origin, const std::string& prefix) {
  Section s;
  const auto e = fixed_mapping(v);
  record(origin, e, prefix);
  if (const Entry* shape = find(e, "shape")) {
    const auto name = choice(shape->value, section_shape_names(), "section shape");
    if (!name) {
      // Which dimensions belong here is unknown, so only unknown keys can be told.
      check_keys(e, v, kSectionKeys, {}, "a section");
      spoil(v);
      return s;
    }
    s.shape = *section_shape_from_string(*name);
  }
  KeyList valid{"shape"};
  for (const auto& dimension : detail::section_dimensions(s.shape)) valid.push_back(dimension.key);
  valid = valid + KeyList{"Asy", "Asz"};
  check_keys(e, v, valid, kSectionKeys, std::string("a ") + to_string(s.shape) + " section");
  for (const auto& dimension : detail::section_dimensions(s.shape))
    if (const Entry* d = required(e, v, dimension.key)) s.*dimension.value = given_number(d->value);
  if (const Entry* a = find(e, "Asy")) s.Asy = given_number(a->value);
  if (const Entry* a = find(e, "Asz")) s.Asz = given_number(a->value);
  return s;
}

void Loader::read_materials(const Entry& section) {
  for (const auto& named : named_mapping(section)) {
    Definition<Material> material;
    material.origin.location = located(named.key_at);
    const std::size_t first = bindings_.size();
    material.value = read_material(named.value, material.origin, "");
    material.bindings.assign(bindings_.begin() + static_cast<std::ptrdiff_t>(first),
                             bindings_.end());
    bindings_.resize(first);
    materials_.emplace(named.key, std::move(material));
  }
}

void Loader::read_sections(const Entry& section) {
  for (const auto& named : named_mapping(section)) {
    Definition<Section> s;
    s.origin.location = located(named.key_at);
    const std::size_t first = bindings_.size();
    s.value = read_section(named.value, s.origin, "");
    s.bindings.assign(bindings_.begin() + static_cast<std::ptrdiff_t>(first), bindings_.end());
    bindings_.resize(first);
    sections_.emplace(named.key, std::move(s));
  }
}

// ---- points and links --------------------------------------------------------------------

void Loader::read_points(const Entry& section) {
  for (const auto& named : named_mapping(section)) {
    const auto position = fixed_vector<3>(named.value, "[x, y, z]");
    // An unreadable position is left undefined so that validation measures nothing from it.
    model_.points.push_back(
        {named.key, position.value_or(Vec3::Constant(std::numeric_limits<double>::quiet_NaN())),
         Origin{located(named.key_at), {}}});
  }
}

void Loader::read_links(const Entry& section) {
  for (const auto& named : named_mapping(section)) model_.links.push_back(read_link(named));
}

Link Loader::read_link(const Entry& named) {
  Link link;
  link.name = named.key;
  link.kind = RigidLink{};  // stands in when the type cannot be read
  link.origin.location = located(named.key_at);
  const Value& v = named.value;
  const auto e = fixed_mapping(v);
  record(link.origin, e, "");
  if (!v.node->is_mapping()) return link;
  std::optional<std::string> type;
  if (const Entry* t = required(e, v, "type")) type = choice(t->value, kLinkTypes, "link type");
  check_keys(e, v, type ? link_keys(*type) : kLinkKeys, kLinkKeys,
             [&] { return type ? "a " + *type + " link" : std::string("a link"); });
  if (const Entry* from = required(e, v, "from")) link.from = text(from->value).value_or("");
  if (const Entry* to = required(e, v, "to")) link.to = text(to->value).value_or("");
  if (type) link.kind = read_link_kind(*type, e, v, link);
  return link;
}

LinkKind Loader::read_link_kind(const std::string& type, const std::vector<Entry>& e,
                                const Value& v, Link& link) {
  if (type == "beam") return read_beam(e, v, link);
  if (type == "matrix") {
    MatrixLink m;
    if (const Entry* K = required(e, v, "K")) m.K = square_matrix<12>(K->value).value_or(m.K);
    read_frame(e, m);
    return m;
  }
  if (type == "compliance") {
    ComplianceLink c;
    if (const Entry* C = required(e, v, "C")) c.C = square_matrix<6>(C->value).value_or(c.C);
    read_frame(e, c);
    return c;
  }
  return RigidLink{};
}

// `frame` and `zref` of a matrix or compliance link.
template <class Kind>
void Loader::read_frame(const std::vector<Entry>& e, Kind& kind) {
  if (const Entry* f = find(e, "frame"))
    if (auto frame = choice(f->value, kFrames, "frame"))
      kind.frame = *frame == "local" ? LinkFrame::local : LinkFrame::global;
  if (const Entry* z = find(e, "zref")) {
    if (kind.frame != LinkFrame::local)
      fail(z->key_at, path_of(z->value),
           "zref applies only with frame: local (it fixes the local axes)");
    else
      kind.zref = fixed_vector<3>(z->value, "[x, y, z]");
  }
}

BeamLink Loader::read_beam(const std::vector<Entry>& e, const Value& v, Link& link) {
  BeamLink beam;
  if (const Entry* m = required(e, v, "material"))
    beam.material = named_or_inline(*m, materials_, "materials", link, &Loader::read_material);
  if (const Entry* s = required(e, v, "section"))
    beam.section = named_or_inline(*s, sections_, "sections", link, &Loader::read_section);
  if (const Entry* shear = find(e, "shear")) beam.shear = boolean(shear->value).value_or(false);
  if (const Entry* z = find(e, "zref")) beam.zref = fixed_vector<3>(z->value, "[x, y, z]");
  return beam;
}

// A beam's material or section: a name defined under `plural`, or an inline mapping. The
// link's origin gets the definition's key locations, so validation points at the values.
template <class T>
T Loader::named_or_inline(const Entry& entry, const std::map<std::string, Definition<T>>& named,
                          const std::string& plural, Link& link, ReadInline<T> read_inline) {
  if (entry.value.node->is_mapping())
    return (this->*read_inline)(entry.value, link.origin, entry.key + ".");
  const auto name = text(entry.value);
  if (!name) return T{};
  const auto found = named.find(*name);
  if (found == named.end()) {
    KeyList names;
    for (const auto& [n, unused] : named) names.push_back(n);
    fail(entry.value, "no " + entry.key + " named '" + *name + "' under " + plural +
                          detail::suggestion(*name, names, plural + " are"));
    return T{};
  }
  const auto& definition = found->second.origin.key_locations;
  link.origin.key_locations.reserve(link.origin.key_locations.size() + definition.size());
  for (const auto& at : definition)
    link.origin.key_locations.push_back({entry.key + "." + at.key, at.line, at.column});
  if (!found->second.bindings.empty()) {
    const auto bound = moved(found->second.bindings, plural + "." + *name, {path_of(entry.value)});
    bindings_.insert(bindings_.end(), bound.begin(), bound.end());
  }
  spoil(entry.value);  // checked at its definition
  return found->second.value;
}

// ---- joints and supports -----------------------------------------------------------------

// Joints and supports share every key but how they name their links (model-format.md).
Loader::Site Loader::read_site(const Entry& named, bool is_support) {
  Site site;
  site.origin.location = located(named.key_at);
  const Value& v = named.value;
  const auto e = fixed_mapping(v);
  record(site.origin, e, "");
  if (!v.node->is_mapping()) return site;
  const std::string noun = is_support ? "support" : "joint";
  const auto type = read_site_type(e, v, noun, is_support);
  if (const Entry* at = required(e, v, "at")) site.at = text(at->value).value_or("");
  site.links = read_site_links(e, v, is_support, site.origin);
  if (const Entry* actuated = find(e, "actuated"))
    site.connection.is_actuated = boolean(actuated->value).value_or(false);
  if (const Entry* d = is_support ? find(e, "displacement") : nullptr)
    site.displacement = fixed_vector<6>(d->value, "[dx, dy, dz, rx, ry, rz]");
  if (!type) return site;
  // Without its free directions, p is unknown and the springs cannot be sized.
  const auto kinematics = read_kinematics(*type, e, v, site.origin);
  if (!kinematics) return site;
  site.connection.kinematics = *kinematics;
  read_springs(e, free_direction_count(*kinematics),
               std::string("a ") + to_string(*type) + " " + noun, site.connection);
  return site;
}

// The type of a joint or support, with its keys checked against it.
std::optional<JointType> Loader::read_site_type(const std::vector<Entry>& e, const Value& v,
                                                const std::string& noun, bool is_support) {
  const KeyList common = is_support ? KeyList{"type", "at", "link", "links", "displacement"}
                                    : KeyList{"type", "at", "links"};
  const KeyList known = common + KeyList{"axis", "axes", "normal", "free"} + kSpringKeys;
  std::optional<JointType> type;
  if (const Entry* t = required(e, v, "type"))
    if (auto name = choice(t->value, joint_type_names(), noun + " type"))
      type = joint_type_from_string(*name);
  if (!type) {
    check_keys(e, v, known, {}, "a " + noun);
    return std::nullopt;
  }
  // A rigid joint has no free directions to spring, preload or actuate.
  const KeyList springs = *type == JointType::rigid ? KeyList{} : kSpringKeys;
  check_keys(e, v, common + parameter_keys(*type) + springs, known,
             std::string("a ") + to_string(*type) + " " + noun);
  return type;
}

// A joint's `links`; a support's `link` or `links`, or neither for every end at its point.
std::vector<std::string> Loader::read_site_links(const std::vector<Entry>& e, const Value& v,
                                                 bool is_support, Origin& origin) {
  const Entry* links = is_support ? find(e, "links") : required(e, v, "links");
  const Entry* link = is_support ? find(e, "link") : nullptr;
  if (link && links)
    fail(link->key_at, path_of(link->value), "give either link or links, not both");
  if (links) return read_link_names(*links, origin);
  if (!link) return {};
  aliases_.emplace(path_of(v) + ".links[0]", path_of(link->value));
  origin.record("links[0]", located(link->key_at));
  return {text(link->value).value_or("")};
}

std::vector<std::string> Loader::read_link_names(const Entry& entry, Origin& origin) {
  const Value& v = entry.value;
  if (!v.node->is_sequence()) {
    fail(v, "expected a list of link names, got " + describe(*v.node));
    return {};
  }
  record_items(origin, entry.key, v);
  std::vector<std::string> names;
  for (std::size_t i = 0; i < v.node->size(); ++i) names.push_back(text(item(v, i)).value_or(""));
  return names;
}

std::optional<Kinematics> Loader::read_kinematics(JointType type, const std::vector<Entry>& e,
                                                  const Value& owner, Origin& origin) {
  const auto axis = [&](const std::string& key) -> std::optional<Vec3> {
    const Entry* a = required(e, owner, key);
    return a ? fixed_vector<3>(a->value, "[x, y, z]") : std::nullopt;
  };
  switch (type) {
    case JointType::rigid: return Kinematics::rigid();
    case JointType::spherical: return Kinematics::spherical();
    case JointType::revolute:
      if (auto a = axis("axis")) return Kinematics::revolute(*a);
      return std::nullopt;
    case JointType::prismatic:
      if (auto a = axis("axis")) return Kinematics::prismatic(*a);
      return std::nullopt;
    case JointType::cylindrical:
      if (auto a = axis("axis")) return Kinematics::cylindrical(*a);
      return std::nullopt;
    case JointType::planar:
      if (auto n = axis("normal")) return Kinematics::planar(*n);
      return std::nullopt;
    case JointType::universal: {
      const Entry* axes = required(e, owner, "axes");
      const auto both = axes ? vector_list<3>(*axes, origin, "[x, y, z]") : std::nullopt;
      if (both && both->size() == 2) return Kinematics::universal((*both)[0], (*both)[1]);
      if (both)
        fail(axes->value,
             "expected two axes [[x, y, z], [x, y, z]], got " + std::to_string(both->size()));
      return std::nullopt;
    }
    case JointType::custom: {
      const Entry* free = required(e, owner, "free");
      auto rows = free ? vector_list<6>(*free, origin, "[dx, dy, dz, rx, ry, rz]") : std::nullopt;
      if (rows) return Kinematics::custom(std::move(*rows));
      return std::nullopt;
    }
  }
  return std::nullopt;
}

void Loader::read_springs(const std::vector<Entry>& e, int p, const std::string& what,
                          Connection& c) {
  if (p == 0) return;  // a rigid joint's spring keys were refused by check_keys
  if (const Entry* k = find(e, "stiffness")) c.stiffness = read_stiffness(k->value, p, what);
  if (const Entry* f = find(e, "preload")) c.preload = read_preload(f->value, p, what);
}

// Model-format.md: a scalar k means k·I, a list of p values the diagonal, else a p×p matrix.
std::optional<MatX> Loader::read_stiffness(const Value& v, int p, const std::string& what) {
  const std::string sized = "p = " + std::to_string(p) + " for " + what;
  const std::size_t first = bindings_.size();
  if (v.node->is_scalar()) {
    const auto k = number(v);
    if (!k) return std::nullopt;
    std::vector<std::string> diagonal;
    for (int i = 0; i < p; ++i) diagonal.push_back(matrix_entry(path_of(v), i, i));
    rebind(first, path_of(v), diagonal);
    return MatX(*k * MatX::Identity(p, p));
  }
  const bool rows_given =
      v.node->is_sequence() && v.node->size() > 0 && v.node->items()[0]->is_sequence();
  if (!rows_given) {
    const auto diagonal = vector(v, p, "(the diagonal; " + sized + ")");
    if (!diagonal) return std::nullopt;
    for (int i = 0; i < p; ++i)
      rebind(first, path_of(v) + "[" + std::to_string(i) + "]", {matrix_entry(path_of(v), i, i)});
    return MatX(diagonal->asDiagonal());
  }
  const auto k = matrix(v);
  if (k && (k->rows() != p || k->cols() != p)) {
    fail(v, "expected a p×p stiffness matrix (" + sized + "), got " + std::to_string(k->rows()) +
                "×" + std::to_string(k->cols()));
    return std::nullopt;
  }
  return k;
}

// Model-format.md: a list of p values; a scalar only where p = 1.
std::optional<VecX> Loader::read_preload(const Value& v, int p, const std::string& what) {
  const std::string sized = "p = " + std::to_string(p) + " for " + what;
  if (v.node->is_scalar() && p == 1) {
    const std::size_t first = bindings_.size();
    const auto f = number(v);
    if (!f) return std::nullopt;
    rebind(first, path_of(v), {path_of(v) + "[0]"});
    return VecX::Constant(1, *f);
  }
  return vector(v, p, "(one per free direction; " + sized + ")");
}

void Loader::read_joints(const Entry& section) {
  for (const auto& named : named_mapping(section)) {
    Site site = read_site(named, false);
    model_.joints.push_back({named.key, std::move(site.at), std::move(site.links),
                             std::move(site.connection), std::move(site.origin)});
  }
}

void Loader::read_supports(const Entry& section) {
  for (const auto& named : named_mapping(section)) {
    Site site = read_site(named, true);
    model_.supports.push_back({named.key, std::move(site.at), std::move(site.links),
                               std::move(site.connection), std::move(site.origin),
                               site.displacement});
  }
}

// ---- loads and end effectors -------------------------------------------------------------

void Loader::read_loads(const Entry& section) {
  read_load_list(section.value, {model_.loads, model_.link_loads, "", true});
}

// A list of loads: on points (`{at, link?, wrench, self_weight?}`, or on a robot's frame) and
// along links (`{link, distributed}`, `{link, force, moment?, position}`), told apart by their
// keys. The model keeps the two kinds in lists of their own: validation's key paths
// (`link_loads[0]`) are aliased to the file's (`loads[3]`).
void Loader::read_load_list(const Value& v, const LoadTarget& target) {
  if (v.node->is_null()) return;
  if (!v.node->is_sequence()) {
    fail(v, "expected a list of loads, e.g. `- {at: E, wrench: [0, -100, 0, 0, 0, 0]}`; got " +
                describe(*v.node));
    return;
  }
  for (std::size_t i = 0; i < v.node->size(); ++i) {
    const Value entry = item(v, i);
    const auto e = fixed_mapping(entry);
    KeyList point_keys, link_keys;
    for (const auto& key : e) {
      if (contains(kLinkLoadOnlyKeys, key.key)) link_keys.push_back(key.key);
      if (contains(kLoadKeys + kFrameLoadKeys, key.key) && key.key != "link")
        point_keys.push_back(key.key);
    }
    if (!link_keys.empty() && !point_keys.empty()) {
      fail(entry,
           "a load is either on a point ({at, link, wrench, self_weight}) or along a link "
           "({link, distributed} or {link, force, moment, position}); this one gives " +
               detail::comma_list(point_keys) + " with " + detail::comma_list(link_keys));
      continue;
    }
    const std::size_t first = bindings_.size();
    if (!link_keys.empty()) {
      const std::size_t index = target.link_loads.size();
      read_link_load(e, entry, target);
      const std::string model_path =
          target.model_path + "link_loads[" + std::to_string(index) + "]";
      if (target.link_loads.size() > index) {
        aliases_.emplace(model_path, path_of(entry));
        rebind(first, path_of(entry), {model_path});
      }
      continue;
    }
    const std::size_t index = target.loads.size();
    read_point_load(e, entry, target);
    // A robot block's weights come first among the model's loads.
    const std::string model_path = target.model_path + "loads[" + std::to_string(index) + "]";
    if (target.loads.size() > index) {
      if (model_path != path_of(entry)) aliases_.emplace(model_path, path_of(entry));
      rebind(first, path_of(entry), {model_path});
    }
  }
}

void Loader::read_point_load(const std::vector<Entry>& e, const Value& entry,
                             const LoadTarget& target) {
  Load load;
  load.origin.location = located(entry.at);
  record(load.origin, e, "");
  if (const Entry* frame = find(e, "frame")) {
    check_keys(e, entry, kFrameLoadKeys, kLoadKeys, "a load on a robot frame");
    if (!target.robot_frames) {
      fail(frame->key_at, path_of(frame->value),
           "a load on a robot frame stands in the top-level `loads:` only; give the load in a "
           "case at a point of the model");
      return;
    }
    const auto link = robot_frame(*frame);
    const std::size_t first = bindings_.size();
    const Entry* w = required(e, entry, "wrench");
    const auto wrench = w ? fixed_vector<6>(w->value, "[Fx, Fy, Fz, Mx, My, Mz]") : std::nullopt;
    std::optional<Vec3> offset;
    if (const Entry* o = find(e, "offset")) offset = fixed_vector<3>(o->value, "[x, y, z]");
    transformed_since(first);  // the layout turns the wrench and the offset with the pose
    bool frame_axes = false;
    if (const Entry* a = find(e, "axes"))
      frame_axes = choice(a->value, kFrameAxes, "axes") == "frame";
    if (link && robot_)
      if (auto problem = robot_->add_load(*link, wrench.value_or(Vec6::Zero()), offset, frame_axes,
                                          load.origin, model_))
        fail(frame->value, *problem);
    return;
  }
  check_keys(e, entry, kLoadKeys, kFrameLoadKeys, "a load");
  if (entry.node->is_mapping()) {
    read_link_end(e, entry, load.at, load.link);
    if (const Entry* w = required(e, entry, "wrench"))
      load.wrench = fixed_vector<6>(w->value, "[Fx, Fy, Fz, Mx, My, Mz]").value_or(Vec6::Zero());
    if (const Entry* weight = find(e, "self_weight"))
      load.self_weight = boolean(weight->value).value_or(false);
  }
  target.loads.push_back(std::move(load));
}

// `{link, distributed: [qx, qy, qz]}`, `{link, distributed: {from, to}}` or
// `{link, force, moment?, position}`.
void Loader::read_link_load(const std::vector<Entry>& e, const Value& entry,
                            const LoadTarget& target) {
  LinkLoad load;
  load.origin.location = located(entry.at);
  record(load.origin, e, "");
  const Entry* distributed = find(e, "distributed");
  if (distributed)
    check_keys(e, entry, kDistributedLoadKeys, kLinkLoadKeys, "a distributed load along a link");
  else
    check_keys(e, entry, kPointLinkLoadKeys, kLinkLoadKeys, "a point load along a link");
  if (const Entry* l = required(e, entry, "link")) load.link = text(l->value).value_or("");
  if (distributed) {
    load.load = read_distributed(*distributed, load.origin).value_or(DistributedLinkLoad{});
  } else {
    PointLinkLoad point;
    if (const Entry* f = required(e, entry, "force"))
      point.force = fixed_vector<3>(f->value, "[Fx, Fy, Fz]").value_or(Vec3::Zero());
    if (const Entry* m = find(e, "moment"))
      point.moment = fixed_vector<3>(m->value, "[Mx, My, Mz]").value_or(Vec3::Zero());
    if (const Entry* p = required(e, entry, "position")) point.position = given_number(p->value);
    load.load = point;
  }
  target.link_loads.push_back(std::move(load));
}

// `[qx, qy, qz]` (uniform) or `{from: [...], to: [...]}` (linear from end to end), N/m.
std::optional<DistributedLinkLoad> Loader::read_distributed(const Entry& entry, Origin& origin) {
  const Value& v = entry.value;
  if (v.node->is_sequence()) {
    const std::size_t first = bindings_.size();
    const auto q = fixed_vector<3>(v, "[qx, qy, qz]");
    if (!q) return std::nullopt;
    rebind(first, path_of(v), {path_of(v) + ".from", path_of(v) + ".to"});
    return DistributedLinkLoad{*q, *q};
  }
  if (!v.node->is_mapping()) {
    fail(v,
         "expected [qx, qy, qz] (uniform, N/m) or {from: [qx, qy, qz], to: [qx, qy, qz]} "
         "(varying linearly from the link's from end to its to end), got " +
             describe(*v.node));
    return std::nullopt;
  }
  const auto e = fixed_mapping(v);
  check_keys(e, v, kDistributedEndKeys, {}, "a distributed load");
  record(origin, e, entry.key + ".");
  DistributedLinkLoad load;
  bool read = true;
  for (const auto& [key, value] : {std::pair{"from", &load.from}, std::pair{"to", &load.to}}) {
    const Entry* end = required(e, v, key);
    const auto q = end ? fixed_vector<3>(end->value, "[qx, qy, qz]") : std::nullopt;
    if (q)
      *value = *q;
    else
      read = false;
  }
  if (!read) return std::nullopt;
  return load;
}

void Loader::read_gravity(const Entry& section) {
  model_key_locations_["gravity"] = located(section.key_at);
  model_.gravity = fixed_vector<3>(section.value, "[gx, gy, gz]");
  // An unreadable gravity still says that the model has one (validation's check of densities).
  if (!model_.gravity) model_.gravity = Vec3::Zero();
}

// `NAME: [loads]` or `NAME: {loads: [...], gravity: [gx, gy, gz]}`.
void Loader::read_load_cases(const Entry& section) {
  for (const auto& named : named_mapping(section)) {
    LoadCase load_case;
    load_case.name = named.key;
    load_case.origin.location = located(named.key_at);
    const LoadTarget target{load_case.loads, load_case.link_loads, "load_cases." + named.key + ".",
                            false};
    const Value& v = named.value;
    if (v.node->is_sequence() || v.node->is_null()) {
      read_load_list(v, target);
    } else if (v.node->is_mapping()) {
      const auto e = fixed_mapping(v);
      check_keys(e, v, kLoadCaseKeys, {}, "a load case");
      record(load_case.origin, e, "");
      if (const Entry* loads = find(e, "loads")) read_load_list(loads->value, target);
      if (const Entry* g = find(e, "gravity"))
        load_case.gravity = fixed_vector<3>(g->value, "[gx, gy, gz]").value_or(Vec3::Zero());
    } else {
      fail(v, "expected a list of loads or {loads: [...], gravity: [gx, gy, gz]}, got " +
                  describe(*v.node));
    }
    model_.load_cases.push_back(std::move(load_case));
  }
}

// `analysis: {mode: linear | loaded, load_steps: N}`.
void Loader::read_analysis(const Entry& section) {
  if (section.value.node->is_null()) return;
  const auto e = fixed_mapping(section.value);
  check_keys(e, section.value, kAnalysisKeys, {}, "the analysis");
  if (const Entry* mode = find(e, "mode"))
    if (const auto name = choice(mode->value, kAnalysisModes, "analysis mode"))
      model_.options.mode = *analysis_mode_from_string(*name);
  if (const Entry* steps = find(e, "load_steps")) {
    model_key_locations_["analysis.load_steps"] = located(steps->value.at);
    // A count, not a value of the model: it varies with no parameter.
    const Value& v = steps->value;
    const auto plain = v.node->is_scalar() && !v.node->quoted()
                           ? detail::plain_number(v.node->text())
                           : std::nullopt;
    if (!plain || *plain != std::floor(*plain) || std::abs(*plain) > INT_MAX)
      fail(v,
           "load_steps is a whole number of load steps (a positive integer, not an "
           "expression), got " +
               describe(*v.node));
    else
      model_.options.load_steps = static_cast<int>(*plain);
  }
}

void Loader::read_end_effectors(const Entry& section) {
  for (const auto& named : named_mapping(section)) {
    EndEffector ee;
    ee.name = named.key;
    ee.origin.location = located(named.key_at);
    const auto e = fixed_mapping(named.value);
    record(ee.origin, e, "");
    if (const Entry* frame = find(e, "frame")) {
      check_keys(e, named.value, kFrameEndEffectorKeys, kEndEffectorKeys,
                 "an end effector on a robot frame");
      const auto link = robot_frame(*frame);
      std::optional<Vec3> offset;
      const std::size_t first = bindings_.size();
      if (const Entry* o = find(e, "offset")) offset = fixed_vector<3>(o->value, "[x, y, z]");
      transformed_since(first);  // the offset becomes a point turned with the pose
      bool frame_axes = false;
      if (const Entry* a = find(e, "axes"))
        frame_axes = choice(a->value, kFrameAxes, "axes") == "frame";
      if (link && robot_)
        if (auto problem =
                robot_->add_end_effector(named.key, *link, offset, frame_axes, ee.origin, model_))
          fail(frame->value, *problem);
      continue;
    }
    check_keys(e, named.value, kEndEffectorKeys, kFrameEndEffectorKeys, "an end effector");
    if (named.value.node->is_mapping()) read_link_end(e, named.value, ee.at, ee.link);
    model_.end_effectors.push_back(std::move(ee));
  }
}

// ---- the robot block (docs/urdf.md) -------------------------------------------------------

void Loader::read_robot(const Entry& section) {
  robot_at_ = section.key_at;
  const Value& v = section.value;
  const auto e = fixed_mapping(v);
  check_keys(e, v, kRobotKeys, {}, "the robot block");
  if (!v.node->is_mapping()) return;
  const Entry* urdf = required(e, v, "urdf");
  const auto file = urdf ? text(urdf->value) : std::nullopt;
  if (!file) {
    spoil("");
    return;
  }
  std::filesystem::path path(*file);
  if (path.is_relative()) path = std::filesystem::path(file_).parent_path() / path;
  detail::RobotBlock block;
  try {
    block.tree = std::make_shared<const detail::UrdfTree>(
        detail::read_urdf(path, located(urdf->value.at), path_of(urdf->value)));
  } catch (const InputError& error) {
    diagnostics_.insert(diagnostics_.end(), error.diagnostics().begin(), error.diagnostics().end());
    spoil("");  // what refers to the robot cannot be checked
    return;
  }
  const detail::UrdfTree& tree = *block.tree;
  const std::string urdf_name = std::filesystem::path(tree.file).filename().string();
  const auto joint_named = [&](const Entry& named) -> std::optional<std::size_t> {
    const auto j = tree.find_joint(named.key);
    if (!j) {
      fail(named.key_at, path_of(named.value),
           "no joint named '" + named.key + "' in " + urdf_name +
               detail::suggestion(named.key, tree.joint_names(), "its joints are"));
      return std::nullopt;
    }
    const detail::UrdfJoint& joint = tree.joints[static_cast<std::size_t>(*j)];
    if (!detail::is_movable(joint.type)) {
      fail(named.key_at, path_of(named.value),
           "joint '" + named.key + "' is fixed in " + urdf_name + " (line " +
               std::to_string(joint.location.line) +
               "): it has no position and gives way through nothing but its links");
      return std::nullopt;
    }
    return static_cast<std::size_t>(*j);
  };

  if (const Entry* base = find(e, "base"))
    if (const auto name = text(base->value)) {
      if (const auto b = tree.find_link(*name))
        block.base = *b;
      else
        fail(base->value, "no link named '" + *name + "' in " + urdf_name +
                              detail::suggestion(*name, tree.link_names(), "its links are"));
    }

  robot_positions_.assign(tree.joints.size(), {});
  block.position_at.assign(tree.joints.size(), located(section.key_at));
  if (const Entry* positions = find(e, "positions"))
    for (const auto& named : named_mapping(*positions)) {
      const auto j = joint_named(named);
      if (!j) continue;
      ExpressionSite site;
      const auto q = robot_position(named.value, site);
      block.position_at[*j] = located(named.value.at);
      if (!q) continue;
      robot_positions_[*j].value = *q;
      if (!site.text.empty()) robot_positions_[*j].expression = std::move(site);
    }

  std::optional<detail::JointSpring> default_spring;
  // A scalar stiffness fills the 1×1 spring of its joint; the default's, of every joint it springs.
  std::vector<Binding> default_bindings;
  std::string default_stiffness;
  if (const Entry* d = find(e, "default_joint")) {
    const std::size_t first = bindings_.size();
    default_spring = read_joint_spring(d->value);
    default_bindings.assign(bindings_.begin() + static_cast<std::ptrdiff_t>(first),
                            bindings_.end());
    bindings_.resize(first);
    default_stiffness = path_of(d->value) + ".stiffness";
  }
  const auto spring_slot = [](const std::string& joint) {
    return matrix_entry("joints." + joint + ".stiffness", 0, 0);
  };
  block.springs.assign(tree.joints.size(), {});
  for (const auto& joint : tree.joints)
    aliases_.emplace("joints." + joint.name + ".axis", "robot.urdf");  // the URDF's <axis>
  std::vector<bool> sprung(tree.joints.size(), false);
  const Entry* joints = find(e, "joints");
  if (joints)
    for (const auto& named : named_mapping(*joints)) {
      const auto j = joint_named(named);
      const std::size_t first = bindings_.size();
      const auto spring = read_joint_spring(named.value);
      rebind(first, path_of(named.value) + ".stiffness", {spring_slot(named.key)});
      if (!j || !spring) {
        if (j) sprung[*j] = true;  // reported already
        if (j) spoil("joints." + named.key);
        continue;
      }
      block.springs[*j] = *spring;
      sprung[*j] = true;
      const std::string key = spring->compliance ? ".compliance" : ".stiffness";
      aliases_.emplace("joints." + named.key + ".stiffness", path_of(named.value) + key);
    }
  for (std::size_t j = 0; j < tree.joints.size(); ++j) {
    const detail::UrdfJoint& joint = tree.joints[j];
    if (!detail::is_movable(joint.type) || sprung[j]) continue;
    if (default_spring) {
      block.springs[j] = *default_spring;
      const auto bound = moved(default_bindings, default_stiffness, {spring_slot(joint.name)});
      bindings_.insert(bindings_.end(), bound.begin(), bound.end());
      aliases_.emplace("joints." + joint.name + ".stiffness", "robot.default_joint");
      continue;
    }
    spoil("joints." + joint.name);  // its zero spring is this defect
    fail(joints ? joints->key_at : section.key_at, joints ? path_of(joints->value) : path_of(v),
         "the " + std::string(detail::to_string(joint.type)) + " joint '" + joint.name + "' of " +
             urdf_name + " (line " + std::to_string(joint.location.line) +
             ") has no stiffness; list it under robot.joints, or give robot.default_joint for "
             "every joint not listed");
  }

  block.flexible.assign(tree.links.size(), std::nullopt);
  // The material and section of a flexible link fill its beam's, or its two beams' where the
  // layout splits it at its centre of mass: rebound once the layout is made.
  const std::size_t flexible_first = bindings_.size();
  std::vector<std::string> flexible_names;
  if (const Entry* links = find(e, "links"))
    for (const auto& named : named_mapping(*links)) {
      const auto l = tree.find_link(named.key);
      if (!l) {
        fail(named.key_at, path_of(named.value),
             "no link named '" + named.key + "' in " + urdf_name +
                 detail::suggestion(named.key, tree.link_names(), "its links are"));
        continue;
      }
      const auto le = fixed_mapping(named.value);
      check_keys(le, named.value, kRobotLinkKeys, {}, "a flexible robot link");
      Link holder;  // collects the key locations of the material and section
      holder.origin.location = located(named.key_at);
      record(holder.origin, le, "");
      BeamLink beam;
      if (const Entry* m = required(le, named.value, "material"))
        beam.material =
            named_or_inline(*m, materials_, "materials", holder, &Loader::read_material);
      if (const Entry* sec = required(le, named.value, "section"))
        beam.section = named_or_inline(*sec, sections_, "sections", holder, &Loader::read_section);
      if (const Entry* shear = find(le, "shear"))
        beam.shear = boolean(shear->value).value_or(false);
      block.flexible[static_cast<std::size_t>(*l)] = detail::FlexibleLink{beam, holder.origin};
      flexible_names.push_back(named.key);
      aliases_.emplace("links." + named.key, path_of(named.value));
      aliases_.emplace("links." + named.key + ".distal", path_of(named.value));
    }

  if (const Entry* g = find(e, "gravity")) {
    const std::size_t first = bindings_.size();
    block.gravity = fixed_vector<3>(g->value, "[gx, gy, gz]");
    transformed_since(first);  // it becomes the links' weights, turned with the pose
  }

  try {
    robot_ = std::make_shared<detail::RobotLayout>(block, model_);
  } catch (const InputError& error) {
    diagnostics_.insert(diagnostics_.end(), error.diagnostics().begin(), error.diagnostics().end());
    spoil("");
    return;
  }
  for (const std::string& name : flexible_names) {
    std::vector<std::string> beams{"links." + name};
    const Link* distal = model_.find_link(name + ".distal");
    if (distal && std::holds_alternative<BeamLink>(distal->kind))
      beams.push_back("links." + distal->name);
    rebind(flexible_first, "robot.links." + name, beams);
  }
}

// A joint's spring: `stiffness` about (along) its axis, or a 6×6 `compliance` in its frame.
std::optional<detail::JointSpring> Loader::read_joint_spring(const Value& v) {
  const auto e = fixed_mapping(v);
  check_keys(e, v, kRobotJointKeys, {}, "a robot joint");
  if (!v.node->is_mapping()) return std::nullopt;
  detail::JointSpring spring;
  spring.origin.location = located(v.at);
  record(spring.origin, e, "");
  const Entry* k = find(e, "stiffness");
  const Entry* c = find(e, "compliance");
  if (k && c) {
    fail(c->key_at, path_of(c->value), "give either stiffness or compliance, not both");
    return std::nullopt;
  }
  if (!k && !c) {
    fail(v.at, path_of(v),
         "give the joint's stiffness (about or along its axis) or its 6×6 compliance");
    return std::nullopt;
  }
  if (k) {
    const auto stiffness = number(k->value);
    if (!stiffness) return std::nullopt;
    spring.stiffness = *stiffness;
    spring.origin.record("stiffness", located(k->value.at));
    return spring;
  }
  const std::size_t first = bindings_.size();
  const auto compliance = square_matrix<6>(c->value);
  transformed_since(first);  // the model's spring is its inverse
  if (!compliance) return std::nullopt;
  spring.origin.record("stiffness", located(c->value.at));
  const double scale = compliance->cwiseAbs().maxCoeff();
  const bool symmetric = (*compliance - compliance->transpose()).cwiseAbs().maxCoeff() <=
                         kComplianceSymmetryTolerance * scale;
  const Mat6 symmetric_part = 0.5 * (*compliance + compliance->transpose());
  if (!symmetric || scale == 0 || Eigen::LLT<Mat6>(symmetric_part).info() != Eigen::Success) {
    fail(
        c->value,
        symmetric
            ? "the compliance is not positive definite: a joint gives way in every direction, by a "
              "positive amount (a rigid direction needs a small compliance, not zero)"
            : "the compliance is not symmetric");
    return std::nullopt;
  }
  spring.compliance = symmetric_part;
  return spring;
}

// A URDF link named by a load's or end effector's `frame`.
std::optional<int> Loader::robot_frame(const Entry& frame) {
  const auto name = text(frame.value);
  if (!name) return std::nullopt;
  if (!robot_) {
    if (!find_robot_block_)
      fail(frame.value,
           "`frame:` names a frame of the robot block's URDF, and the model has no `robot:`");
    return std::nullopt;
  }
  if (const auto link = robot_->tree().find_link(*name)) return *link;
  fail(frame.value, "no frame (URDF link) named '" + *name + "' in " +
                        std::filesystem::path(robot_->tree().file).filename().string() +
                        detail::suggestion(*name, robot_->tree().link_names(), "its links are"));
  return std::nullopt;
}

// A joint position: a number, or an expression of the parameters that the builder evaluates
// for each member: forward kinematics turns it into many numbers, none of them its value.
std::optional<double> Loader::robot_position(const Value& v, ExpressionSite& site) {
  if (!parametric_ || !v.node->is_scalar() || detail::plain_number(v.node->text()))
    return number(v);
  const std::string& expression = v.node->text();
  const auto outcome = expressions_->evaluate(expression);
  if (outcome.follows_earlier_error) {
    spoil(v);
    return std::nullopt;
  }
  if (!outcome.error.empty()) {
    fail(v, outcome.error);
    return std::nullopt;
  }
  site = {expression, path_of(v), located(v.at)};
  return outcome.value;
}

// `{at: point, link: name}`, the link optional, as loads and end effectors name a link end.
void Loader::read_link_end(const std::vector<Entry>& e, const Value& v, std::string& at,
                           std::optional<std::string>& link) {
  if (const Entry* a = required(e, v, "at")) at = text(a->value).value_or("");
  if (const Entry* l = find(e, "link")) link = text(l->value).value_or("");
}

// ---- merging with validation -------------------------------------------------------------

// The lengths of the key paths that `path` lies within, itself first: "links.L1.K[2]" lies
// within "links.L1.K", "links.L1", "links" and "", the whole model.
std::vector<std::size_t> enclosing_lengths(const std::string& path) {
  std::vector<std::size_t> lengths{path.size()};
  for (std::size_t i = path.size(); i-- > 0;)
    if (path[i] == '.' || path[i] == '[') lengths.push_back(i);
  lengths.push_back(0);
  return lengths;
}

template <class T, class Check>
void add_definition_defects(std::vector<Diagnostic>& out, const std::string& plural,
                            const std::map<std::string, Definition<T>>& definitions, Check check) {
  for (const auto& [name, definition] : definitions)
    for (const auto& defect : check(definition.value))
      out.push_back({definition.origin.of(defect.key),
                     plural + "." + name + (defect.key.empty() ? "" : "." + defect.key),
                     defect.message});
}

void Loader::check_definitions() {
  add_definition_defects(definition_defects_, "materials", materials_, detail::material_defects);
  add_definition_defects(definition_defects_, "sections", sections_, detail::section_defects);
}

std::vector<Diagnostic> Loader::merge(std::vector<Diagnostic> defects) {
  defects.insert(defects.begin(), definition_defects_.begin(), definition_defects_.end());
  std::vector<Diagnostic> all = diagnostics_;
  if (!defects.empty()) {
    for (const PathId id : spoiled_values_) spoiled_.insert(path_of(id));
    spoiled_values_.clear();
  }
  // Aliases and spoiled parts are looked up by the paths enclosing a defect's, not scanned:
  // a model of 100 000 supports has as many of them.
  for (auto& d : defects) {
    for (const std::size_t length : enclosing_lengths(d.key_path)) {
      const auto alias = aliases_.find(d.key_path.substr(0, length));
      if (alias == aliases_.end()) continue;
      d.key_path = alias->second + d.key_path.substr(length);
      break;
    }
    if (d.location.line == 0)
      for (const std::size_t length : enclosing_lengths(d.key_path))
        if (const auto at = model_key_locations_.find(d.key_path.substr(0, length));
            at != model_key_locations_.end()) {
          d.location = at->second;
          break;
        }
    const auto lengths = enclosing_lengths(d.key_path);
    const bool spoiled = std::any_of(lengths.begin(), lengths.end(), [&](std::size_t length) {
      return spoiled_.count(d.key_path.substr(0, length)) > 0;
    });
    if (!spoiled) all.push_back(std::move(d));
  }
  // Unknown positions (0) go last.
  const auto order = [](const Diagnostic& d) {
    return std::pair(d.location.line > 0 ? d.location.line : INT_MAX, d.location.column);
  };
  std::stable_sort(all.begin(), all.end(),
                   [&](const Diagnostic& a, const Diagnostic& b) { return order(a) < order(b); });
  return all;
}

// ---- limits ------------------------------------------------------------------------------

const KeyList kEntityKinds{"materials", "sections", "points",        "links",     "joints",
                           "supports",  "loads",    "end_effectors", "load_cases"};

std::string byte_count(std::uintmax_t bytes) {
  std::string text = std::to_string(bytes) + " bytes";
  constexpr double mebibyte = 1024.0 * 1024.0;
  if (bytes >= 1024 * 1024) {
    std::ostringstream mib;
    mib.precision(1);
    mib << std::fixed << static_cast<double>(bytes) / mebibyte;
    text += " (" + mib.str() + " MiB)";
  }
  return text;
}

// `size_and_limit` says how large the file is against the limit.
[[noreturn]] void throw_too_large(const std::string& file, const std::string& size_and_limit) {
  throw InputError({file, 0, 0}, "",
                   "the model file is " + size_and_limit +
                       "; if the model is meant to be this large, raise the limit "
                       "(LoadLimits::max_file_bytes)");
}

void require_size_within(std::uintmax_t bytes, const std::string& file, const LoadLimits& limits) {
  if (bytes > limits.max_file_bytes)
    throw_too_large(
        file, byte_count(bytes) + ", above the limit of " + byte_count(limits.max_file_bytes));
}

// How deeply mappings and lists nest in a text.
struct Nesting {
  int deepest = 0;
  SourceLocation first_too_deep;  // line 0 where the text stays within the limit
};

// Measures nesting on the characters of a YAML or JSON text before it is parsed, so that a
// refusal can say how deep the whole file goes, even where the parser would stop at an error
// further on; the tree builder holds the same limit again, for whatever this scan misreads.
// A flow collection is an open `[` or `{`; a block collection is a
// line indented deeper than the collection it is in, or a `- ` or `? ` item whose content on
// the same line is a mapping or list (`- - x`, `- key: value`). Quoted text, comments and the
// lines of block scalars (`|`, `>`) hold no collections. Where it cannot tell, as on the
// continuation line of a plain scalar, the scan counts a level: a few levels too many cost
// nothing under a limit far above real models, a level missed could let a file through.
// Letters, digits and `_ . + - /`: characters that, outside quotes, change nothing the scan
// below counts.
constexpr std::array<bool, 256> kWordCharacters = [] {
  std::array<bool, 256> word{};
  for (int c = 0; c < 256; ++c)
    word[static_cast<std::size_t>(c)] = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                                        (c >= '0' && c <= '9') || c == '_' || c == '.' ||
                                        c == '+' || c == '-' || c == '/';
  return word;
}();

Nesting measure_nesting(std::string_view text, int limit) {
  constexpr auto npos = std::string_view::npos;
  Nesting nesting;
  std::vector<std::size_t> block_columns;  // the indentation of each open block collection
  int flow = 0;                            // open `[` and `{`
  char quote = 0;                          // '"' or '\'' within quoted text, which may span lines
  std::optional<std::size_t> block_scalar_indent;  // lines indented deeper are literal text
  int line_number = 0;

  const auto reach = [&](std::size_t column) {
    const int depth = static_cast<int>(block_columns.size()) + flow;
    nesting.deepest = std::max(nesting.deepest, depth);
    if (depth > limit && nesting.first_too_deep.line == 0)
      nesting.first_too_deep = {"", line_number, static_cast<int>(column) + 1};
  };
  const auto block_at = [&](std::size_t column) {
    while (!block_columns.empty() && block_columns.back() > column) block_columns.pop_back();
    if (block_columns.empty() || block_columns.back() < column) block_columns.push_back(column);
    reach(column);
  };

  for (std::size_t start = 0; start < text.size();) {
    const std::size_t newline = text.find('\n', start);
    const std::size_t end = newline == npos ? text.size() : newline;
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);

    const std::size_t indent = line.find_first_not_of(" \t");  // npos: a blank line
    const bool in_block_context = quote == 0 && flow == 0;
    std::size_t i = 0;
    if (in_block_context) {
      if (block_scalar_indent) {
        if (indent == npos || indent > *block_scalar_indent) continue;
        block_scalar_indent.reset();
      }
      if (indent == npos || line[indent] == '#') continue;
      i = indent;
      if (line[i] == '[' || line[i] == '{') {
        // A flow collection that begins a line (a JSON file's root, a value under its key)
        // counts itself; it is in the block collections that are not deeper than it.
        while (!block_columns.empty() && block_columns.back() > indent) block_columns.pop_back();
      } else {
        block_at(indent);
      }
      while ((line[i] == '-' || line[i] == '?') &&
             (i + 1 == line.size() || line[i + 1] == ' ' || line[i + 1] == '\t')) {
        const std::size_t content = line.find_first_not_of(" \t", i + 1);
        if (content == npos || line[content] == '#') break;  // the item's content follows
        i = content;
        if (line[i] == '[' || line[i] == '{') break;  // counted as a flow collection
        block_at(i);
      }
    }

    bool token_start = true;  // a quote here opens quoted text; within a plain scalar it is text
    std::size_t code_end = line.size();
    for (; i < line.size(); ++i) {
      const char c = line[i];
      // Most of a line, its names and numbers: no quote, comment or bracket, nor a token start.
      if (quote == 0 && kWordCharacters[static_cast<unsigned char>(c)]) {
        token_start = false;
        continue;
      }
      if (quote == '"') {
        if (c == '\\')
          ++i;
        else if (c == '"')
          quote = 0;
        continue;
      }
      if (quote == '\'') {
        if (c == '\'' && i + 1 < line.size() && line[i + 1] == '\'')
          ++i;  // '' is a quote within the text
        else if (c == '\'')
          quote = 0;
        continue;
      }
      if (c == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')) {
        code_end = i;
        break;
      }
      if ((c == '"' || c == '\'') && token_start) {
        quote = c;
        continue;
      }
      if (c == '[' || c == '{') {
        ++flow;
        reach(i);
      } else if ((c == ']' || c == '}') && flow > 0) {
        --flow;
      }
      token_start = c == ' ' || c == '\t' || c == '[' || c == '{' || c == ',' || c == ':';
    }

    // `key: |` or `- >-` ends a line whose following, deeper lines are text. (In `a: b |` the
    // bar ends a plain scalar: those lines are scanned, which can only count too deep.)
    if (in_block_context && quote == 0 && flow == 0) {
      const std::string_view code = line.substr(0, code_end);
      const std::size_t last = code.find_last_not_of(" \t");
      if (last == npos) continue;
      const std::size_t blank = code.find_last_of(" \t", last);
      const std::size_t token = blank == npos ? 0 : blank + 1;
      const std::string_view word = code.substr(token, last + 1 - token);
      const std::size_t before = token == 0 ? npos : code.find_last_not_of(" \t", token - 1);
      const bool after_indicator =
          before == npos || code[before] == ':' || code[before] == '-' || code[before] == '?';
      if (after_indicator && (word[0] == '|' || word[0] == '>') &&
          word.find_first_not_of("0123456789+-", 1) == npos)
        block_scalar_indent = indent;
    }
  }
  return nesting;
}

void require_nesting_within(std::string_view text, const std::string& file,
                            const LoadLimits& limits) {
  const Nesting nesting = measure_nesting(text, limits.max_nesting_depth);
  if (nesting.first_too_deep.line == 0) return;
  SourceLocation at = nesting.first_too_deep;
  at.file = file;
  throw InputError(at, "",
                   detail::nesting_too_deep_message(limits.max_nesting_depth, nesting.deepest));
}

// Counted on the parsed file, before each entity becomes part of a Model that validation and
// the solver work through.
void require_entity_counts_within(const YamlNode& root, const std::string& file,
                                  const LoadLimits& limits) {
  std::vector<Diagnostic> too_many;
  for (const auto& [key, section] : root.entries()) {
    if (!key->is_scalar() || !contains(kEntityKinds, key->text())) continue;
    if (!section->is_mapping() && !section->is_sequence()) continue;
    const std::size_t count = section->size();
    if (count <= limits.max_entities) continue;
    std::string kind = key->text();
    std::replace(kind.begin(), kind.end(), '_', ' ');
    too_many.push_back({SourceLocation{file, key->line(), key->column()}, key->text(),
                        "the model has " + std::to_string(count) + " " + kind +
                            ", above the limit of " + std::to_string(limits.max_entities) +
                            " of each kind; if the model is meant to be this large, raise the "
                            "limit (LoadLimits::max_entities)"});
  }
  if (!too_many.empty()) throw InputError(std::move(too_many));
}

}  // namespace

namespace {

detail::YamlTree parse_tree(std::string_view text, const std::string& file_name,
                            const LoadLimits& limits) {
  require_size_within(text.size(), file_name, limits);
  require_nesting_within(text, file_name, limits);
  detail::YamlTree tree = detail::parse_yaml(text, file_name, limits.max_nesting_depth);
  require_entity_counts_within(tree.root(), file_name, limits);
  return tree;
}

// A model read from a parsed file and validated, with the file's positions in every message.
Model read_checked(const YamlNode& root, const std::string& file_name,
                   detail::ExpressionEvaluator* expressions, std::span<const double> values) {
  Loader loader(file_name, expressions, values);
  Model model = loader.read(root);
  for (std::size_t i = 0; i < values.size() && i < model.parameters.size(); ++i)
    model.parameters[i].value = values[i];
  auto defects = loader.merge(find_defects(model));
  if (!defects.empty()) throw InputError(std::move(defects));
  return model;
}

std::string read_model_text(const std::filesystem::path& path, const LoadLimits& limits) {
  const std::string file = path.string();
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  // The system's reason (no such file, permission denied), where the open left one.
  if (!in)
    throw IoError("cannot open model file '" + file + "'" +
                  (errno != 0 ? ": " + std::generic_category().message(errno) : std::string()));
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw IoError("cannot read model file '" + file + "': it is a directory");
  std::string text;
  // Refused before a byte is read. A pipe or device has no size to ask: it is read up to the
  // limit instead.
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (!error) {
    require_size_within(size, file, limits);
    text.reserve(static_cast<std::size_t>(size));
  }
  std::array<char, 1 << 16> buffer;
  while (in.read(buffer.data(), buffer.size()) || in.gcount() > 0) {
    text.append(buffer.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > limits.max_file_bytes)
      throw_too_large(file, "larger than the limit of " + byte_count(limits.max_file_bytes));
  }
  if (in.bad()) throw IoError("cannot read model file '" + file + "'");
  return text;
}

// What a writer needs to write a member's values without reading the file again: which slot
// of the structure each expression fills, as the one reading of the file bound them, and each
// expression's site for its messages (the source map of the family's values). Every site is
// evaluated for each member, bound or not (a material that no beam uses), so that an
// expression that fails at a member's values is reported as a reading of the file would.
struct SlotBindings {
  Structure structure;
  std::vector<ExpressionSite> sites;
  std::vector<ExpressionSite> derived;
  std::vector<std::pair<std::size_t, std::size_t>> filled;  // (slot, site), slots ascending
  // A robot block's layout and joint positions: each member is posed after its numbers are in.
  std::shared_ptr<const detail::RobotLayout> robot;
  std::vector<Loader::RobotPosition> robot_positions;
};

// The slots that the expressions of a file fill, as the loader that read it bound them.
// Nullopt where a number could not be bound: an expression the reader transforms on its way
// into the model (Loader::transformed()), or a slot name the structure does not have (a case
// the reader does not foresee; its members are then read from the file, with the same result).
std::optional<SlotBindings> bound_slots(const Loader& loader, const Structure& structure) {
  if (loader.transformed()) return std::nullopt;
  SlotBindings bindings{structure, loader.sites(), loader.derived_sites(), {}, nullptr, {}};
  // The slots' names are made only for a file that binds something: a large model without
  // expressions would spend more on them than on its reading.
  if (loader.bindings().empty()) return bindings;
  const std::vector<std::string>& names = structure.slot_names();
  std::unordered_map<std::string_view, std::size_t> slot_of;
  slot_of.reserve(names.size());
  for (std::size_t i = 0; i < names.size(); ++i) slot_of.emplace(names[i], i);
  for (const Binding& b : loader.bindings()) {
    const auto slot = slot_of.find(b.slot);
    if (slot == slot_of.end()) return std::nullopt;
    bindings.filled.emplace_back(slot->second, b.site);
  }
  std::sort(bindings.filled.begin(), bindings.filled.end());
  return bindings;
}

// A writer that evaluates the expressions for the member's parameter values and writes them
// into their slots; the other slots keep the structure's defaults. A robot block's member is
// posed on a model of the writer's own, whose numbers are then the member's values.
ModelFamily::ValueWriter slot_writer(std::shared_ptr<const SlotBindings> bindings,
                                     std::vector<std::string> names,
                                     std::vector<std::string> derived_names) {
  auto expressions =
      std::make_shared<detail::ExpressionEvaluator>(std::move(names), std::move(derived_names));
  const Structure& structure = bindings->structure;
  // An expression written at several places (a point and an axis through it) is evaluated once
  // per member: `distinct` holds the first site of each text, `site_text` each site's.
  std::vector<std::size_t> distinct, site_text;
  {
    std::unordered_map<std::string_view, std::size_t> seen;
    for (std::size_t k = 0; k < bindings->sites.size(); ++k) {
      const auto [at, added] = seen.try_emplace(bindings->sites[k].text, distinct.size());
      if (added) distinct.push_back(k);
      site_text.push_back(at->second);
    }
  }
  std::vector<double> text_values(distinct.size());
  return
      [bindings, expressions, defaults = structure.default_values(), distinct = std::move(distinct),
       site_text = std::move(site_text), text_values = std::move(text_values),
       robot_values = std::vector<double>(bindings->robot_positions.size()),
       posed = bindings->robot ? std::make_shared<Model>(structure.model()) : nullptr](
          std::span<const double> parameters, std::span<double> values,
          std::vector<Diagnostic>& warnings) mutable {
        expressions->set_values(parameters);
        std::vector<Diagnostic> defects;
        const auto report = [&](const ExpressionSite& site,
                                const detail::ExpressionEvaluator::Outcome& outcome) {
          if (!outcome.error.empty() && !outcome.follows_earlier_error)
            defects.push_back({site.at, site.path, outcome.error});
        };
        for (std::size_t i = 0; i < bindings->derived.size(); ++i)
          report(bindings->derived[i], expressions->evaluate_derived(i, bindings->derived[i].text));
        bool all_values = true;
        std::vector<std::pair<std::size_t, detail::ExpressionEvaluator::Outcome>>
            failed;  // (text, outcome)
        for (std::size_t t = 0; t < distinct.size(); ++t) {
          auto outcome = expressions->evaluate(bindings->sites[distinct[t]].text);
          text_values[t] = outcome.value;
          if (!outcome.error.empty()) failed.emplace_back(t, std::move(outcome));
        }
        if (!failed.empty()) {
          // Every site of a failed text is reported at its own key, the sites in reading order.
          all_values = false;
          for (std::size_t k = 0; k < site_text.size(); ++k)
            for (const auto& [t, outcome] : failed)
              if (site_text[k] == t) report(bindings->sites[k], outcome);
        }
        for (std::size_t j = 0; j < bindings->robot_positions.size(); ++j) {
          const auto& position = bindings->robot_positions[j];
          robot_values[j] = position.value;
          if (!position.expression) continue;
          const auto outcome = expressions->evaluate(position.expression->text);
          report(*position.expression, outcome);
          all_values = all_values && outcome.error.empty();
          robot_values[j] = outcome.value;
        }
        // A value that is missing without a defect of its own follows from a derived value's,
        // which is reported: defects is never empty here.
        if (!all_values) throw InputError(std::move(defects));
        std::copy(defaults.begin(), defaults.end(), values.begin());
        for (const auto& [slot, site] : bindings->filled)
          values[slot] = text_values[site_text[site]];
        if (!posed) {
          warnings = bindings->structure.model().warnings;
          return;
        }
        bindings->structure.write_values(values, *posed);
        bindings->robot->pose(robot_values, *posed);
        double* next = values.data();
        detail::for_each_number(*posed, [&](double v) { *next++ = v; });
        warnings = posed->warnings;
      };
}

// Writers of a file whose expressions could not all be bound read the file for each member: each
// parses the text once into a tree of its own, so writers on different threads share nothing.
ModelFamily::ValueWriter rereading_writer(std::shared_ptr<const std::string> text,
                                          const std::string& file_name, const LoadLimits& limits,
                                          const Structure& structure,
                                          std::vector<std::string> names,
                                          std::vector<std::string> derived_names) {
  auto own_tree = std::make_shared<const detail::YamlTree>(parse_tree(*text, file_name, limits));
  auto expressions =
      std::make_shared<detail::ExpressionEvaluator>(std::move(names), std::move(derived_names));
  return [own_tree, expressions, file_name, structure](std::span<const double> parameters,
                                                       std::span<double> values,
                                                       std::vector<Diagnostic>& warnings) {
    Loader loader(file_name, expressions.get(), parameters);
    const Model member = loader.read(own_tree->root());
    auto defects = loader.merge({});
    if (!defects.empty()) throw InputError(std::move(defects));
    const std::vector<double> read = structure.values_of(member);
    std::copy(read.begin(), read.end(), values.begin());
    warnings = member.warnings;
  };
}

// Reads a family's file once, at the parameters' defaults with `settings` in their place, into
// `loader` (which keeps the expressions' bindings), and returns the structure of that member.
Structure read_structure(Loader& loader, const YamlNode& root, const std::string& file_name,
                         const ParameterSettings& settings) {
  loader.set_defaults(&settings);
  Model at_defaults = loader.read(root);
  // Settings for a file without `parameters:` reach no read_parameters(): all are unknown.
  std::vector<std::string> unknown = loader.unknown_settings();
  if (loader.parameters().empty() && loader.derived_names().empty())
    for (const auto& [name, value] : settings) unknown.push_back(name);
  std::vector<std::string> names;
  for (const auto& p : loader.parameters()) names.push_back(p.name);
  if (!unknown.empty())
    throw detail::NameErrorInContext(
        "parameter", unknown.front(), names,
        detail::no_parameter_message(at_defaults.name, file_name, unknown.front(), names));
  // The structure validates the model at the defaults; its defects join the loader's own.
  if (!loader.merge({}).empty()) throw InputError(loader.merge(find_defects(at_defaults)));
  try {
    return Structure(std::move(at_defaults));
  } catch (const InputError& e) {
    throw InputError(loader.merge(e.diagnostics()));
  }
}

ModelFamily family_of(std::string_view text, const std::string& file_name, const LoadLimits& limits,
                      const ParameterSettings& settings) {
  const detail::YamlTree tree = parse_tree(text, file_name, limits);
  const YamlNode& root = tree.root();
  Loader loader(file_name);
  const Structure structure = read_structure(loader, root, file_name, settings);
  std::vector<std::string> names;
  for (const auto& p : loader.parameters()) names.push_back(p.name);
  const std::vector<std::string> derived_names = loader.derived_names();
  std::shared_ptr<const SlotBindings> bindings;
  if (auto bound = bound_slots(loader, structure)) {
    bound->robot = loader.robot();
    bound->robot_positions = loader.robot_positions();
    bindings = std::make_shared<const SlotBindings>(std::move(*bound));
  }
  // The text is kept only for writers that must read it again.
  auto shared_text = bindings ? nullptr : std::make_shared<const std::string>(text);
  auto make_writer = [bindings, shared_text, file_name, limits, names, derived_names,
                      structure]() -> ModelFamily::ValueWriter {
    if (bindings) return slot_writer(bindings, names, derived_names);
    return rereading_writer(shared_text, file_name, limits, structure, names, derived_names);
  };
  return ModelFamily(structure.model().name, loader.parameters(), structure, make_writer);
}

}  // namespace

Model parse_model(std::string_view text, const std::string& file_name) {
  return parse_model(text, file_name, LoadLimits{});
}

Model parse_model(std::string_view text, const std::string& file_name, const LoadLimits& limits) {
  return read_checked(parse_tree(text, file_name, limits).root(), file_name, nullptr, {});
}

Model load_model(const std::filesystem::path& path) { return load_model(path, LoadLimits{}); }

Model load_model(const std::filesystem::path& path, const LoadLimits& limits) {
  return parse_model(read_model_text(path, limits), path.string(), limits);
}

ModelFamily parse_model_family(std::string_view text, const std::string& file_name,
                               const LoadLimits& limits, const ParameterSettings& settings) {
  return family_of(text, file_name, limits, settings);
}

std::optional<std::vector<detail::ExpressionBinding>> detail::expression_bindings(
    std::string_view text, const std::string& file_name) {
  const detail::YamlTree tree = parse_tree(text, file_name, LoadLimits{});
  Loader loader(file_name);
  const Structure structure = read_structure(loader, tree.root(), file_name, {});
  const auto bound = bound_slots(loader, structure);
  if (!bound) return std::nullopt;
  std::vector<ExpressionBinding> bindings;
  for (const auto& [slot, site] : bound->filled)
    bindings.push_back(
        {structure.slot_names()[slot], bound->sites[site].text, bound->sites[site].path});
  return bindings;
}

ModelFamily load_model_family(const std::filesystem::path& path, const LoadLimits& limits,
                              const ParameterSettings& settings) {
  return parse_model_family(read_model_text(path, limits), path.string(), limits, settings);
}

}  // namespace stiffmsa

// The model viewer's page: the model, its deformed shape and its end effectors' ellipsoids as
// JSON data inside a page that draws them with three.js (src/io/viewer/model_view.js).
#include "stiffmsa/io/view_html.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "io/view_assets.hpp"
#include "io/view_page.hpp"
#include "stiffmsa/analysis.hpp"
#include "stiffmsa/deformed_shape.hpp"
#include "stiffmsa/io/result_file.hpp"

namespace stiffmsa {
namespace {

using nlohmann::json;

// The largest displacement is drawn as this fraction of the model's size.
constexpr double kDrawnDisplacementFraction = 0.1;
// Deflection samples in the page, at most about this many in all (the page's size and load time).
constexpr std::size_t kMostDeflectionSamples = 200'000;
constexpr int kMostBeamSegments = 8;

// Codes the page knows by these lists (sent with the data, so the page names them).
const std::vector<std::string> kLinkKindNames = {"beam", "rigid", "matrix (CAD)",
                                                 "compliance (CAD)"};
const std::vector<std::string> kRoleNames = {"rigid", "passive", "elastic", "actuated"};

int link_kind_code(const LinkKind& kind) { return static_cast<int>(kind.index()); }

int role_code(const Connection& c) {
  if (c.is_actuated) return 3;
  if (c.stiffness) return 2;
  if (c.kinematics.type == JointType::rigid) return 0;
  return 1;
}

std::vector<float> to_floats(const Vec3& v) { return {float(v.x()), float(v.y()), float(v.z())}; }
json vector_json(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

// Drawn width (local y) and height (local z) of a beam's section, and whether it is round.
struct DrawnSection {
  double width, height;
  bool round;
};
DrawnSection drawn_section(const Section& s) {
  switch (s.shape) {
    case SectionShape::circle:
    case SectionShape::tube: return {s.D, s.D, true};
    case SectionShape::rect:
    case SectionShape::rect_tube: return {s.b, s.h, false};
    case SectionShape::generic: break;
  }
  const double diameter =
      std::sqrt(4 * std::max(s.A, 0.0) / M_PI);  // the round section of that area
  return {diameter, diameter, true};
}

// The axes a joint draws: revolute, prismatic, cylindrical their axis, universal both, planar
// its normal; others none (zeros).
std::vector<float> drawn_axes(const Kinematics& k) {
  Vec3 first = Vec3::Zero(), second = Vec3::Zero();
  switch (k.type) {
    case JointType::revolute:
    case JointType::prismatic:
    case JointType::cylindrical: first = k.axis.normalized(); break;
    case JointType::universal:
      first = k.axis.normalized();
      second = k.axis_b.normalized();
      break;
    case JointType::planar: first = k.normal.normalized(); break;
    default: break;
  }
  return {float(first.x()),  float(first.y()),  float(first.z()),
          float(second.x()), float(second.y()), float(second.z())};
}

template <typename Connected>
json connections_json(const std::vector<Connected>& items, const ModelPoints& index) {
  json names = json::array(), types = json::array();
  std::vector<std::int32_t> at, role;
  std::vector<float> axes;
  for (const Connected& item : items) {
    names.push_back(item.name);
    types.push_back(to_string(item.connection.kinematics.type));
    at.push_back(index.of_name(item.at));
    role.push_back(role_code(item.connection));
    const auto a = drawn_axes(item.connection.kinematics);
    axes.insert(axes.end(), a.begin(), a.end());
  }
  return {{"names", names},
          {"types", types},
          {"at", detail::base64_of(at)},
          {"role", detail::base64_of(role)},
          {"axes", detail::base64_of(axes)}};
}

double model_size(const Model& model) {
  if (model.points.empty()) return 1;
  Vec3 low = model.points.front().position, high = low;
  for (const Point& p : model.points) {
    low = low.cwiseMin(p.position);
    high = high.cwiseMax(p.position);
  }
  const double size = (high - low).norm();
  return size > 0 ? size : 1;
}

// A link end's deflection from the result, if the solve determined it.
const std::optional<Vec6>& end_deflection(const LinkResult& link, LinkEnd end) {
  return end == LinkEnd::from ? link.from.deflection : link.to.deflection;
}

json deformed_json(const Model& model, const Result* result, const ModelPoints& index,
                   const ModelViewOptions& options, double size) {
  json deformed = {{"solved", result != nullptr}, {"message", options.not_solved}};
  if (!result) return deformed;
  const std::size_t link_count = model.links.size();
  const auto samples_per_link =
      static_cast<long>(kMostDeflectionSamples / std::max<std::size_t>(link_count, 1));
  const int segments = options.beam_segments.value_or(
      static_cast<int>(std::clamp(samples_per_link - 1, 1L, long{kMostBeamSegments})));
  std::vector<float> displacement;
  displacement.reserve(link_count * static_cast<std::size_t>(segments + 1) * 3);
  std::vector<std::int32_t> known(link_count, 0);
  double largest = 0;
  for (std::size_t i = 0; i < link_count; ++i) {
    const Link& link = model.links[i];
    static const LinkResult unsolved;
    const LinkResult& solved = i < result->links.size() ? result->links[i] : unsolved;
    const auto& from = end_deflection(solved, LinkEnd::from);
    const auto& to = end_deflection(solved, LinkEnd::to);
    const int from_point = index.of_link_end(i, LinkEnd::from),
              to_point = index.of_link_end(i, LinkEnd::to);
    known[i] = from && to && from_point >= 0 && to_point >= 0;
    for (int s = 0; s <= segments; ++s) {
      Vec3 d = Vec3::Zero();
      if (known[i]) {
        d = centre_line_motion(bends(link.kind),
                               model.points[static_cast<std::size_t>(from_point)].position,
                               model.points[static_cast<std::size_t>(to_point)].position, *from,
                               *to, static_cast<double>(s) / segments)
                .displacement;
        largest = std::max(largest, d.norm());
      }
      const auto f = to_floats(d);
      displacement.insert(displacement.end(), f.begin(), f.end());
    }
  }
  const double automatic = largest > 0 ? kDrawnDisplacementFraction * size / largest : 1;
  deformed["segments"] = segments;
  deformed["displacement"] = detail::base64_of(displacement);
  deformed["known"] = detail::base64_of(known);
  deformed["largest_displacement"] = largest;
  deformed["automatic_scale"] = automatic;
  deformed["scale"] = options.scale.value_or(automatic);
  return deformed;
}

json end_effectors_json(const Model& model, const Result* result, const ModelPoints& index) {
  json list = json::array();
  for (std::size_t i = 0; i < model.end_effectors.size(); ++i) {
    const EndEffector& effector = model.end_effectors[i];
    json entry = {{"name", effector.name}, {"at", index.of_name(effector.at)}, {"link", nullptr}};
    if (result && i < result->end_effectors.size()) {
      const EndEffectorResult& solved = result->end_effectors[i];
      entry["link"] = solved.link;
      if (solved.compliance) {
        const PrincipalAxes axes = principal_axes(solved.compliance->topLeftCorner<3, 3>());
        entry["compliance"] = vector_json(axes.compliance);
        json stiffness = json::array();
        for (int k = 0; k < 3; ++k)
          stiffness.push_back(std::isfinite(axes.stiffness(k)) ? json(axes.stiffness(k))
                                                               : json(nullptr));
        entry["stiffness"] = stiffness;
        json directions = json::array();
        for (int k = 0; k < 3; ++k) directions.push_back(vector_json(axes.directions.col(k)));
        entry["directions"] = directions;
      }
      if (solved.deflection) entry["deflection"] = vector_json(*solved.deflection);
    }
    list.push_back(entry);
  }
  return list;
}

// Loads along links as arrows at places along the link (`at` −1, `position` its place): a point
// load at its own place; a distributed load as kLinkLoadArrows arrows at the middles of equal
// parts of the link, each the force on its part, so that they scale with the point loads.
constexpr int kLinkLoadArrows = 5;
void add_link_loads_json(const Model& model, const ModelPoints& index, json& loads) {
  std::map<std::string, std::size_t, std::less<>> links;
  for (std::size_t i = 0; i < model.links.size(); ++i) links.emplace(model.links[i].name, i);
  for (const LinkLoad& load : model.link_loads) {
    const auto found = links.find(load.link);
    if (found == links.end()) continue;
    const int from = index.of_link_end(found->second, LinkEnd::from),
              to = index.of_link_end(found->second, LinkEnd::to);
    if (from < 0 || to < 0) continue;
    const Vec3& a = model.points[static_cast<std::size_t>(from)].position;
    const Vec3& b = model.points[static_cast<std::size_t>(to)].position;
    const auto arrow = [&](double xi, const Vec3& force, const Vec3& moment) {
      loads.push_back({{"at", -1},
                       {"position", vector_json(a + xi * (b - a))},
                       {"force", vector_json(force)},
                       {"moment", vector_json(moment)}});
    };
    if (const auto* point = std::get_if<PointLinkLoad>(&load.load)) {
      arrow(point->position, point->force, point->moment);
      continue;
    }
    const auto& distributed = std::get<DistributedLinkLoad>(load.load);
    const double part = (b - a).norm() / kLinkLoadArrows;
    for (int k = 0; k < kLinkLoadArrows; ++k) {
      const double xi = (k + 0.5) / kLinkLoadArrows;
      arrow(xi, part * ((1 - xi) * distributed.from + xi * distributed.to), Vec3::Zero());
    }
  }
}

json model_json(const Model& model, const Result* result, const ModelViewOptions& options) {
  const ModelPoints index(model);
  const double size = model_size(model);

  json point_names = json::array();
  std::vector<float> xyz;
  for (const Point& p : model.points) {
    point_names.push_back(p.name);
    const auto f = to_floats(p.position);
    xyz.insert(xyz.end(), f.begin(), f.end());
  }

  json link_names = json::array();
  std::vector<std::int32_t> ends, kinds;
  std::vector<float> sections, y_axes;
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    const Link& link = model.links[i];
    link_names.push_back(link.name);
    const int from = index.of_link_end(i, LinkEnd::from), to = index.of_link_end(i, LinkEnd::to);
    ends.push_back(from);
    ends.push_back(to);
    kinds.push_back(link_kind_code(link.kind));
    DrawnSection drawn{0, 0, true};
    Vec3 y_axis = Vec3::Zero();
    if (const auto* beam = std::get_if<BeamLink>(&link.kind)) {
      drawn = drawn_section(beam->section);
      const Vec3& a = model.points[static_cast<std::size_t>(from)].position;
      const Vec3& b = model.points[static_cast<std::size_t>(to)].position;
      if ((b - a).norm() > 0) y_axis = beam_y_axis(a, b, beam->zref);
    }
    sections.insert(sections.end(),
                    {float(drawn.width), float(drawn.height), drawn.round ? 1.0f : 0.0f});
    const auto f = to_floats(y_axis);
    y_axes.insert(y_axes.end(), f.begin(), f.end());
  }

  json loads = json::array();
  for (const Load& load : model.loads) {
    loads.push_back({{"at", index.of_name(load.at)},
                     {"force", vector_json(load.wrench.head<3>())},
                     {"moment", vector_json(load.wrench.tail<3>())}});
  }
  add_link_loads_json(model, index, loads);

  json notes = json::array();
  if (result) {
    for (const std::string& w : result->report.warnings) notes.push_back(w);
    for (const std::string& n : result->report.notes) notes.push_back(n);
  }

  return {
      {"format", "stiffmsa-view/1"},
      {"name", model.name},
      {"source", std::filesystem::path(model.source_file).filename().string()},
      {"parameters", options.parameters},
      {"size", size},
      {"link_kinds", kLinkKindNames},
      {"roles", kRoleNames},
      {"points", {{"names", point_names}, {"xyz", detail::base64_of(xyz)}}},
      {"links",
       {{"names", link_names},
        {"ends", detail::base64_of(ends)},
        {"kinds", detail::base64_of(kinds)},
        {"sections", detail::base64_of(sections)},
        {"y_axes", detail::base64_of(y_axes)}}},
      {"joints", connections_json(model.joints, index)},
      {"supports", connections_json(model.supports, index)},
      {"loads", loads},
      {"end_effectors", end_effectors_json(model, result, index)},
      {"deformed", deformed_json(model, result, index, options, size)},
      {"notes", notes},
  };
}

}  // namespace

std::string json_for_script_block(const std::string& json_text) {
  std::string safe;
  safe.reserve(json_text.size());
  for (const char c : json_text) {
    switch (c) {
      case '<': safe += "\\u003c"; break;
      case '>': safe += "\\u003e"; break;
      case '&': safe += "\\u0026"; break;
      default: safe += c;
    }
  }
  return safe;
}

namespace detail {

std::string page_from_template(std::string_view page_template, const std::string& json_text,
                               std::string_view page_js) {
  const auto script = [](std::string_view code) {
    return "<script>" + std::string(code) + "</script>\n";
  };
  const std::pair<std::string_view, std::string> parts[] = {
      {"<!--stiffmsa:style-->", "<style>" + std::string(viewer_css()) + "</style>"},
      {"<!--stiffmsa:data-->", "<script type=\"application/json\" id=\"stiffmsa-data\">" +
                                   json_for_script_block(json_text) + "</script>"},
      {"<!--stiffmsa:scripts-->",
       script(three_js()) + script(orbit_controls_js()) + script(page_js)},
  };
  std::string page(page_template);
  for (const auto& [marker, text] : parts) {
    const auto at = page.find(marker);
    if (at == std::string::npos)
      throw std::logic_error("viewer template without " + std::string(marker));
    page.replace(at, marker.size(), text);
  }
  return page;
}

}  // namespace detail

std::string model_view_html(const Model& model, const Result* result,
                            const ModelViewOptions& options) {
  if (options.scale && !(std::isfinite(*options.scale) && *options.scale > 0))
    throw UsageError("the deformation scale must be a positive number, got " +
                     std::to_string(*options.scale));
  if (options.beam_segments && *options.beam_segments < 1)
    throw UsageError("the beam segments of the deformed shape must be at least 1");
  const json data = model_json(model, result, options);
  return detail::page_from_template(detail::model_view_template(),
                                    data.dump(-1, ' ', false, json::error_handler_t::replace),
                                    detail::model_view_js());
}

void write_model_view(const Model& model, const Result* result, const ModelViewOptions& options,
                      const std::filesystem::path& file) {
  write_file_atomically(file, model_view_html(model, result, options));
}

}  // namespace stiffmsa

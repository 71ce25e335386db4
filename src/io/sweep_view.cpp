// The sweep map's page: the sweep's columns as JSON data inside a page that draws them on a
// canvas (src/io/viewer/sweep_view.js).
#include "stiffmsa/io/sweep_view.hpp"

#include <limits>
#include <nlohmann/json.hpp>

#include "io/view_assets.hpp"
#include "io/view_page.hpp"
#include "stiffmsa/io/result_file.hpp"
#include "stiffmsa/io/sweep_file.hpp"

namespace stiffmsa {
namespace {

using nlohmann::json;

json sweep_json(const SweepResult& sweep) {
  const std::size_t poses = sweep.poses.size();
  json parameters = json::array();
  for (std::size_t k = 0; k < sweep.poses.parameters.size(); ++k) {
    std::vector<float> values(poses);
    for (std::size_t i = 0; i < poses; ++i) values[i] = static_cast<float>(sweep.poses.pose(i)[k]);
    parameters.push_back({{"name", sweep.poses.parameters[k]},
                          {"unit", k < sweep.units.size() ? sweep.units[k] : ""},
                          {"values", detail::base64_of(values)}});
  }
  json grid = json::array();
  for (const GridAxis& axis : sweep.poses.grid)
    grid.push_back({{"parameter", axis.parameter},
                    {"start", axis.start},
                    {"stop", axis.stop},
                    {"count", axis.count}});

  // The summary columns (principal stiffnesses, deflections); the 72 matrix entries of --full
  // are shown as ellipsoids instead.
  json columns = json::array();
  for (const SweepColumn& column : sweep_columns(sweep, false)) {
    std::vector<float> values(poses);
    for (std::size_t i = 0; i < poses; ++i)
      values[i] = static_cast<float>(column_value(sweep, column, i));
    columns.push_back({{"name", column.name},
                       {"unit", column.unit},
                       {"worst_is_largest", column.worst_is_largest},
                       {"values", detail::base64_of(values)}});
  }

  json status = json::array(), messages = json::object();
  for (std::size_t i = 0; i < poses; ++i) {
    const PoseResult& result = sweep.results[i];
    status.push_back(to_string(result.status));
    if (!result.message.empty()) messages[std::to_string(i)] = result.message;
  }

  // Per end effector and pose: principal compliances (3) and their directions (9, by columns),
  // NaN where the pose kept no matrix.
  json ellipsoids = json::array();
  bool any_matrix = false;
  for (std::size_t e = 0; e < sweep.end_effectors.size(); ++e) {
    std::vector<float> axes(poses * 12, std::numeric_limits<float>::quiet_NaN());
    for (std::size_t i = 0; i < poses; ++i) {
      const PoseResult& result = sweep.results[i];
      if (e >= result.end_effectors.size() || !result.end_effectors[e].compliance) continue;
      any_matrix = true;
      const PrincipalAxes principal =
          principal_axes(result.end_effectors[e].compliance->topLeftCorner<3, 3>());
      for (int k = 0; k < 3; ++k)
        axes[i * 12 + static_cast<std::size_t>(k)] = static_cast<float>(principal.compliance(k));
      for (int k = 0; k < 9; ++k)
        axes[i * 12 + 3 + static_cast<std::size_t>(k)] =
            static_cast<float>(principal.directions.data()[k]);
    }
    ellipsoids.push_back(detail::base64_of(axes));
  }

  return {{"format", "stiffmsa-sweep-view/1"},
          {"model", sweep.model},
          {"poses", poses},
          {"parameters", parameters},
          {"grid", grid},
          {"end_effectors", sweep.end_effectors},
          {"columns", columns},
          {"status", status},
          {"messages", messages},
          {"ellipsoids", any_matrix ? ellipsoids : json(nullptr)}};
}

}  // namespace

std::string sweep_view_html(const SweepResult& sweep) {
  return detail::page_from_template(
      detail::sweep_view_template(),
      sweep_json(sweep).dump(-1, ' ', false, json::error_handler_t::replace),
      detail::sweep_view_js());
}

void write_sweep_view(const SweepResult& sweep, const std::filesystem::path& file) {
  write_file_atomically(file, sweep_view_html(sweep));
}

}  // namespace stiffmsa

// VTK XML files for ParaView, in ASCII: readable by ParaView, meshio and a person.
#include "stiffmsa/io/vtk_file.hpp"

#include <cctype>
#include <cstdio>
#include <utility>

#include "stiffmsa/deformed_shape.hpp"
#include "stiffmsa/io/result_file.hpp"
#include "stiffmsa/number_text.hpp"

namespace stiffmsa {
namespace {

namespace fs = std::filesystem;

constexpr int kVtkLine = 3;  // VTK's cell type of a straight two-point line

void append_number(std::string& out, double value) {
  append_shortest_text(out, value);
  out += ' ';
}

// Text with '&', '<', '>' and '"' escaped, for an XML attribute or comment.
std::string xml_escaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

struct DataArray {
  std::string name;
  std::string type;  // "Float64" or "Int32"
  int components;
  std::string values;
};

void append_array(std::string& out, const DataArray& array) {
  out += "        <DataArray type=\"" + array.type + "\" Name=\"" + array.name +
         "\" NumberOfComponents=\"" + std::to_string(array.components) + "\" format=\"ascii\">\n" +
         array.values + "\n        </DataArray>\n";
}

}  // namespace

std::string vtu_text(const Model& model, const Result& result, int beam_segments) {
  const ModelPoints index(model);
  DataArray points{"Points", "Float64", 3, {}}, displacement{"displacement", "Float64", 3, {}},
      rotation{"rotation", "Float64", 3, {}}, point_determined{"determined", "Int32", 1, {}};
  DataArray connectivity{"connectivity", "Int32", 1, {}}, offsets{"offsets", "Int32", 1, {}},
      types{"types", "Int32", 1, {}};
  DataArray link{"link", "Int32", 1, {}}, link_kind{"link_kind", "Int32", 1, {}},
      wrench_from{"end_wrench_from", "Float64", 6, {}},
      wrench_to{"end_wrench_to", "Float64", 6, {}}, cell_determined{"determined", "Int32", 1, {}};
  long point_count = 0, cell_count = 0;
  static const LinkResult unsolved;
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    const int from_point = index.of_link_end(i, LinkEnd::from);
    const int to_point = index.of_link_end(i, LinkEnd::to);
    if (from_point < 0 || to_point < 0) continue;
    const Vec3& from = model.points[static_cast<std::size_t>(from_point)].position;
    const Vec3& to = model.points[static_cast<std::size_t>(to_point)].position;
    const LinkResult& solved = i < result.links.size() ? result.links[i] : unsolved;
    const bool known = solved.from.deflection && solved.to.deflection;
    const int segments = bends(model.links[i].kind) ? beam_segments : 1;
    for (int s = 0; s <= segments; ++s) {
      const double xi = static_cast<double>(s) / segments;
      const Vec3 position = from + xi * (to - from);
      CentreLineMotion motion;
      if (known)
        motion = centre_line_motion(bends(model.links[i].kind), from, to, *solved.from.deflection,
                                    *solved.to.deflection, xi);
      for (int k = 0; k < 3; ++k) {
        append_number(points.values, position(k));
        append_number(displacement.values, motion.displacement(k));
        append_number(rotation.values, motion.rotation(k));
      }
      point_determined.values += known ? "1 " : "0 ";
    }
    for (int s = 0; s < segments; ++s) {
      connectivity.values +=
          std::to_string(point_count + s) + ' ' + std::to_string(point_count + s + 1) + ' ';
      ++cell_count;
      offsets.values += std::to_string(2 * cell_count) + ' ';
      types.values += std::to_string(kVtkLine) + ' ';
      link.values += std::to_string(i) + ' ';
      link_kind.values += std::to_string(model.links[i].kind.index()) + ' ';
      const bool wrenches_known = solved.from.wrench && solved.to.wrench;
      for (int k = 0; k < 6; ++k) {
        append_number(wrench_from.values, wrenches_known ? (*solved.from.wrench)(k) : 0.0);
        append_number(wrench_to.values, wrenches_known ? (*solved.to.wrench)(k) : 0.0);
      }
      cell_determined.values += wrenches_known ? "1 " : "0 ";
    }
    point_count += segments + 1;
  }

  std::string out = "<?xml version=\"1.0\"?>\n<!-- stiffmsa: model " + xml_escaped(model.name) +
                    "; link_kind 0 beam, 1 rigid, 2 matrix, 3 compliance; end wrenches [F; M] "
                    "applied to the link, "
                    "global axes; SI units -->\n";
  out +=
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n  "
      "<UnstructuredGrid>\n";
  out += "    <Piece NumberOfPoints=\"" + std::to_string(point_count) + "\" NumberOfCells=\"" +
         std::to_string(cell_count) + "\">\n";
  out += "      <PointData Vectors=\"displacement\">\n";
  for (const DataArray* a : {&displacement, &rotation, &point_determined}) append_array(out, *a);
  out += "      </PointData>\n      <CellData Scalars=\"link_kind\">\n";
  for (const DataArray* a : {&link, &link_kind, &wrench_from, &wrench_to, &cell_determined})
    append_array(out, *a);
  out += "      </CellData>\n      <Points>\n";
  append_array(out, points);
  out += "      </Points>\n      <Cells>\n";
  for (const DataArray* a : {&connectivity, &offsets, &types}) append_array(out, *a);
  out += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

std::string pvd_text(const std::vector<VtkCollectionEntry>& entries) {
  std::string out =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" "
      "byte_order=\"LittleEndian\">\n  <Collection>\n";
  for (std::size_t i = 0; i < entries.size(); ++i) {
    out += "    <DataSet timestep=\"" + std::to_string(i) + "\" part=\"0\" name=\"" +
           xml_escaped(entries[i].name) + "\" file=\"" +
           xml_escaped(entries[i].file.generic_string()) + "\"/>\n";
  }
  out += "  </Collection>\n</VTKFile>\n";
  return out;
}

namespace {

// A load case's name as part of a file name: letters, digits, '-' and '_' kept, others '_'.
std::string file_safe(const std::string& name) {
  std::string safe = name;
  for (char& c : safe)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return safe;
}

// Every load case of a result with its results: the unnamed case as "loads" where the top level
// is it, then each named case.
std::vector<std::pair<std::string, const Result*>> cases_of(const Result& result) {
  std::vector<std::pair<std::string, const Result*>> cases;
  if (result.load_case.empty()) cases.emplace_back("loads", &result);
  for (const Result& c : result.load_cases) cases.emplace_back(c.load_case, &c);
  return cases;
}

}  // namespace

std::vector<fs::path> write_vtk(const Model& model, const Result& result, const fs::path& file) {
  const std::string extension = file.extension().string();
  if (extension != ".vtu" && extension != ".pvd") {
    std::string message = "'";  // built in steps: GCC 12 warns wrongly (-Wrestrict) on "'" + string
    message += file.string();
    message +=
        "': a ParaView file must end in .vtu (one grid) or .pvd (a collection of load cases)";
    throw UsageError(message);
  }
  std::vector<fs::path> written;
  // A .vtu of a model without named load cases is its one grid; with them, it holds the
  // top-level results and a collection beside it holds every case's.
  if (extension == ".vtu") {
    write_file_atomically(file, vtu_text(model, result));
    written.push_back(file);
    if (result.load_cases.empty()) return written;
  }
  std::vector<VtkCollectionEntry> entries;
  for (const auto& [name, case_result] : cases_of(result)) {
    const fs::path grid_name = file.stem().string() + "-" + file_safe(name) + ".vtu";
    const fs::path grid = file.parent_path() / grid_name;
    write_file_atomically(grid, vtu_text(model, *case_result));
    written.push_back(grid);
    entries.push_back({name, grid_name});
  }
  fs::path collection = file;
  collection.replace_extension(".pvd");
  write_file_atomically(collection, pvd_text(entries));
  written.push_back(collection);
  return written;
}

}  // namespace stiffmsa

#pragma once
// ParaView files (docs/viewer.md): a model with its result as a VTK XML unstructured grid
// (.vtu), and a ParaView collection (.pvd) that names one .vtu per load case. Each link is a
// line, a beam cut into pieces that follow its deflected shape (deformed_shape.hpp); point data
// `displacement` and `rotation`, cell data `link`, `link_kind` and the wrenches at the link's
// ends, with `determined` telling where the solve left a value undetermined (written as 0).
#include <filesystem>
#include <string>
#include <vector>

#include "stiffmsa/model.hpp"
#include "stiffmsa/result.hpp"

namespace stiffmsa {

// Pieces per beam in the .vtu files.
constexpr int kVtkBeamSegments = 8;

// The .vtu text of a model and its result.
std::string vtu_text(const Model& model, const Result& result,
                     int beam_segments = kVtkBeamSegments);

// One data set of a collection: a load case's name and its .vtu, relative to the .pvd.
struct VtkCollectionEntry {
  std::string name;
  std::filesystem::path file;
};
std::string pvd_text(const std::vector<VtkCollectionEntry>& entries);

// Writes `file`, whole or not at all: a .vtu, or a .pvd with one .vtu per load case beside it
// (STEM-loads.vtu for the model's unnamed case, STEM-NAME.vtu for each named one). A .vtu of a
// model with named load cases holds the top-level results and gets that collection beside it
// too (STEM.pvd). Returns the files written. Throws UsageError for another extension, IoError
// when a file cannot be written.
std::vector<std::filesystem::path> write_vtk(const Model& model, const Result& result,
                                             const std::filesystem::path& file);

}  // namespace stiffmsa

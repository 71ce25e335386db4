#pragma once
// The sweep map (`stiffmsa sweep --view`): one self-contained HTML page with the map of any
// result column over a 2-D grid (a strip over a 1-D grid or a list of poses), the row of values
// of the pose under the mouse and, where the sweep kept its matrices (`--full`), that pose's
// translational compliance ellipsoid of each end effector seen along x, y and z.
#include <filesystem>
#include <string>

#include "stiffmsa/sweep.hpp"

namespace stiffmsa {

std::string sweep_view_html(const SweepResult& sweep);

// Writes that page whole or not at all. Throws IoError.
void write_sweep_view(const SweepResult& sweep, const std::filesystem::path& file);

}  // namespace stiffmsa

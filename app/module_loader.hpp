#pragma once
// The command's modules: parts built as shared modules and loaded with dlopen when a run needs
// them (the plots and cairo, HDF5 and the libraries it brings), so that `stiffmsa --version` or a
// solve loads none of them (docs/library.md, "The command's modules").
#include <string>

namespace stiffmsa::cli {

// The module's entry `entry` (an extern "C" function taking nothing), from the module file
// `file_name` beside the command (a build folder) or in its install's library folder. Loaded on
// the first call and kept. Throws IoError naming `what` when the module cannot be loaded.
void* module_entry(const std::string& file_name, const char* entry, const std::string& what);

}  // namespace stiffmsa::cli

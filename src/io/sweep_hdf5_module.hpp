#pragma once
// The HDF5 module (target stiffmsa_sweep_hdf5_module): the sweep's HDF5 writer built as a shared
// module that the command loads with dlopen when it writes HDF5, so that its other runs do not
// load libhdf5 and the dozens of libraries it brings (docs/library.md, "The command's modules").
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "stiffmsa/io/sweep_file.hpp"

namespace stiffmsa::detail {

inline constexpr const char* kHdf5ModuleFile = "stiffmsa_hdf5.so";
inline constexpr const char* kHdf5ModuleEntry = "stiffmsa_hdf5_module";

// What the module's entry returns: SweepHdf5Writer's and SweepHdf5Reader's members on opaque
// objects. The sizes tell
// a module built from other headers (a stale install) from this command's.
struct Hdf5Module {
  std::size_t rows_size = sizeof(SweepRows);
  std::size_t summary_size = sizeof(SweepSummary);
  std::size_t column_size = sizeof(SweepColumn);
  void* (*open)(const std::filesystem::path& target, const std::vector<std::string>& parameters,
                const std::vector<std::string>& parameter_units,
                const std::vector<SweepColumn>& columns) = nullptr;
  void (*close)(void* writer) = nullptr;
  const std::filesystem::path& (*temporary_path)(const void* writer) = nullptr;
  void (*append)(void* writer, const SweepRows& rows) = nullptr;
  void (*commit)(void* writer, const std::string& summary_json,
                 const SweepSummary& summary) = nullptr;
  void* (*open_reader)(const std::filesystem::path& file,
                       const std::vector<std::string>& parameters,
                       const std::vector<SweepColumn>& columns) = nullptr;
  void (*close_reader)(void* reader) = nullptr;
  SweepRows (*read)(void* reader, std::size_t first_pose, std::size_t count) = nullptr;
  std::size_t (*rows_read)(const void* reader) = nullptr;
  std::optional<std::string> (*summary_of)(const std::filesystem::path& file) = nullptr;
};

}  // namespace stiffmsa::detail

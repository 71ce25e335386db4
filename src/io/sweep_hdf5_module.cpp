// The HDF5 module's entry point (src/io/sweep_hdf5_module.hpp); everything else is hidden.
#include "io/sweep_hdf5_module.hpp"

#include "stiffmsa/io/sweep_hdf5.hpp"

namespace {

using stiffmsa::SweepHdf5Reader;
using stiffmsa::SweepHdf5Writer;

SweepHdf5Writer& writer_of(void* writer) { return *static_cast<SweepHdf5Writer*>(writer); }

}  // namespace

extern "C" __attribute__((visibility("default"))) const stiffmsa::detail::Hdf5Module*
stiffmsa_hdf5_module() {
  static const stiffmsa::detail::Hdf5Module module{
      sizeof(stiffmsa::SweepRows),
      sizeof(stiffmsa::SweepSummary),
      sizeof(stiffmsa::SweepColumn),
      [](const std::filesystem::path& target, const std::vector<std::string>& parameters,
         const std::vector<std::string>& parameter_units,
         const std::vector<stiffmsa::SweepColumn>& columns) -> void* {
        return new SweepHdf5Writer(target, parameters, parameter_units, columns);
      },
      [](void* writer) { delete static_cast<SweepHdf5Writer*>(writer); },
      [](const void* writer) -> const std::filesystem::path& {
        return static_cast<const SweepHdf5Writer*>(writer)->temporary_path();
      },
      [](void* writer, const stiffmsa::SweepRows& rows) { writer_of(writer).append(rows); },
      [](void* writer, const std::string& summary_json, const stiffmsa::SweepSummary& summary) {
        writer_of(writer).commit(summary_json, summary);
      },
      [](const std::filesystem::path& file, const std::vector<std::string>& parameters,
         const std::vector<stiffmsa::SweepColumn>& columns) -> void* {
        return new SweepHdf5Reader(file, parameters, columns);
      },
      [](void* reader) { delete static_cast<SweepHdf5Reader*>(reader); },
      [](void* reader, std::size_t first_pose, std::size_t count) {
        return static_cast<SweepHdf5Reader*>(reader)->read(first_pose, count);
      },
      [](const void* reader) { return static_cast<const SweepHdf5Reader*>(reader)->rows_read(); },
      [](const std::filesystem::path& file) { return SweepHdf5Reader::summary_of(file); }};
  return &module;
}

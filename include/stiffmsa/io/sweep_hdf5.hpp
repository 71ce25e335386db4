#pragma once
// Sweep rows in HDF5 (target stiffmsa_sweep_hdf5, built when HDF5 is found): one dataset per
// CSV column at the file's root, extended block by block so that memory does not grow with
// the number of poses; the summary as attributes (docs/model-format.md, "Sweep files").
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "stiffmsa/io/sweep_file.hpp"

namespace stiffmsa {

class SweepHdf5Writer {
 public:
  // The file appears at `target` whole at commit(), or not at all. Throws IoError.
  SweepHdf5Writer(const std::filesystem::path& target, const std::vector<std::string>& parameters,
                  const std::vector<std::string>& parameter_units, const std::vector<SweepColumn>& columns);
  SweepHdf5Writer(const SweepHdf5Writer&) = delete;
  SweepHdf5Writer& operator=(const SweepHdf5Writer&) = delete;
  ~SweepHdf5Writer();

  const std::filesystem::path& temporary_path() const;
  // The next rows, in pose order.
  void append(const SweepRows& rows);
  // Root attributes: `summary` (the summary JSON), `poses`, and the count of each status.
  void commit(const std::string& summary_json, const SweepSummary& summary);

 private:
  struct File;
  std::unique_ptr<File> file_;
};

}  // namespace stiffmsa

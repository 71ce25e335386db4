#pragma once
// Sweep rows in HDF5 (target stiffmsa_sweep_hdf5, built when HDF5 is found): one dataset per
// CSV column at the file's root, extended block by block so that memory does not grow with
// the number of poses; the summary as attributes (docs/model-format.md, "Sweep files").
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "stiffmsa/io/sweep_file.hpp"

namespace stiffmsa {

class SweepHdf5Writer {
 public:
  // The file appears at `target` whole at commit(), or not at all. Throws IoError.
  SweepHdf5Writer(const std::filesystem::path& target, const std::vector<std::string>& parameters,
                  const std::vector<std::string>& parameter_units,
                  const std::vector<SweepColumn>& columns);
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

// The rows of an HDF5 file the writer above wrote, read block by block (to join the parts of a
// sharded sweep). Throws IoError when the file cannot be read and InputError (the file, a
// column) for a file that is not a sweep of these columns.
class SweepHdf5Reader {
 public:
  SweepHdf5Reader(const std::filesystem::path& file, const std::vector<std::string>& parameters,
                  const std::vector<SweepColumn>& columns);
  SweepHdf5Reader(const SweepHdf5Reader&) = delete;
  SweepHdf5Reader& operator=(const SweepHdf5Reader&) = delete;
  ~SweepHdf5Reader();

  // Up to `count` rows, the first being pose `first_pose`; fewer at the end of the file.
  SweepRows read(std::size_t first_pose, std::size_t count);
  std::size_t rows_read() const;
  // The file's root attribute `summary` (the summary JSON), if it is a file of this writer's.
  static std::optional<std::string> summary_of(const std::filesystem::path& file);

 private:
  struct File;
  std::unique_ptr<File> file_;
};

}  // namespace stiffmsa

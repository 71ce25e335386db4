// stiffmsa::SweepHdf5Writer and SweepHdf5Reader for the command: forwarded to the HDF5 module,
// loaded when the first HDF5 file is written (src/io/sweep_hdf5_module.hpp), so that the command
// itself links no HDF5.
#include "io/sweep_hdf5_module.hpp"
#include "module_loader.hpp"
#include "stiffmsa/errors.hpp"
#include "stiffmsa/io/sweep_hdf5.hpp"

namespace stiffmsa {

namespace {

const detail::Hdf5Module& hdf5_module() {
  using Entry = const detail::Hdf5Module* (*)();
  const auto entry = reinterpret_cast<Entry>(cli::module_entry(
      detail::kHdf5ModuleFile, detail::kHdf5ModuleEntry, "the HDF5 module (--hdf5)"));
  const detail::Hdf5Module* module = entry();
  if (module->rows_size != sizeof(SweepRows) || module->summary_size != sizeof(SweepSummary) ||
      module->column_size != sizeof(SweepColumn))
    throw IoError("the HDF5 module was built from another version of stiffmsa than this command");
  return *module;
}

}  // namespace

struct SweepHdf5Writer::File {
  const detail::Hdf5Module& module;
  void* writer;
};

SweepHdf5Writer::SweepHdf5Writer(const std::filesystem::path& target,
                                 const std::vector<std::string>& parameters,
                                 const std::vector<std::string>& parameter_units,
                                 const std::vector<SweepColumn>& columns) {
  const detail::Hdf5Module& module = hdf5_module();
  file_ = std::make_unique<File>(
      File{module, module.open(target, parameters, parameter_units, columns)});
}

SweepHdf5Writer::~SweepHdf5Writer() {
  if (file_) file_->module.close(file_->writer);
}

const std::filesystem::path& SweepHdf5Writer::temporary_path() const {
  return file_->module.temporary_path(file_->writer);
}

void SweepHdf5Writer::append(const SweepRows& rows) { file_->module.append(file_->writer, rows); }

void SweepHdf5Writer::commit(const std::string& summary_json, const SweepSummary& summary) {
  file_->module.commit(file_->writer, summary_json, summary);
}

struct SweepHdf5Reader::File {
  const detail::Hdf5Module& module;
  void* reader;
};

SweepHdf5Reader::SweepHdf5Reader(const std::filesystem::path& file,
                                 const std::vector<std::string>& parameters,
                                 const std::vector<SweepColumn>& columns) {
  const detail::Hdf5Module& module = hdf5_module();
  file_ = std::make_unique<File>(File{module, module.open_reader(file, parameters, columns)});
}

SweepHdf5Reader::~SweepHdf5Reader() {
  if (file_) file_->module.close_reader(file_->reader);
}

SweepRows SweepHdf5Reader::read(std::size_t first_pose, std::size_t count) {
  return file_->module.read(file_->reader, first_pose, count);
}

std::size_t SweepHdf5Reader::rows_read() const { return file_->module.rows_read(file_->reader); }

std::optional<std::string> SweepHdf5Reader::summary_of(const std::filesystem::path& file) {
  return hdf5_module().summary_of(file);
}

}  // namespace stiffmsa

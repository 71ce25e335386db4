#include "stiffmsa/io/sweep_hdf5.hpp"

#include <hdf5.h>

#include <array>
#include <cstdint>
#include <optional>

#include "stiffmsa/errors.hpp"
#include "stiffmsa/io/atomic_file.hpp"

namespace stiffmsa {
namespace {

// Rows per HDF5 chunk: large enough for fast appends, small enough that the chunk cache of a
// --full file (80 datasets per end effector) stays in megabytes.
constexpr hsize_t kChunkRows = 16384;

// An HDF5 identifier closed by the function that matches it.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(Handle&& other) noexcept : id_(other.id_), close_(other.close_) { other.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& other) noexcept {
    std::swap(id_, other.id_);
    std::swap(close_, other.close_);
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  hid_t get() const { return id_; }
  herr_t reset() {
    const herr_t status = id_ >= 0 && close_ ? close_(id_) : 0;
    id_ = H5I_INVALID_HID;
    return status;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  herr_t (*close_)(hid_t) = nullptr;
};

std::string hdf5_error(const std::filesystem::path& file, const std::string& what) {
  return "cannot write the HDF5 file '" + file.string() + "': " + what;
}

}  // namespace

struct SweepHdf5Writer::File {
  std::filesystem::path target;
  AtomicFileWriter temporary;
  Handle file, text_type, status_type;
  struct Dataset {
    Handle id;
    hid_t type = H5I_INVALID_HID;
  };
  std::vector<Dataset> parameters, values;
  Dataset status, message;
  hsize_t rows = 0;

  explicit File(const std::filesystem::path& path) : target(path), temporary(path) {}

  hid_t check(hid_t id, const std::string& what) const {
    if (id < 0) throw IoError(hdf5_error(target, what));
    return id;
  }

  Dataset create(const std::string& name, hid_t type, const std::string& unit) {
    const hsize_t empty = 0, unlimited = H5S_UNLIMITED;
    Handle space(check(H5Screate_simple(1, &empty, &unlimited), "a dataspace"), H5Sclose);
    Handle properties(check(H5Pcreate(H5P_DATASET_CREATE), "dataset properties"), H5Pclose);
    check(H5Pset_chunk(properties.get(), 1, &kChunkRows), "chunking");
    Dataset dataset{Handle(check(H5Dcreate2(file.get(), name.c_str(), type, space.get(), H5P_DEFAULT,
                                            properties.get(), H5P_DEFAULT),
                                 "the dataset '" + name + "' (a name used twice?)"),
                           H5Dclose),
                    type};
    if (!unit.empty()) attribute_text(dataset.id.get(), "unit", unit);
    return dataset;
  }

  void attribute_text(hid_t owner, const std::string& name, const std::string& text) {
    Handle space(check(H5Screate(H5S_SCALAR), "a dataspace"), H5Sclose);
    Handle attribute(check(H5Acreate2(owner, name.c_str(), text_type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                           "the attribute '" + name + "'"),
                     H5Aclose);
    const char* data = text.c_str();
    check(H5Awrite(attribute.get(), text_type.get(), &data), "the attribute '" + name + "'");
  }

  void attribute_texts(hid_t owner, const std::string& name, const std::vector<std::string>& texts) {
    const hsize_t count = texts.size();
    Handle space(check(H5Screate_simple(1, &count, nullptr), "a dataspace"), H5Sclose);
    Handle attribute(check(H5Acreate2(owner, name.c_str(), text_type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                           "the attribute '" + name + "'"),
                     H5Aclose);
    std::vector<const char*> data;
    for (const auto& t : texts) data.push_back(t.c_str());
    check(H5Awrite(attribute.get(), text_type.get(), data.data()), "the attribute '" + name + "'");
  }

  void attribute_count(hid_t owner, const std::string& name, std::uint64_t value) {
    Handle space(check(H5Screate(H5S_SCALAR), "a dataspace"), H5Sclose);
    Handle attribute(check(H5Acreate2(owner, name.c_str(), H5T_NATIVE_UINT64, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                           "the attribute '" + name + "'"),
                     H5Aclose);
    check(H5Awrite(attribute.get(), H5T_NATIVE_UINT64, &value), "the attribute '" + name + "'");
  }

  void append(const Dataset& dataset, hsize_t count, const void* data) {
    const hsize_t size = rows + count;
    check(H5Dset_extent(dataset.id.get(), &size), "extending a dataset");
    Handle file_space(check(H5Dget_space(dataset.id.get()), "a dataspace"), H5Sclose);
    check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &rows, nullptr, &count, nullptr), "a selection");
    Handle memory_space(check(H5Screate_simple(1, &count, nullptr), "a dataspace"), H5Sclose);
    check(H5Dwrite(dataset.id.get(), dataset.type, memory_space.get(), file_space.get(), H5P_DEFAULT, data),
          "writing rows (disk full?)");
  }
};

SweepHdf5Writer::SweepHdf5Writer(const std::filesystem::path& target, const std::vector<std::string>& parameters,
                                 const std::vector<std::string>& parameter_units,
                                 const std::vector<SweepColumn>& columns)
    : file_(std::make_unique<File>(target)) {
  // Errors are reported as IoError with our words, not as HDF5's stack on stderr.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  File& f = *file_;
  f.file = Handle(f.check(H5Fcreate(f.temporary.temporary_path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                          "cannot create it"),
                  H5Fclose);
  f.text_type = Handle(f.check(H5Tcopy(H5T_C_S1), "a string type"), H5Tclose);
  f.check(H5Tset_size(f.text_type.get(), H5T_VARIABLE), "a string type");
  f.check(H5Tset_cset(f.text_type.get(), H5T_CSET_UTF8), "a string type");
  // The status as an HDF5 enumeration, which h5py reads with its names (h5py.check_enum_dtype).
  f.status_type = Handle(f.check(H5Tenum_create(H5T_NATIVE_INT8), "the status type"), H5Tclose);
  for (auto status : kPoseStatuses) {
    const auto code = static_cast<std::int8_t>(status);
    f.check(H5Tenum_insert(f.status_type.get(), to_string(status), &code), "the status type");
  }
  std::vector<std::string> names;
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    f.parameters.push_back(f.create(parameters[k], H5T_NATIVE_DOUBLE, k < parameter_units.size() ? parameter_units[k] : ""));
    names.push_back(parameters[k]);
  }
  f.status = f.create("status", f.status_type.get(), "");
  f.message = f.create("message", f.text_type.get(), "");
  names.insert(names.end(), {"status", "message"});
  for (const auto& column : columns) {
    f.values.push_back(f.create(column.name, H5T_NATIVE_DOUBLE, column.unit));
    names.push_back(column.name);
  }
  f.attribute_text(f.file.get(), "format", "stiffmsa-sweep/1");
  f.attribute_texts(f.file.get(), "columns", names);
}

SweepHdf5Writer::~SweepHdf5Writer() = default;

const std::filesystem::path& SweepHdf5Writer::temporary_path() const { return file_->temporary.temporary_path(); }

void SweepHdf5Writer::append(const SweepRows& rows) {
  File& f = *file_;
  const hsize_t count = rows.size();
  if (count == 0) return;
  std::vector<double> column(count);
  for (std::size_t k = 0; k < f.parameters.size(); ++k) {
    for (std::size_t row = 0; row < count; ++row) column[row] = rows.pose(row)[k];
    f.append(f.parameters[k], count, column.data());
  }
  std::vector<std::int8_t> statuses(count);
  std::vector<const char*> messages(count);
  for (std::size_t row = 0; row < count; ++row) {
    statuses[row] = static_cast<std::int8_t>(rows.statuses[row]);
    messages[row] = rows.messages[row].c_str();
  }
  f.append(f.status, count, statuses.data());
  f.append(f.message, count, messages.data());
  for (std::size_t c = 0; c < f.values.size(); ++c) {
    for (std::size_t row = 0; row < count; ++row) column[row] = rows.value(row, c);
    f.append(f.values[c], count, column.data());
  }
  f.rows += count;
}

void SweepHdf5Writer::commit(const std::string& summary_json, const SweepSummary& summary) {
  File& f = *file_;
  f.attribute_text(f.file.get(), "summary", summary_json);
  f.attribute_count(f.file.get(), "poses", summary.poses());
  for (auto status : kPoseStatuses)
    f.attribute_count(f.file.get(), std::string("status.") + to_string(status), summary.count(status));
  f.parameters.clear();
  f.values.clear();
  f.status = {};
  f.message = {};
  if (f.file.reset() < 0) throw IoError(hdf5_error(f.target, "closing it failed (disk full?)"));
  f.temporary.commit();
}

}  // namespace stiffmsa

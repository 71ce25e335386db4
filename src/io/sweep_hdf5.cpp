#include "stiffmsa/io/sweep_hdf5.hpp"

#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>

#include "stiffmsa/errors.hpp"
#include "stiffmsa/io/atomic_file.hpp"
#include "stiffmsa/result.hpp"

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
  Handle(Handle&& other) noexcept : id_(other.id_), close_(other.close_) {
    other.id_ = H5I_INVALID_HID;
  }
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

constexpr const char* kFormat = "stiffmsa-sweep/1";

// Variable-length UTF-8 text, as h5py reads into str. Negative: HDF5 failed.
hid_t make_text_type() {
  const hid_t type = H5Tcopy(H5T_C_S1);
  if (type < 0 || H5Tset_size(type, H5T_VARIABLE) < 0 || H5Tset_cset(type, H5T_CSET_UTF8) < 0)
    return -1;
  return type;
}

// The status as an HDF5 enumeration, which h5py reads with its names (h5py.check_enum_dtype).
// Negative: HDF5 failed.
hid_t make_status_type() {
  const hid_t type = H5Tenum_create(H5T_NATIVE_INT8);
  for (auto status : kPoseStatuses) {
    const auto code = static_cast<std::int8_t>(status);
    if (type < 0 || H5Tenum_insert(type, to_string(status), &code) < 0) return -1;
  }
  return type;
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
    Dataset dataset{Handle(check(H5Dcreate2(file.get(), name.c_str(), type, space.get(),
                                            H5P_DEFAULT, properties.get(), H5P_DEFAULT),
                                 "the dataset '" + name + "' (a name used twice?)"),
                           H5Dclose),
                    type};
    if (!unit.empty()) attribute_text(dataset.id.get(), "unit", unit);
    return dataset;
  }

  void attribute_text(hid_t owner, const std::string& name, const std::string& text) {
    Handle space(check(H5Screate(H5S_SCALAR), "a dataspace"), H5Sclose);
    Handle attribute(check(H5Acreate2(owner, name.c_str(), text_type.get(), space.get(),
                                      H5P_DEFAULT, H5P_DEFAULT),
                           "the attribute '" + name + "'"),
                     H5Aclose);
    const char* data = text.c_str();
    check(H5Awrite(attribute.get(), text_type.get(), &data), "the attribute '" + name + "'");
  }

  void attribute_texts(hid_t owner, const std::string& name,
                       const std::vector<std::string>& texts) {
    const hsize_t count = texts.size();
    Handle space(check(H5Screate_simple(1, &count, nullptr), "a dataspace"), H5Sclose);
    Handle attribute(check(H5Acreate2(owner, name.c_str(), text_type.get(), space.get(),
                                      H5P_DEFAULT, H5P_DEFAULT),
                           "the attribute '" + name + "'"),
                     H5Aclose);
    std::vector<const char*> data;
    for (const auto& t : texts) data.push_back(t.c_str());
    check(H5Awrite(attribute.get(), text_type.get(), data.data()), "the attribute '" + name + "'");
  }

  void attribute_count(hid_t owner, const std::string& name, std::uint64_t value) {
    Handle space(check(H5Screate(H5S_SCALAR), "a dataspace"), H5Sclose);
    Handle attribute(check(H5Acreate2(owner, name.c_str(), H5T_NATIVE_UINT64, space.get(),
                                      H5P_DEFAULT, H5P_DEFAULT),
                           "the attribute '" + name + "'"),
                     H5Aclose);
    check(H5Awrite(attribute.get(), H5T_NATIVE_UINT64, &value), "the attribute '" + name + "'");
  }

  void append(const Dataset& dataset, hsize_t count, const void* data) {
    const hsize_t size = rows + count;
    check(H5Dset_extent(dataset.id.get(), &size), "extending a dataset");
    Handle file_space(check(H5Dget_space(dataset.id.get()), "a dataspace"), H5Sclose);
    check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &rows, nullptr, &count, nullptr),
          "a selection");
    Handle memory_space(check(H5Screate_simple(1, &count, nullptr), "a dataspace"), H5Sclose);
    check(H5Dwrite(dataset.id.get(), dataset.type, memory_space.get(), file_space.get(),
                   H5P_DEFAULT, data),
          "writing rows (disk full?)");
  }
};

SweepHdf5Writer::SweepHdf5Writer(const std::filesystem::path& target,
                                 const std::vector<std::string>& parameters,
                                 const std::vector<std::string>& parameter_units,
                                 const std::vector<SweepColumn>& columns)
    : file_(std::make_unique<File>(target)) {
  // Errors are reported as IoError with our words, not as HDF5's stack on stderr.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  File& f = *file_;
  f.file = Handle(f.check(H5Fcreate(f.temporary.temporary_path().c_str(), H5F_ACC_TRUNC,
                                    H5P_DEFAULT, H5P_DEFAULT),
                          "cannot create it"),
                  H5Fclose);
  f.text_type = Handle(f.check(make_text_type(), "a string type"), H5Tclose);
  f.status_type = Handle(f.check(make_status_type(), "the status type"), H5Tclose);
  std::vector<std::string> names;
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    f.parameters.push_back(f.create(parameters[k], H5T_NATIVE_DOUBLE,
                                    k < parameter_units.size() ? parameter_units[k] : ""));
    names.push_back(parameters[k]);
  }
  f.status = f.create("status", f.status_type.get(), "");
  f.message = f.create("message", f.text_type.get(), "");
  names.insert(names.end(), {"status", "message"});
  for (const auto& column : columns) {
    f.values.push_back(f.create(column.name, H5T_NATIVE_DOUBLE, column.unit));
    names.push_back(column.name);
  }
  f.attribute_text(f.file.get(), "format", kFormat);
  f.attribute_texts(f.file.get(), "columns", names);
}

SweepHdf5Writer::~SweepHdf5Writer() = default;

const std::filesystem::path& SweepHdf5Writer::temporary_path() const {
  return file_->temporary.temporary_path();
}

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
    f.attribute_count(f.file.get(), std::string("status.") + to_string(status),
                      summary.count(status));
  f.parameters.clear();
  f.values.clear();
  f.status = {};
  f.message = {};
  if (f.file.reset() < 0) throw IoError(hdf5_error(f.target, "closing it failed (disk full?)"));
  f.temporary.commit();
}

// ---- reading ---------------------------------------------------------------------------------

namespace {

// A root attribute's text (one string, or every string of a list); nullopt where there is none
// of that kind.
std::optional<std::vector<std::string>> attribute_texts(hid_t file, const char* name) {
  if (H5Aexists(file, name) <= 0) return std::nullopt;
  Handle attribute(H5Aopen(file, name, H5P_DEFAULT), H5Aclose);
  Handle stored_type(attribute.get() < 0 ? -1 : H5Aget_type(attribute.get()), H5Tclose);
  if (stored_type.get() < 0 || H5Tget_class(stored_type.get()) != H5T_STRING ||
      H5Tis_variable_str(stored_type.get()) <= 0)
    return std::nullopt;
  Handle space(H5Aget_space(attribute.get()), H5Sclose);
  Handle text_type(make_text_type(), H5Tclose);
  const hssize_t count = space.get() < 0 ? -1 : H5Sget_simple_extent_npoints(space.get());
  if (count < 0 || text_type.get() < 0) return std::nullopt;
  std::vector<char*> data(static_cast<std::size_t>(count), nullptr);
  if (H5Aread(attribute.get(), text_type.get(), data.data()) < 0) return std::nullopt;
  std::vector<std::string> texts;
  for (char* text : data) texts.emplace_back(text ? text : "");
  H5Dvlen_reclaim(text_type.get(), space.get(), H5P_DEFAULT, data.data());
  return texts;
}

}  // namespace

struct SweepHdf5Reader::File {
  std::string name;
  Handle file, text_type, status_type;
  std::vector<Handle> parameters, values;
  Handle status, message;
  hsize_t rows = 0, rows_read = 0;
  bool sized = false;  // by the first dataset opened

  InputError defect(const std::string& key, const std::string& message) const {
    return InputError({name, 0, 0}, key, message);
  }

  Handle open(const std::string& dataset) {
    Handle id(H5Dopen2(file.get(), dataset.c_str(), H5P_DEFAULT), H5Dclose);
    if (id.get() < 0) throw defect(dataset, "the dataset '" + dataset + "' is missing");
    Handle space(H5Dget_space(id.get()), H5Sclose);
    hsize_t size = 0;
    if (space.get() < 0 || H5Sget_simple_extent_ndims(space.get()) != 1 ||
        H5Sget_simple_extent_dims(space.get(), &size, nullptr) != 1)
      throw defect(dataset, "the dataset '" + dataset + "' is not a column of rows");
    if (!sized) rows = size;
    sized = true;
    if (size != rows)
      throw defect(dataset, "the dataset '" + dataset + "' has " + std::to_string(size) +
                                " rows where the first has " + std::to_string(rows) +
                                " (cut short?)");
    return id;
  }

  // `count` rows of a dataset from the next unread row on, converted to `memory_type`.
  void read(const Handle& dataset, hid_t memory_type, hsize_t count, void* data,
            const std::string& what) const {
    Handle file_space(H5Dget_space(dataset.get()), H5Sclose);
    Handle memory_space(H5Screate_simple(1, &count, nullptr), H5Sclose);
    if (file_space.get() < 0 || memory_space.get() < 0 ||
        H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &rows_read, nullptr, &count,
                            nullptr) < 0 ||
        H5Dread(dataset.get(), memory_type, memory_space.get(), file_space.get(), H5P_DEFAULT,
                data) < 0)
      throw defect(what, "cannot read rows " + std::to_string(rows_read + 1) + " to " +
                             std::to_string(rows_read + count) + " of '" + what +
                             "' (not of the type this sweep writes, or a damaged file)");
  }
};

SweepHdf5Reader::SweepHdf5Reader(const std::filesystem::path& path,
                                 const std::vector<std::string>& parameters,
                                 const std::vector<SweepColumn>& columns)
    : file_(std::make_unique<File>()) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  File& f = *file_;
  f.name = path.string();
  std::error_code error;
  if (std::filesystem::is_directory(path, error) || H5Fis_hdf5(f.name.c_str()) <= 0)
    throw IoError("cannot read the sweep rows '" + f.name + "' (not an HDF5 file, or missing)");
  f.file = Handle(H5Fopen(f.name.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  f.text_type = Handle(make_text_type(), H5Tclose);
  f.status_type = Handle(make_status_type(), H5Tclose);
  if (f.file.get() < 0 || f.text_type.get() < 0 || f.status_type.get() < 0)
    throw IoError("cannot read the sweep rows '" + f.name + "'");
  const auto format = attribute_texts(f.file.get(), "format");
  if (!format || format->size() != 1 || format->front() != kFormat)
    throw f.defect("format",
                   std::string("not the rows of a sweep (the root attribute `format` is not ") +
                       kFormat + ")");
  std::vector<std::string> expected = parameters;
  expected.insert(expected.end(), {"status", "message"});
  for (const auto& column : columns) expected.push_back(column.name);
  if (attribute_texts(f.file.get(), "columns") != expected) {
    std::string list;
    for (const auto& name : expected) list += (list.empty() ? "" : ", ") + name;
    throw f.defect("columns", "the columns are not the ones this sweep writes (" + list + ")");
  }
  for (const auto& name : parameters) f.parameters.push_back(f.open(name));
  f.status = f.open("status");
  f.message = f.open("message");
  for (const auto& column : columns) f.values.push_back(f.open(column.name));
}

SweepHdf5Reader::~SweepHdf5Reader() = default;

std::size_t SweepHdf5Reader::rows_read() const {
  return static_cast<std::size_t>(file_->rows_read);
}

SweepRows SweepHdf5Reader::read(std::size_t first_pose, std::size_t count) {
  File& f = *file_;
  SweepRows rows;
  rows.first_pose = first_pose;
  rows.parameter_count = f.parameters.size();
  rows.column_count = f.values.size();
  const hsize_t n = std::min<hsize_t>(count, f.rows - f.rows_read);
  if (n == 0) return rows;
  const std::size_t size = static_cast<std::size_t>(n);
  std::vector<double> column(size);
  rows.parameters.resize(size * rows.parameter_count);
  for (std::size_t k = 0; k < f.parameters.size(); ++k) {
    f.read(f.parameters[k], H5T_NATIVE_DOUBLE, n, column.data(),
           "parameter " + std::to_string(k + 1));
    for (std::size_t row = 0; row < size; ++row)
      rows.parameters[row * rows.parameter_count + k] = column[row];
  }
  // Read through the enumeration's names: a code of another meaning cannot pass as a status.
  std::vector<std::int8_t> statuses(size);
  f.read(f.status, f.status_type.get(), n, statuses.data(), "status");
  for (std::int8_t code : statuses) rows.statuses.push_back(static_cast<PoseStatus>(code));
  std::vector<char*> messages(size, nullptr);
  f.read(f.message, f.text_type.get(), n, messages.data(), "message");
  for (char* text : messages) rows.messages.emplace_back(text ? text : "");
  Handle memory_space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  H5Dvlen_reclaim(f.text_type.get(), memory_space.get(), H5P_DEFAULT, messages.data());
  for (std::size_t row = 0; row < size; ++row)
    rows.large_deflections.push_back(rows.statuses[row] == PoseStatus::ok &&
                                     rows.messages[row].starts_with(kLargeDeflectionWarning));
  rows.values.resize(size * rows.column_count);
  for (std::size_t c = 0; c < f.values.size(); ++c) {
    f.read(f.values[c], H5T_NATIVE_DOUBLE, n, column.data(), "column " + std::to_string(c + 1));
    for (std::size_t row = 0; row < size; ++row)
      rows.values[row * rows.column_count + c] = column[row];
  }
  f.rows_read += n;
  return rows;
}

std::optional<std::string> SweepHdf5Reader::summary_of(const std::filesystem::path& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  std::error_code error;
  if (std::filesystem::is_directory(path, error) || H5Fis_hdf5(path.string().c_str()) <= 0)
    return std::nullopt;
  Handle file(H5Fopen(path.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (file.get() < 0) return std::nullopt;
  const auto format = attribute_texts(file.get(), "format");
  const auto summary = attribute_texts(file.get(), "summary");
  if (!format || format->size() != 1 || format->front() != kFormat || !summary ||
      summary->size() != 1)
    return std::nullopt;
  return summary->front();
}

}  // namespace stiffmsa

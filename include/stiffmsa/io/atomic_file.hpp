#pragma once
// Output files written whole or not at all, also when they are written in pieces (a sweep's
// rows, block by block).
#include <filesystem>
#include <memory>
#include <string_view>

namespace stiffmsa {

// A file filled through a temporary file in the target's folder and renamed over the target by
// commit(). Destroyed before commit() (an error, an exception), it removes the temporary file
// and leaves any earlier file at the target untouched. Throws IoError.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(const std::filesystem::path& target);
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
  ~AtomicFileWriter();

  void append(std::string_view bytes);
  // For a writer that opens the file by name itself (HDF5): it must close it before commit().
  const std::filesystem::path& temporary_path() const;
  void commit();

 private:
  struct Temporary;
  std::filesystem::path target_;
  std::unique_ptr<Temporary> temporary_;
};

}  // namespace stiffmsa

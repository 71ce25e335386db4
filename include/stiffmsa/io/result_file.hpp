#pragma once
// The result file format "stiffmsa-result/1" (model-format.md).
#include <filesystem>
#include <string>

#include "stiffmsa/result.hpp"

namespace stiffmsa {

// The result as JSON text.
std::string result_to_json(const Result& result);

// Writes the result JSON whole or not at all (temporary file, then rename). Throws IoError.
void write_result_file(const Result& result, const std::filesystem::path& path);

// Writes `contents` to `path` through a temporary file in the same folder and a rename.
void write_file_atomically(const std::filesystem::path& path, const std::string& contents);

}  // namespace stiffmsa

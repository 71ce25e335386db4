#pragma once
// Reading model files (YAML, or JSON as a subset of it) into a Model. Syntax, types, sizes and
// unknown keys are checked here with file positions; the model is then validated.
#include <filesystem>
#include <string>
#include <string_view>

#include "stiffmsa/model.hpp"

namespace stiffmsa {

// Reads and validates a model file. Throws IoError when the file cannot be read and
// InputError listing every defect.
Model load_model(const std::filesystem::path& path);

// The same for text already in memory; `file_name` is used in messages and as default name.
Model parse_model(std::string_view text, const std::string& file_name);

}  // namespace stiffmsa

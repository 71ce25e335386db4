#pragma once
// Reading model files (YAML, or JSON as a subset of it) into a Model. Syntax, types, sizes and
// unknown keys are checked here with file positions; the model is then validated.
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>

#include "stiffmsa/model.hpp"
#include "stiffmsa/parametric.hpp"

namespace stiffmsa {

// Bounds on what a model file may hold, checked before the file is parsed (size, nesting) or
// before it becomes a Model (entity counts), so that a huge or hostile file is refused with a
// message instead of exhausting memory or overflowing the stack. The defaults are far above
// real models; the `stiffmsa` command raises them with --max-file-size, --max-depth and
// --max-entities.
struct LoadLimits {
  // The parser holds about 80 bytes of memory per byte of a model file (up to 250 for a flat
  // list of one-digit numbers), so this bounds the memory a file can take to a few GB. A
  // 100 000-link chain takes 20–25 MB; real robots take kilobytes.
  std::size_t max_file_bytes = std::size_t{64} << 20;  // 64 MiB
  // Levels of mappings and lists, the top-level mapping being 1. The deepest place of a valid
  // model, a row of a link's matrix, is at level 5; the parser recurses once per level.
  int max_nesting_depth = 64;
  // Points, links, joints, supports, loads and end effectors (and named materials and
  // sections), each kind counted on its own. Ten
  // times the 100 000-link chain; a million links already make a system of 24 million
  // unknowns, more than a sparse LU can factorise in memory.
  std::size_t max_entities = 1'000'000;
};

// Reads and validates a model file. Throws IoError when the file cannot be read and
// InputError listing every defect, or naming the limit the file exceeds.
Model load_model(const std::filesystem::path& path);
Model load_model(const std::filesystem::path& path, const LoadLimits& limits);

// The same for text already in memory; `file_name` is used in messages and as default name.
Model parse_model(std::string_view text, const std::string& file_name);
Model parse_model(std::string_view text, const std::string& file_name, const LoadLimits& limits);

// Values that replace a file's parameter defaults (as `stiffmsa … --set x=0.1` gives them).
using ParameterSettings = std::map<std::string, double>;

// A parametric model file (its top-level `parameters:`) as a family of models: checked here
// at the parameters' defaults, where `settings` replace those of the file, and each member
// built from its parameter values. A file without parameters is a family of one model.
// load_model() and parse_model() give the member at the file's defaults. Throws UsageError
// when a setting names no parameter.
ModelFamily load_model_family(const std::filesystem::path& path, const LoadLimits& limits = {},
                              const ParameterSettings& settings = {});
ModelFamily parse_model_family(std::string_view text, const std::string& file_name,
                               const LoadLimits& limits = {},
                               const ParameterSettings& settings = {});

// A model as a plain model file (format stiffmsa/1, no parameters, no robot block), that reads
// back to the same numbers: what `stiffmsa expand` writes. write_model_file() writes it whole
// or not at all; it throws IoError.
std::string model_to_yaml(const Model& model);
void write_model_file(const Model& model, const std::filesystem::path& path);

}  // namespace stiffmsa

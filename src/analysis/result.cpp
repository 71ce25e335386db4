#include "stiffmsa/result.hpp"

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace stiffmsa {

namespace {
template <class Entry>
const Entry& named(const std::vector<Entry>& entries, std::string_view name, const char* kind) {
  for (const Entry& e : entries)
    if (e.name == name) return e;
  std::vector<std::string> names;
  names.reserve(entries.size());
  for (const Entry& e : entries) names.push_back(e.name);
  throw NameError(kind, std::string(name), names);
}

constexpr std::array<std::pair<SolverUsed, const char*>, 7> kSolverUsedNames{{
    {SolverUsed::none, ""},
    {SolverUsed::tree, "tree"},
    {SolverUsed::tree_with_cuts, "tree_with_cuts"},
    {SolverUsed::frame, "frame"},
    {SolverUsed::klu, "klu"},
    {SolverUsed::sparse_lu, "sparse_lu"},
    {SolverUsed::umfpack, "umfpack"},
}};
}  // namespace

const EndEffectorResult& Result::end_effector(std::string_view name) const {
  return named(end_effectors, name, "end effector");
}
const Result& Result::load_case_result(std::string_view name) const {
  for (const Result& r : load_cases)
    if (r.load_case == name) return r;
  std::vector<std::string> names;
  names.reserve(load_cases.size());
  for (const Result& r : load_cases) names.push_back(r.load_case);
  throw NameError("load case", std::string(name), names);
}
const LinkResult& Result::link(std::string_view name) const { return named(links, name, "link"); }
const JointResult& Result::joint(std::string_view name) const {
  return named(joints, name, "joint");
}
const SupportResult& Result::support(std::string_view name) const {
  return named(supports, name, "support");
}

const char* to_string(SolverUsed solver) {
  for (const auto& [value, text] : kSolverUsedNames)
    if (value == solver) return text;
  return "";
}
std::optional<SolverUsed> solver_used_from_string(std::string_view name) {
  for (const auto& [value, text] : kSolverUsedNames)
    if (name == text) return value;
  return std::nullopt;
}

}  // namespace stiffmsa

#pragma once
// "Did you mean ...?": the one rule for suggesting a valid key or name in place of a typo.
#include <algorithm>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "stiffmsa/number_text.hpp"

namespace stiffmsa::detail {

// Levenshtein distance: insertions, deletions and substitutions each cost 1.
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitution});
    }
  }
  return row[b.size()];
}

// The candidate nearest to `word`, if it is near enough to be what was meant. A typo changes
// a few characters: a candidate needing more edits than a third of the word (at least one), or
// as many edits as the word has characters, is a different word, and suggesting it misleads.
inline std::optional<std::string> nearest(std::string_view word,
                                          const std::vector<std::string>& candidates) {
  const std::size_t limit = std::max<std::size_t>(1, word.size() / 3);
  std::optional<std::string> best;
  std::size_t best_distance = limit + 1;
  for (const auto& candidate : candidates) {
    // The length difference bounds the edit distance from below: skip what cannot be near.
    const std::size_t length_gap = candidate.size() > word.size() ? candidate.size() - word.size()
                                                                  : word.size() - candidate.size();
    if (length_gap >= best_distance) continue;
    const std::size_t d = edit_distance(word, candidate);
    if (d < best_distance && d < word.size()) {
      best_distance = d;
      best = candidate;
    }
  }
  return best;
}

// Valid keys or names listed for a message: a long list is cut, since a message names a few.
inline std::string comma_list(const std::vector<std::string>& items) {
  constexpr std::size_t kShown = 12;
  return name_list(items, ", ", kShown);
}

// The tail of a message about `word` not being one of `candidates`: "; did you mean 'x'?"
// when one is near, else the list of what is valid (`what` names them, e.g. "valid keys").
inline std::string suggestion(std::string_view word, const std::vector<std::string>& candidates,
                              std::string_view what) {
  if (auto near = nearest(word, candidates)) return "; did you mean '" + *near + "'?";
  if (candidates.empty()) return "";
  return "; " + std::string(what) + ": " + comma_list(candidates);
}

// A parameter a parametric model does not declare, asked for by a setting, a sweep or a
// member's values: the model's name and its file (each left out where empty), the name, and the
// nearest declared parameter or that it declares none.
inline std::string no_parameter_message(const std::string& model, const std::string& file,
                                        const std::string& name,
                                        const std::vector<std::string>& parameters) {
  return "the model" + (model.empty() ? std::string() : " '" + model + "'") +
         (file.empty() ? std::string() : " (" + file + ")") + " has no parameter '" + name + "'" +
         (parameters.empty() ? std::string("; it declares no `parameters:`")
                             : suggestion(name, parameters, "its parameters are"));
}

}  // namespace stiffmsa::detail

#pragma once
// The one reading of a plain number written as text (a parameter's default, a number of a
// parametric file that may be an expression, a value of a pose file): all of the text is a
// finite decimal number, with an optional leading '+'.
#include <charconv>
#include <cmath>
#include <optional>
#include <string_view>

namespace stiffmsa::detail {

inline std::optional<double> plain_number(std::string_view text) {
  if (text.starts_with('+')) {
    text.remove_prefix(1);
    if (text.starts_with('-')) return std::nullopt;  // from_chars would read the rest as a number
  }
  double value = 0;
  const auto [stop, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || stop != text.data() + text.size() ||
      !std::isfinite(value))
    return std::nullopt;
  return value;
}

}  // namespace stiffmsa::detail

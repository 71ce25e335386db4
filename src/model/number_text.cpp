#include "stiffmsa/number_text.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace stiffmsa {

void append_shortest_text(std::string& out, double value) {
  if (std::isnan(value)) {
    out += "nan";
  } else if (std::isinf(value)) {
    out += value > 0 ? "inf" : "-inf";
  } else {
    char buffer[32];
    // Adding +0.0 turns a negative zero into a plain one.
    const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, value + 0.0);
    if (error == std::errc()) out.append(buffer, end);
  }
}

double shortest_decimal_near(double value, double round_off) {
  char buffer[32];
  for (int digits = 1; digits < std::numeric_limits<double>::max_digits10; ++digits) {
    const auto [end, error] =
        std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, digits);
    double decimal = value;
    if (error != std::errc() || std::from_chars(buffer, end, decimal).ec != std::errc()) break;
    if (std::abs(decimal - value) <= round_off) return decimal;
  }
  return value;
}

std::string name_list(const std::vector<std::string>& names, std::string_view last,
                      std::size_t at_most) {
  const std::size_t shown = std::min(names.size(), at_most);
  std::string text;
  for (std::size_t i = 0; i < shown; ++i) {
    if (i > 0) text += i + 1 == shown && shown == names.size() ? last : std::string_view(", ");
    text += names[i];
  }
  if (names.size() > shown) text += " and " + std::to_string(names.size() - shown) + " more";
  return text;
}

std::string counted(std::size_t count, const std::string& noun) {
  return std::to_string(count) + " " + noun + (count == 1 ? "" : "s");
}

std::string shortest_text(double value) {
  std::string text;
  append_shortest_text(text, value);
  return text;
}

}  // namespace stiffmsa

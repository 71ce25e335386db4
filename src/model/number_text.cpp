#include "stiffmsa/number_text.hpp"

#include <charconv>
#include <cmath>

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

std::string counted(std::size_t count, const std::string& noun) {
  return std::to_string(count) + " " + noun + (count == 1 ? "" : "s");
}

std::string shortest_text(double value) {
  std::string text;
  append_shortest_text(text, value);
  return text;
}

}  // namespace stiffmsa

#pragma once
// What the model viewer and the sweep map share: binary arrays inside JSON, and the page made
// from its template, its data and its scripts.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace stiffmsa::detail {

// Little-endian bytes of 32-bit numbers as base64: a large model's coordinates and deflections
// take a quarter of the room of JSON numbers and are read by the page as typed arrays.
template <typename T>
std::string base64_of(const std::vector<T>& values) {
  static_assert(sizeof(T) == 4);
  static constexpr char alphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes(values.size() * 4, '\0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint32_t word = 0;
    std::memcpy(&word, &values[i], 4);
    for (int b = 0; b < 4; ++b)
      bytes[4 * i + static_cast<std::size_t>(b)] = static_cast<char>((word >> (8 * b)) & 0xff);
  }
  std::string text;
  text.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const auto byte = [&](std::size_t k) {
      return k < bytes.size() ? static_cast<unsigned char>(bytes[k]) : 0u;
    };
    const unsigned triple = (byte(i) << 16) | (byte(i + 1) << 8) | byte(i + 2);
    text += alphabet[(triple >> 18) & 63];
    text += alphabet[(triple >> 12) & 63];
    text += i + 1 < bytes.size() ? alphabet[(triple >> 6) & 63] : '=';
    text += i + 2 < bytes.size() ? alphabet[triple & 63] : '=';
  }
  return text;
}

// The page: `page_template` with its marker <!--stiffmsa:data--> replaced by the JSON (made
// safe for a script block) and <!--stiffmsa:scripts--> by three.js, its orbit controls and
// `page_js`, the style sheet at <!--stiffmsa:style-->.
std::string page_from_template(std::string_view page_template, const std::string& json,
                               std::string_view page_js);

}  // namespace stiffmsa::detail

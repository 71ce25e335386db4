#pragma once
// Numbers as stiffmsa writes them for people and for files (result file, sweep rows and summary,
// plot labels, messages): one formatter, so that a value reads the same everywhere; and the one
// way a message lists names.
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace stiffmsa {

// The shortest decimal text that reads back (std::from_chars, strtod) as the same double:
// 0.11, 70000, 2.1e+11. A negative zero is written "0" (rounding's sign of nothing, not a
// value), infinities "inf" and "-inf", NaN "nan".
std::string shortest_text(double value);
// Names listed in a message: "a, b, c", or "a, b and c" where `last` is " and ". A list longer
// than `at_most` shows that many and counts the rest: "a, b, c and 8 more".
std::string name_list(const std::vector<std::string>& names, std::string_view last = ", ",
                      std::size_t at_most = std::numeric_limits<std::size_t>::max());

// "1 number", "3 numbers": a count with its noun, plural by an "s".
std::string counted(std::size_t count, const std::string& noun);

// The same appended to `out`, without a string of its own (files of millions of numbers).
void append_shortest_text(std::string& out, double value);

// The double of the shortest decimal within `round_off` of `value`, where there is one (0.11
// for 0.11000000000000001), else `value`: the value a user meant by a decimal grid, so that
// shortest_text writes it as the user would (GridAxis::value).
double shortest_decimal_near(double value, double round_off);

}  // namespace stiffmsa

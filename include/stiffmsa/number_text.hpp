#pragma once
// Numbers as stiffmsa writes them for people and for files (result file, sweep rows and summary,
// plot labels, messages): one formatter, so that a value reads the same everywhere.
#include <cstddef>
#include <string>

namespace stiffmsa {

// The shortest decimal text that reads back (std::from_chars, strtod) as the same double:
// 0.11, 70000, 2.1e+11. A negative zero is written "0" (rounding's sign of nothing, not a
// value), infinities "inf" and "-inf", NaN "nan".
std::string shortest_text(double value);
// "1 number", "3 numbers": a count with its noun, plural by an "s".
std::string counted(std::size_t count, const std::string& noun);

// The same appended to `out`, without a string of its own (files of millions of numbers).
void append_shortest_text(std::string& out, double value);

}  // namespace stiffmsa

#pragma once
// What the tests that run the `stiffmsa` command share: a file's text, a shell-quoted argument,
// and a run with its output in a file.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace stiffmsa::testing {

// The whole file, as bytes ("" where it cannot be read).
inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// `text` as one argument of /bin/sh, in single quotes.
inline std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Runs `command arguments` with its standard output and error into `output`; its exit code, or
// −1 where it did not exit.
inline int run_into(const std::string& command, const std::string& arguments,
                    const std::string& output) {
  const int status = std::system((command + " " + arguments + " >" + output + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace stiffmsa::testing

#pragma once
// The command module (target stiffmsa_command): every subcommand of stiffmsa, with the libraries
// they use, built as a shared module that the launcher (app/launcher.cpp) loads with dlopen, so
// that `stiffmsa --version` maps none of them (docs/library.md, "The command's modules").
// Plain C types only: the launcher is built without the C++ library.

namespace stiffmsa::cli {

inline constexpr const char* kCommandModuleFile = "stiffmsa_command.so";
inline constexpr const char* kCommandModuleEntry = "stiffmsa_command_main";

// The entry: the command line as main() received it, and the version the launcher was built
// with, which the module compares with its own (a stale install); returns the exit code.
using CommandEntry = int (*)(int argc, char** argv, const char* launcher_version);

}  // namespace stiffmsa::cli

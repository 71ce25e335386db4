// The stiffmsa executable: answers `stiffmsa --version` itself and hands every other command line
// to the command module (app/command_module.hpp), loaded from beside the executable (a build
// folder) or from its install's library folder. Starting a process that maps the sparse
// solvers, OpenBLAS, oneTBB and libfyaml costs milliseconds in relocations alone; the
// version needs none of them. Written against the C library only (no C++ library, no
// exceptions), so that this program's own start is the C library's.
#include <dlfcn.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "command_module.hpp"
#include "stiffmsa/config.hpp"

#ifndef STIFFMSA_CLI_MODULE_DIR
#define STIFFMSA_CLI_MODULE_DIR "../lib/stiffmsa"
#endif

namespace {

constexpr int kExitInvalidInput = 2;  // as app/summary.hpp's exit_invalid_input

// `folder/name` into `out`; false when it does not fit.
bool join(char (&out)[PATH_MAX], const char* folder, const char* name) {
  const int written = snprintf(out, sizeof out, "%s/%s", folder, name);
  return written > 0 && static_cast<size_t>(written) < sizeof out;
}

// The command module, beside this executable or in the install's library folder; null with a
// message on stderr when neither loads.
void* load_command_module() {
  char executable[PATH_MAX];
  const ssize_t length = readlink("/proc/self/exe", executable, sizeof executable - 1);
  if (length <= 0) {
    fprintf(stderr, "stiffmsa: error: cannot find this executable's folder (/proc/self/exe)\n");
    return nullptr;
  }
  executable[length] = '\0';
  char* const slash = strrchr(executable, '/');
  if (slash) *slash = '\0';
  const char* const folder = slash ? executable : ".";

  char beside[PATH_MAX];
  char installed[PATH_MAX];
  char installed_folder[PATH_MAX];
  if (!join(beside, folder, stiffmsa::cli::kCommandModuleFile) ||
      !join(installed_folder, folder, STIFFMSA_CLI_MODULE_DIR) ||
      !join(installed, installed_folder, stiffmsa::cli::kCommandModuleFile)) {
    fprintf(stderr, "stiffmsa: error: the path of this executable is too long\n");
    return nullptr;
  }
  const char* const candidates[] = {beside, installed};
  for (const char* candidate : candidates) {
    if (access(candidate, F_OK) != 0) continue;
#ifdef STIFFMSA_CLI_BLAS
    // The BLAS first, on its own (CMakeLists.txt): its symbols are then found among a handful of
    // libraries rather than behind the module's thirty. Only an order: where it fails, the
    // module loads it as before.
    dlopen(STIFFMSA_CLI_BLAS, RTLD_LAZY | RTLD_GLOBAL);
#endif
#ifdef STIFFMSA_CLI_CXX_RUNTIME
    // The C++ library next, for the same reason: its own 1 800 symbol lookups, and those of every
    // library after it that calls it, then stop at the start of the search list.
    dlopen(STIFFMSA_CLI_CXX_RUNTIME, RTLD_LAZY | RTLD_GLOBAL);
#endif
    // Lazy, as the dynamic loader binds an executable's libraries: RTLD_NOW would bind every
    // function the libraries it brings could call (10 000 more symbol lookups for a solve).
    // Global: the plot, HDF5 and MPI modules the command module loads in turn take their
    // library functions from it.
    if (void* module = dlopen(candidate, RTLD_LAZY | RTLD_GLOBAL)) return module;
    fprintf(stderr, "stiffmsa: error: cannot load the command module (%s): %s\n", candidate,
            dlerror());
    return nullptr;
  }
  fprintf(stderr,
          "stiffmsa: error: the command module is not installed with this executable (looked for "
          "%s and %s)\n",
          beside, installed);
  return nullptr;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && strcmp(argv[1], "--version") == 0) {
    if (puts("stiffmsa " STIFFMSA_VERSION) < 0 || fflush(stdout) != 0) {
      fprintf(stderr, "stiffmsa: error: cannot write to standard output\n");
      return kExitInvalidInput;
    }
    return 0;
  }
  void* const module = load_command_module();
  if (!module) return kExitInvalidInput;
  const auto entry = reinterpret_cast<stiffmsa::cli::CommandEntry>(
      dlsym(module, stiffmsa::cli::kCommandModuleEntry));
  if (!entry) {
    fprintf(stderr, "stiffmsa: error: the command module has no entry %s\n",
            stiffmsa::cli::kCommandModuleEntry);
    return kExitInvalidInput;
  }
  return entry(argc, argv, STIFFMSA_VERSION);
}

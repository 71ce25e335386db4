#include "module_loader.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <map>
#include <mutex>
#include <system_error>

#include "stiffmsa/errors.hpp"

#ifndef STIFFMSA_CLI_MODULE_DIR
#define STIFFMSA_CLI_MODULE_DIR "../lib/stiffmsa"
#endif

namespace stiffmsa::cli {

namespace fs = std::filesystem;

void* module_entry(const std::string& file_name, const char* entry, const std::string& what) {
  static std::mutex mutex;
  static std::map<std::string, void*> loaded;
  const std::lock_guard lock(mutex);
  if (const auto found = loaded.find(file_name); found != loaded.end()) return found->second;

  std::error_code error;
  const fs::path command = fs::read_symlink("/proc/self/exe", error);
  const fs::path folder = error ? fs::path() : command.parent_path();
  std::string tried;
  for (const fs::path& candidate :
       {folder / file_name, folder / STIFFMSA_CLI_MODULE_DIR / file_name}) {
    if (!fs::exists(candidate, error)) {
      tried += (tried.empty() ? "" : ", ") + candidate.lexically_normal().string();
      continue;
    }
    void* module = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!module)
      throw IoError("cannot load " + what + " (" + candidate.string() + "): " + dlerror());
    void* function = dlsym(module, entry);
    if (!function)
      throw IoError("cannot load " + what + " (" + candidate.string() + "): no entry " + entry);
    return loaded[file_name] = function;
  }
  throw IoError(what + " is not installed with this stiffmsa command (looked for " + tried + ")");
}

}  // namespace stiffmsa::cli

#include "core/firmware/firmware_library.hpp"

#include <dlfcn.h>

#include <cstring>

namespace packsim {

std::string checkFirmwareDescriptor(const psfw_firmware& fw) {
  if (fw.abi_version < PSFW_ABI_VERSION_MIN || fw.abi_version > PSFW_ABI_VERSION)
    return "ABI mismatch: the firmware was built against contract version " + std::to_string(fw.abi_version) +
           ", this packsim runs versions " + std::to_string(PSFW_ABI_VERSION_MIN) + " to " +
           std::to_string(PSFW_ABI_VERSION);
  if (fw.task_count > PSFW_MAX_TASKS)
    return "task_count " + std::to_string(fw.task_count) + " exceeds PSFW_MAX_TASKS (" + std::to_string(PSFW_MAX_TASKS) + ")";
  for (uint32_t i = 0; i < fw.task_count; ++i) {
    if (fw.tasks[i].run == nullptr) return "task " + std::to_string(i) + " has no run function";
    if (fw.tasks[i].period_ms == 0) return "task " + std::to_string(i) + " has a period of 0 ms";
  }
  if (fw.instance_bytes > (64u << 20)) return "instance_bytes above 64 MiB: " + std::to_string(fw.instance_bytes);
  return "";
}

FirmwareLibrary::FirmwareLibrary(const std::string& path) {
  handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle_) {
    const char* e = dlerror();
    error_ = "cannot load " + path + ": " + (e ? e : "unknown dlopen error");
    return;
  }
  dlerror();
  void* sym = dlsym(handle_, PSFW_ENTRY_SYMBOL);
  if (!sym) {
    error_ = path + " does not export " PSFW_ENTRY_SYMBOL;
    return;
  }
  std::memcpy(&entry_, &sym, sizeof entry_);  // object pointer -> function pointer (POSIX)
}

FirmwareLibrary::~FirmwareLibrary() {
  if (handle_) dlclose(handle_);
}

}  // namespace packsim

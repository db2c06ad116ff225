#include "core/firmware/emulator_libraries.hpp"

#include <dlfcn.h>

#include <stdexcept>
#include <string>

// The sonames of the versions packsim was built against (core/CMakeLists.txt, from
// pkg-config's version of each library).
#ifndef PACKSIM_UNICORN_SONAME
#error "PACKSIM_UNICORN_SONAME is set by core/CMakeLists.txt"
#endif
#ifndef PACKSIM_CAPSTONE_SONAME
#error "PACKSIM_CAPSTONE_SONAME is set by core/CMakeLists.txt"
#endif

namespace packsim {

namespace {

const char* const kInstallHint = "install it with `bash scripts/install-deps.sh --run`";

// The function `name` of the library, with the type of the field it fills.
template <typename F>
void resolve(void* lib, const char* soname, const char* name, F& out) {
  void* f = dlsym(lib, name);
  if (!f)
    throw std::runtime_error(std::string(soname) + " has no function " + name + " (a version packsim was not built for; " +
                             kInstallHint + ")");
  out = reinterpret_cast<F>(f);
}

UnicornApi loadUnicorn() {
  const char* so = PACKSIM_UNICORN_SONAME;
  void* lib = openEmulatorLibrary(so, "the Unicorn engine (the ARM emulator)", "libunicorn2");
  UnicornApi a{};
  resolve(lib, so, "uc_open", a.open);
  resolve(lib, so, "uc_close", a.close);
  resolve(lib, so, "uc_strerror", a.strerror);
  resolve(lib, so, "uc_ctl", a.ctl);
  resolve(lib, so, "uc_mem_map", a.mem_map);
  resolve(lib, so, "uc_mmio_map", a.mmio_map);
  resolve(lib, so, "uc_mem_read", a.mem_read);
  resolve(lib, so, "uc_mem_write", a.mem_write);
  resolve(lib, so, "uc_reg_read", a.reg_read);
  resolve(lib, so, "uc_reg_write", a.reg_write);
  resolve(lib, so, "uc_hook_add", a.hook_add);
  resolve(lib, so, "uc_hook_del", a.hook_del);
  resolve(lib, so, "uc_emu_start", a.emu_start);
  resolve(lib, so, "uc_emu_stop", a.emu_stop);
  return a;
}

CapstoneApi loadCapstone() {
  const char* so = PACKSIM_CAPSTONE_SONAME;
  void* lib = openEmulatorLibrary(so, "Capstone (the disassembler of the cycle model)", "libcapstone4");
  CapstoneApi a{};
  resolve(lib, so, "cs_open", a.open);
  resolve(lib, so, "cs_close", a.close);
  resolve(lib, so, "cs_option", a.option);
  resolve(lib, so, "cs_disasm", a.disasm);
  resolve(lib, so, "cs_free", a.free);
  return a;
}

}  // namespace

void* openEmulatorLibrary(const char* soname, const char* role, const char* debianPackage) {
  // Never closed: the process keeps it, as it kept a library the linker loaded.
  void* lib = dlopen(soname, RTLD_NOW | RTLD_LOCAL);
  if (!lib) {
    const char* e = dlerror();
    throw std::runtime_error(std::string("target mode (bms.firmware.target: cortex-m4) needs ") + role + ", " + soname +
                             ", which could not be loaded (" + (e ? e : "unknown dlopen error") + "); " + kInstallHint +
                             " (Debian package " + debianPackage + ")");
  }
  return lib;
}

const UnicornApi& unicorn() {
  static const UnicornApi api = loadUnicorn();  // a failed load throws and is tried again next time
  return api;
}

const CapstoneApi& capstone() {
  static const CapstoneApi api = loadCapstone();
  return api;
}

}  // namespace packsim

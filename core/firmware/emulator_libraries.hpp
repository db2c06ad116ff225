#pragma once
// Target mode's two libraries, Unicorn (the ARM emulator) and Capstone (the disassembler
// of the cycle model), loaded when a target-mode run first needs them (dlopen) instead of
// by the dynamic linker at every start: their relocations cost ~12 ms of CPU in each
// process that starts packsim (the executable, a batch case, the Python module), whether
// or not it runs a firmware on the target (docs/firmware.md, "Target mode").
// Only the functions packsim calls, typed from the libraries' own headers.
#include <capstone/capstone.h>
#include <unicorn/unicorn.h>

namespace packsim {

struct UnicornApi {
  decltype(&::uc_open) open;
  decltype(&::uc_close) close;
  decltype(&::uc_strerror) strerror;
  decltype(&::uc_ctl) ctl;
  decltype(&::uc_mem_map) mem_map;
  decltype(&::uc_mmio_map) mmio_map;
  decltype(&::uc_mem_read) mem_read;
  decltype(&::uc_mem_write) mem_write;
  decltype(&::uc_reg_read) reg_read;
  decltype(&::uc_reg_write) reg_write;
  decltype(&::uc_hook_add) hook_add;
  decltype(&::uc_hook_del) hook_del;
  decltype(&::uc_emu_start) emu_start;
  decltype(&::uc_emu_stop) emu_stop;
};

struct CapstoneApi {
  decltype(&::cs_open) open;
  decltype(&::cs_close) close;
  decltype(&::cs_option) option;
  decltype(&::cs_disasm) disasm;
  decltype(&::cs_free) free;
};

// The loaded library's functions (loaded once per process); throws std::runtime_error
// naming the library, the loader's reason and the Debian package that provides it.
const UnicornApi& unicorn();
const CapstoneApi& capstone();

// dlopen(soname) or that error (what unicorn() and capstone() use; a test gives it a
// library that does not exist).
void* openEmulatorLibrary(const char* soname, const char* role, const char* debianPackage);

}  // namespace packsim

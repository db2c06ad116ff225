// A firmware shared library loaded at run time: dlopen and the one entry symbol
// (psfw_firmware_entry); the host calls the entry under its fault guard and checks the
// descriptor it returns (checkFirmwareDescriptor). Problems are reported as text (the
// run records them as a firmware_fault), never thrown.
#pragma once
#include <bms/packsim_fw.h>

#include <string>

namespace packsim {

class FirmwareLibrary {
 public:
  explicit FirmwareLibrary(const std::string& path);
  ~FirmwareLibrary();
  FirmwareLibrary(const FirmwareLibrary&) = delete;
  FirmwareLibrary& operator=(const FirmwareLibrary&) = delete;

  // entry() is null when loading failed; error() says why.
  psfw_entry_fn entry() const { return entry_; }
  const std::string& error() const { return error_; }

 private:
  void* handle_ = nullptr;
  psfw_entry_fn entry_ = nullptr;
  std::string error_;
};

// The checks of a descriptor against this host (ABI, task table); "" if it is usable.
std::string checkFirmwareDescriptor(const psfw_firmware& fw);

}  // namespace packsim

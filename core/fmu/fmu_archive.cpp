#include "core/fmu/fmu_archive.hpp"

#include <zip.h>

#include <filesystem>
#include <memory>
#include <random>
#include <stdexcept>
#include <system_error>

namespace packsim {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(zip_t* z, const std::string& tmp, const std::string& out, const std::string& why) {
  if (z) zip_discard(z);
  std::error_code ec;
  fs::remove(tmp, ec);
  throw std::runtime_error("cannot write " + out + ": " + why);
}

}  // namespace

void writeFmuArchive(const FmuArchive& a, const std::string& outPath) {
  std::random_device rd;
  const std::string tmp = outPath + ".tmp" + std::to_string(rd() % 1000000);
  int err = 0;
  zip_t* z = zip_open(tmp.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  if (!z) {
    zip_error_t ze;
    zip_error_init_with_code(&ze, err);
    const std::string why = zip_error_strerror(&ze);
    zip_error_fini(&ze);
    fail(nullptr, tmp, outPath, why);
  }
  for (const auto& [name, bytes] : a.contents) {
    zip_source_t* src = zip_source_buffer(z, bytes.data(), bytes.size(), 0);  // `a` outlives zip_close
    if (!src || zip_file_add(z, name.c_str(), src, ZIP_FL_OVERWRITE | ZIP_FL_ENC_UTF_8) < 0) {
      if (src) zip_source_free(src);
      fail(z, tmp, outPath, name + ": " + zip_strerror(z));
    }
  }
  for (const auto& [name, path] : a.files) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) fail(z, tmp, outPath, "missing " + path);
    zip_source_t* src = zip_source_file(z, path.c_str(), 0, -1);
    if (!src || zip_file_add(z, name.c_str(), src, ZIP_FL_OVERWRITE | ZIP_FL_ENC_UTF_8) < 0) {
      if (src) zip_source_free(src);
      fail(z, tmp, outPath, name + ": " + zip_strerror(z));
    }
  }
  if (zip_close(z) < 0) fail(z, tmp, outPath, zip_strerror(z));
  std::error_code ec;
  fs::rename(tmp, outPath, ec);
  if (ec) fail(nullptr, tmp, outPath, ec.message());
}

}  // namespace packsim

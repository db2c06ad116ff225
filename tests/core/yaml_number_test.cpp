// plainDecimal (core/scenario/yaml_map.hpp) reads a scenario's plain decimal numbers with
// std::from_chars instead of yaml-cpp's stream: the same bits as yaml-cpp's as<double>
// for every number it takes (random doubles in every format and precision, subnormals,
// the ends of the range, long mantissas), and it leaves every other text to yaml-cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "core/scenario/yaml_map.hpp"

namespace packsim {
namespace {

// Whether plainDecimal takes s, and then with yaml-cpp's bits.
bool takenAsYamlCpp(const std::string& s, bool& taken) {
  double v = 0.0;
  taken = plainDecimal(s, v);
  if (!taken) return true;
  double y = 0.0;
  if (!YAML::convert<double>::decode(YAML::Node(s), y)) return false;
  return std::memcmp(&v, &y, sizeof v) == 0;
}

TEST(PlainDecimal, IsYamlCppsValueForEveryNumberItTakes) {
  std::mt19937_64 rng(3);
  char buf[64];
  long taken = 0;
  const auto check = [&](const std::string& s) {
    bool t = false;
    EXPECT_TRUE(takenAsYamlCpp(s, t)) << s;
    taken += t;
  };
  for (int k = 0; k < 20000; ++k) {
    const uint64_t bits = rng();
    double d;
    std::memcpy(&d, &bits, sizeof d);
    if (!std::isfinite(d)) continue;
    const int precision = static_cast<int>(rng() % 20);
    const char* formats[] = {"%.*g", "%.*e", "%.*f"};
    const int f = std::fabs(d) > 1e30 ? static_cast<int>(rng() % 2) : static_cast<int>(rng() % 3);
    std::snprintf(buf, sizeof buf, formats[f], precision, d);
    check(buf);
    const double e = std::ldexp(static_cast<double>(rng() % 100000) / 1000.0, static_cast<int>(rng() % 80) - 40);
    std::snprintf(buf, sizeof buf, "%.*g", static_cast<int>(rng() % 18 + 1), e);
    check(buf);
    std::snprintf(buf, sizeof buf, "%ld.%0*ld", static_cast<long>(rng() % 5000) - 2500, static_cast<int>(rng() % 6 + 1),
                  static_cast<long>(rng() % 100000));
    check(buf);
  }
  for (const char* s : {"0", "-0", "0.0", "1e-320", "4.9e-324", "2.4703282292062327e-324", "2.4703282292062328e-324",
                        "1e308", "1.7976931348623157e308", "1.7976931348623158e308", "123456789012345678901234567890",
                        "0.1", "00012", "1E5", "1e+5", "-1.5E-7", "9007199254740993", "2.2250738585072011e-308",
                        "2.2250738585072012e-308", "1e-400", "-1e-400", "3.000000000000000444089209850062616169452667236328125"})
    check(s);
  EXPECT_GT(taken, 50000);
}

TEST(PlainDecimal, LeavesEveryOtherTextToYamlCpp) {
  for (const char* s : {"", "-", "+5", ".5", "5.", "1e", "1e+", "1.5e", "0x10", "1_000", " 1", "1 ", ".inf", "-.inf",
                        ".nan", "1e400", "-1e400", "1,5", "1.2.3", "--1", "1e5.0", "inf", "nan", "1d5"}) {
    double v = 0.0;
    EXPECT_FALSE(plainDecimal(s, v)) << s;
  }
}

}  // namespace
}  // namespace packsim

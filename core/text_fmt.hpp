// printf-style text of up to three numbers: the one formatter the summary, `check`,
// balance-time and load-time lines share (each of their files had its own copy).
#pragma once
#include <cstdio>
#include <string>

namespace packsim {

inline std::string fmt(const char* format, double a, double b = 0.0, double c = 0.0) {
  char buf[240];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

}  // namespace packsim

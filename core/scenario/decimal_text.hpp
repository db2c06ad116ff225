// Whether a text is a plain decimal number, -?D+(.D*)?([eE][-+]?D+)? (D: a digit); with
// `fractionDigits`, a '.' must be followed by at least one digit. The two fast paths
// around yaml-cpp (reading a number, writing a list of numbers back) take only texts of
// this shape and leave everything else to yaml-cpp.
#pragma once
#include <string>

namespace packsim {

inline bool decimalText(const std::string& s, bool fractionDigits) {
  size_t i = !s.empty() && s[0] == '-' ? 1 : 0;
  const auto digits = [&] {
    const size_t from = i;
    while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
    return i - from;
  };
  if (digits() == 0) return false;
  if (i < s.size() && s[i] == '.') {
    ++i;
    if (digits() == 0 && fractionDigits) return false;
  }
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '-' || s[i] == '+')) ++i;
    if (digits() == 0) return false;
  }
  return i == s.size();
}

}  // namespace packsim

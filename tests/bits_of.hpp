// A double's bits, for the tests that hold a fast path or a cache to the plain
// computation bit for bit (the tests' one copy of it).
#pragma once
#include <cstdint>
#include <cstring>

namespace packsim::test {

inline uint64_t bitsOf(double v) {
  uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

}  // namespace packsim::test

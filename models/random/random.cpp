#include "models/random/random.hpp"

#include <cmath>

namespace packsim {

// flatten: the two draws of the engine inline (a call each otherwise, some 10 of the
// 40 instructions a draw costs); the same draws in the same order.
#if defined(__GNUC__)
__attribute__((flatten))
#endif
double standardNormalPair(Rng& rng) {
  constexpr double kTwoPi = 6.283185307179586;
  const double u1 = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
  const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  const double r = std::sqrt(-2.0 * std::log(u1));
  const double a = kTwoPi * u2;
  rng.spare_ = r * std::sin(a);
  rng.hasSpare_ = true;
  return r * std::cos(a);
}

uint64_t deriveSeed(uint64_t seed, uint64_t stream) {
  uint64_t z = seed + 0x9E3779B97F4A7C15ull * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace packsim

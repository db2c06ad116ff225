#include "models/random/random.hpp"

#include <cmath>

#include "models/random/approx_sincos.hpp"

namespace packsim {

namespace {

// The pair's radius and angle from the engine's next two words (53-bit uniforms u1 in
// (0, 1), u2 in [0, 1)).
struct Polar {
  double r, a;
};
inline Polar polarOf(Rng& rng) {
  constexpr double kTwoPi = 6.283185307179586;
  const double u1 = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
  const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return Polar{std::sqrt(-2.0 * std::log(u1)), kTwoPi * u2};
}

// The pair's two normals, the libm's sin and cos (one sincos call): the one formula of
// every normal's value.
inline void normalsOf(const Polar& p, double& first, double& second) {
  second = p.r * std::sin(p.a);
  first = p.r * std::cos(p.a);
}

// r·x's bracket for x within kApproxSinCosBound of approx (r > 0: u1 < 1). Rounding is
// monotonic: x - bound <= x <= x + bound, so each product rounds to its side of r·x.
NormalBracket bracket(double r, double approx) {
  return NormalBracket{r * (approx - kApproxSinCosBound), r * (approx + kApproxSinCosBound)};
}

}  // namespace

double lazyPairNormal(const Rng& rng, bool second) {
  double first, sec;
  normalsOf(Polar{rng.pairR_, rng.pairA_}, first, sec);
  return second ? sec : first;
}

// flatten: the two draws of the engine inline (a call each otherwise, some 10 of the
// 40 instructions a draw costs); the same draws in the same order.
#if defined(__GNUC__)
__attribute__((flatten))
#endif
double standardNormalPair(Rng& rng) {
  double first;
  normalsOf(polarOf(rng), first, rng.spare_);
  rng.hasSpare_ = true;
  return first;
}

#if defined(__GNUC__)
__attribute__((flatten))
#endif
NormalBracket lazyNormalPair(Rng& rng) {
  const Polar p = polarOf(rng);
  double s, c;
  approxSinCos(p.a, s, c);
  rng.pairR_ = p.r, rng.pairA_ = p.a;
  rng.pending_ = bracket(p.r, s);
  rng.hasPending_ = true;
  return bracket(p.r, c);
}

uint64_t deriveSeed(uint64_t seed, uint64_t stream) {
  uint64_t z = seed + 0x9E3779B97F4A7C15ull * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace packsim

// The noise draws that skip the libm's sincos against the plain ones, bit for bit:
// approxSinCos within its bound of std::sin / std::cos over the whole angle range,
// standardNormalLazy's brackets holding standardNormal's values (and lazyNormalValue
// giving them) whichever consumer takes which normal, and AdcChannel's codes against the plain
// conversion written out here, where the bracket decides and where it needs the value.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

#include "models/random/approx_sincos.hpp"
#include "models/random/random.hpp"
#include "models/sensors/adc.hpp"
#include "models/sensors/round_even.hpp"
#include "tests/bits_of.hpp"

namespace packsim {
namespace {

using test::bitsOf;

void expectWithinBound(double u2) {
  const double a = 6.283185307179586 * u2;  // as the draws form it
  double s, c;
  approxSinCos(a, s, c);
  // A thousandth of the bound: the margin the bound keeps.
  ASSERT_LE(std::fabs(s - std::sin(a)), kApproxSinCosBound * 1e-3) << std::hexfloat << a;
  ASSERT_LE(std::fabs(c - std::cos(a)), kApproxSinCosBound * 1e-3) << std::hexfloat << a;
}

TEST(ApproxSinCos, WithinItsBoundOfTheLibmOverTheWholeRange) {
  for (int i = 0; i < (1 << 20); ++i) expectWithinBound(static_cast<double>(i) / (1 << 20));
  // Around every quadrant's edge and the rounding points between quadrants, to the last bit.
  for (double edge : {0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0}) {
    double u = edge;
    for (int k = 0; k < 2000; ++k) {
      if (u >= 0.0 && u < 1.0) expectWithinBound(u);
      u = std::nextafter(u, 2.0);
    }
    u = edge;
    for (int k = 0; k < 2000; ++k) {
      u = std::nextafter(u, -1.0);
      if (u >= 0.0 && u < 1.0) expectWithinBound(u);
    }
  }
  std::mt19937_64 gen(11);
  for (int i = 0; i < 1000000; ++i) expectWithinBound(static_cast<double>(gen() >> 11) * 0x1.0p-53);
}

// Normals taken lazily or exactly in a random mix (as a stream shared by an ADC and a
// plain consumer is): the same values in the same order as standardNormal alone, and the
// engines stay in step.
TEST(StandardNormalLazy, SameSequenceAsStandardNormalInAnyMix) {
  for (uint64_t seed : {uint64_t{1}, uint64_t{0x536A}, uint64_t{20261127}}) {
    Rng rng(seed), ref(seed);
    std::mt19937 pick(static_cast<uint32_t>(seed));
    for (int k = 0; k < 300000; ++k) {
      const double want = standardNormal(ref);
      if (pick() & 1u) {
        ASSERT_EQ(bitsOf(standardNormal(rng)), bitsOf(want)) << "seed " << seed << " draw " << k;
      } else {
        const NormalBracket n = standardNormalLazy(rng);
        ASSERT_LE(n.lo, want) << "seed " << seed << " draw " << k;
        ASSERT_GE(n.hi, want) << "seed " << seed << " draw " << k;
        ASSERT_EQ(bitsOf(lazyNormalValue(rng, n)), bitsOf(want)) << "seed " << seed << " draw " << k;
      }
      if (k % 1001 == 0) ASSERT_EQ(rng(), ref()) << "a raw draw between normals";
    }
  }
}

// The conversion as adc.hpp documents it, its normal from standardNormal.
int64_t plainCode(const AdcChannel& adc, double x, Rng& rng) {
  double v = x * (1.0 + adc.gain_error) + adc.offset;
  if (adc.noise_rms > 0.0) v += adc.noise_rms * standardNormal(rng);
  const double code = std::nearbyint(v / adc.lsb);
  if (!(code > static_cast<double>(adc.code_min))) return adc.code_min;
  if (code > static_cast<double>(adc.code_max)) return adc.code_max;
  return static_cast<int64_t>(code);
}

// A usual channel (the bracket decides nearly every code), one whose codes are finer
// than the bracket (every code needs the normal's value), a rail-bound one and a
// negative lsb; the draws of the two shared with a plain consumer in between.
TEST(AdcChannel, NoisyCodesSameAsThePlainConversion) {
  AdcChannel usual{381.47e-6, 0.001, -0.0005, 1e-3, 0, 16383};
  AdcChannel fine{1e-15, 0.0, 0.0, 1.0, INT64_MIN / 2, INT64_MAX / 2};
  AdcChannel rails{0.01, 0.0, 0.0, 0.5, 0, 10};
  AdcChannel negative{-1e-3, 0.0, 0.0, 2e-3, -4000, 4000};
  std::mt19937_64 gen(5);
  for (const AdcChannel* adc : {&usual, &fine, &rails, &negative}) {
    Rng rng(77), ref(77);
    for (int k = 0; k < 200000; ++k) {
      const double x = static_cast<double>(gen() >> 11) * 0x1.0p-53 * 5.0 - 0.5;
      ASSERT_EQ(adc->convert(x, rng), plainCode(*adc, x, ref)) << "lsb " << adc->lsb << " draw " << k << " x " << x;
      if (k % 7 == 0) ASSERT_EQ(bitsOf(standardNormal(rng)), bitsOf(standardNormal(ref)));
    }
  }
}

// The fine channel above takes the exact path: its brackets span many codes.
TEST(AdcChannel, FineChannelBracketsSpanCodes) {
  const AdcChannel fine{1e-15, 0.0, 0.0, 1.0, INT64_MIN / 2, INT64_MAX / 2};
  Rng rng(3);
  int spanning = 0;
  for (int k = 0; k < 100; ++k) {
    const NormalBracket n = standardNormalLazy(rng);
    if (fine.codeOf(fine.noise_rms * n.lo) != fine.codeOf(fine.noise_rms * n.hi)) ++spanning;
  }
  EXPECT_EQ(spanning, 100);
}

}  // namespace
}  // namespace packsim

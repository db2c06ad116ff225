// The quantisation/noise model: many readings of a fixed input have the configured
// mean error and spread.
#include <gtest/gtest.h>

#include <cmath>

#include "models/sensors/adc.hpp"
#include "models/sensors/thermistor.hpp"

namespace packsim {
namespace {

TEST(Adc, MeanAndSpreadMatchGainOffsetNoise) {
  AdcChannel a;
  a.lsb = 6.25 / 16383.0;
  a.gain_error = 0.01;
  a.offset = 0.002;
  a.noise_rms = 0.003;
  a.code_max = 16383;
  Rng rng(7);
  const double v = 3.6;
  const int n = 200000;
  double sum = 0, sum2 = 0;
  for (int k = 0; k < n; ++k) {
    const double r = static_cast<double>(a.convert(v, rng)) * a.lsb;
    sum += r;
    sum2 += r * r;
  }
  const double mean = sum / n;
  const double sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, v * 1.01 + 0.002, 3e-5);  // 4 sigma of the mean estimate plus rounding
  // Spread = noise with uniform quantisation noise (lsb²/12) added in quadrature.
  EXPECT_NEAR(sd, std::sqrt(0.003 * 0.003 + a.lsb * a.lsb / 12.0), 5e-5);
}

TEST(Adc, WithoutNoiseRoundsToNearestCodeAndSaturates) {
  AdcChannel a;
  a.lsb = 0.001;
  a.code_max = 4095;
  Rng rng(1);
  EXPECT_EQ(a.convert(1.2344, rng), 1234);
  EXPECT_EQ(a.convert(1.2346, rng), 1235);
  EXPECT_EQ(a.convert(9.0, rng), 4095);
  EXPECT_EQ(a.convert(-1.0, rng), 0);
}

TEST(Thermistor, HalfScaleAt25C) {
  Thermistor t;
  Rng rng(1);
  EXPECT_EQ(t.code(25.0, rng), 2048);  // 4095 · 10k / 20k = 2047.5, rounds to even
}

}  // namespace
}  // namespace packsim

// Analog-to-digital conversion shared by the sensor models: an ideal converter with
// gain and offset error and Gaussian noise, rounding to the nearest code and
// saturating at the rails.
//
//   code = clamp(round((x·(1 + gain_error) + offset + noise) / lsb), code_min, code_max)
//   noise ~ N(0, noise_rms)
#pragma once
#include <cstdint>
#include <random>

namespace packsim {

// The simulator's random source: a 64-bit Mersenne Twister plus the second normal of
// the last Box-Muller pair, so each pair of uniforms yields two normals. A standard
// UniformRandomBitGenerator, so std:: algorithms take it too.
class Rng {
 public:
  using result_type = std::mt19937_64::result_type;
  explicit Rng(uint64_t seed = std::mt19937_64::default_seed) : engine_(seed) {}
  result_type operator()() { return engine_(); }
  static constexpr result_type min() { return std::mt19937_64::min(); }
  static constexpr result_type max() { return std::mt19937_64::max(); }

 private:
  friend double standardNormal(Rng& rng);
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool hasSpare_ = false;
};

struct AdcChannel {
  double lsb = 1.0;          // input units per code
  double gain_error = 0.0;   // relative: 0.055 reads 5.5 % high
  double offset = 0.0;       // input units
  double noise_rms = 0.0;    // input units
  int64_t code_min = 0;
  int64_t code_max = 65535;

  int64_t convert(double x, Rng& rng) const;
};

// Zero-mean unit normal drawn with a fixed algorithm (Box-Muller on 53-bit uniforms,
// both outputs of each pair used in turn), so the noise sequence for a seed is the same
// with every standard library.
double standardNormal(Rng& rng);

}  // namespace packsim

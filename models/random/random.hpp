// The simulator's random numbers: one generator type and the derivation of independent
// streams from the scenario's seed. Same seed, same streams, same run, bit for bit.
//
//   measurement noise         Rng(seed): the run's own stream, drawn tick by tick
//   stream s of a seed        Rng(deriveSeed(seed, s)), s one of RngStream below
//   Monte Carlo sample i      deriveSeed(master_seed, i) (core/batch/sweep.hpp)
//
// deriveSeed is splitmix64 of seed + (stream + 1)·0x9E3779B97F4A7C15: nearby seeds and
// nearby streams give unrelated generators.
#pragma once
#include <cstdint>

#include "models/random/mt19937_64.hpp"

namespace packsim {

// Streams drawn once when a model is built, each from its own derived seed so that
// turning one on does not shift the draws of another. The values are part of the
// result: changing one changes every result that uses it.
enum class RngStream : uint64_t {
  CellSpread = 1,                 // cell-to-cell capacity / resistance / SOC spread (models/pack)
  MonitorChannelErrors = 0xAFE,   // per-channel gain and offset of the monitor ICs (models/afe)
  MonitorBoard = 0xB0A4D00,       // + b: the seed of monitor board b >= 1's stack (board 0 uses the run's)
};

// The simulator's random source: a 64-bit Mersenne Twister (std::mt19937_64's numbers,
// mt19937_64.hpp) plus the second normal of the last Box-Muller pair, so each pair of
// uniforms yields two normals. A standard UniformRandomBitGenerator, so std:: algorithms
// take it too.
class Rng {
 public:
  using result_type = uint64_t;
  explicit Rng(uint64_t seed = Mt19937_64::kDefaultSeed) : engine_(seed) {}
  result_type operator()() { return engine_(); }
  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return ~result_type{0}; }

 private:
  friend double standardNormal(Rng& rng);
  friend double standardNormalPair(Rng& rng);
  Mt19937_64 engine_;
  double spare_ = 0.0;
  bool hasSpare_ = false;
};

// A new Box-Muller pair: returns its first normal, keeps the second (standardNormal).
double standardNormalPair(Rng& rng);

// Zero-mean unit normal drawn with a fixed algorithm (Box-Muller on 53-bit uniforms,
// both outputs of each pair used in turn), so the noise sequence for a seed is the same
// with every standard library. Inline: every other draw is the kept second normal, not
// worth a call (several draws per tick and cell on the read-out path).
inline double standardNormal(Rng& rng) {
  if (rng.hasSpare_) {
    rng.hasSpare_ = false;
    return rng.spare_;
  }
  return standardNormalPair(rng);
}

// splitmix64: the seed of stream `stream` of `seed`.
uint64_t deriveSeed(uint64_t seed, uint64_t stream);
inline uint64_t deriveSeed(uint64_t seed, RngStream stream) { return deriveSeed(seed, static_cast<uint64_t>(stream)); }

}  // namespace packsim

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

// One normal of a Box-Muller pair, r·cos(a) (the pair's first) or r·sin(a) (its second),
// as a bracket lo <= value <= hi from a cheap sine and cosine (approx_sincos.hpp); its
// value, the libm's (what standardNormal gives, bit for bit), only when asked
// (lazyNormalValue). A user whose result is the same at both ends of the bracket and
// monotonic in between (an ADC's code: AdcChannel::convertWith) needs no libm sincos
// (some 130 instructions a pair): the bracket is some 1e-12 wide, a code some 1e-3 of
// the noise. lo == hi: the value itself (a second normal its pair's draw computed).
// Two doubles: returned in registers.
struct NormalBracket {
  double lo, hi;
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
  friend NormalBracket standardNormalLazy(Rng& rng);
  friend NormalBracket lazyNormalPair(Rng& rng);
  friend double lazyNormalValue(const Rng& rng, const NormalBracket& n);
  friend double lazyPairNormal(const Rng& rng, bool second);
  Mt19937_64 engine_;
  // The pair's second normal: its value (a pair drawn by standardNormal) or its bracket
  // (a pair drawn by standardNormalLazy, its radius and angle kept); at most one of the two.
  double spare_ = 0.0;
  bool hasSpare_ = false;
  bool hasPending_ = false;
  NormalBracket pending_{0.0, 0.0};
  double pairR_ = 0.0, pairA_ = 0.0;  // the last pair lazyNormalPair drew
};

// A new Box-Muller pair: returns its first normal, keeps the second (standardNormal).
double standardNormalPair(Rng& rng);
// The same pair as a bracket each (no libm sincos): returns the first, keeps the second.
NormalBracket lazyNormalPair(Rng& rng);
// The libm's value of the last pair lazyNormalPair drew: its second or its first normal.
double lazyPairNormal(const Rng& rng, bool second);

// Zero-mean unit normal drawn with a fixed algorithm (Box-Muller on 53-bit uniforms,
// both outputs of each pair used in turn), so the noise sequence for a seed is the same
// with every standard library. Inline: every other draw is the kept second normal, not
// worth a call (several draws per tick and cell on the read-out path).
inline double standardNormal(Rng& rng) {
  if (rng.hasSpare_) {
    rng.hasSpare_ = false;
    return rng.spare_;
  }
  if (rng.hasPending_) {
    rng.hasPending_ = false;
    return lazyPairNormal(rng, true);
  }
  return standardNormalPair(rng);
}

// The next normal of the same sequence as standardNormal's (the draws of the engine and
// the values the same, whichever of the two takes each), as a bracket.
inline NormalBracket standardNormalLazy(Rng& rng) {
  if (rng.hasPending_) {
    rng.hasPending_ = false;
    return rng.pending_;
  }
  if (rng.hasSpare_) {
    rng.hasSpare_ = false;
    return NormalBracket{rng.spare_, rng.spare_};
  }
  return lazyNormalPair(rng);
}

// The value of n, the normal standardNormalLazy(rng) just gave, asked before the next
// draw from rng: its pair is still the last one drawn, and its second normal is pending
// exactly while n is the first.
inline double lazyNormalValue(const Rng& rng, const NormalBracket& n) {
  return n.lo == n.hi ? n.lo : lazyPairNormal(rng, !rng.hasPending_);
}

// splitmix64: the seed of stream `stream` of `seed`.
uint64_t deriveSeed(uint64_t seed, uint64_t stream);
inline uint64_t deriveSeed(uint64_t seed, RngStream stream) { return deriveSeed(seed, static_cast<uint64_t>(stream)); }

}  // namespace packsim

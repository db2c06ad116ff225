// The per-tick helpers that replace a library call on the read-out path must give what
// the call gave, bit for bit: roundHalfEven and the SSE4.1 build's roundsd
// (RoundNearbyint) against std::nearbyint (the default rounding mode), roundHalfAway against std::llround, copyBytes / zeroBytes / copyValues against a plain loop, windowMasks
// (two cells per SSE2 compare) against its plain loop, takeOverBytes / takeOverDoubles
// against a compare-and-copy loop, standardNormal (its kept second
// normal served inline) against Box-Muller written out here on the same engine, ReplySlots
// (a sample reply's kept slot order) against the bit scan, FrameCrcMemo (a repeated short
// frame's kept CRC) against the CRC computed every time, ThermistorCodeCache (a kept code
// range) against the conversion computed every time.
#include <gtest/gtest.h>

#include <cfenv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <random>
#include <vector>

#include <bms/bms_crc.hpp>

#include "core/sim/hw_take_over.hpp"
#include "models/afe/byte_copy.hpp"
#include "models/afe/cell_conversion.hpp"
#include "models/afe/frame_crc_memo.hpp"
#include "models/afe/reply_slots.hpp"
#include "models/afe/window_masks.hpp"
#include "models/random/random.hpp"
#include "models/sensors/round_even.hpp"
#include "models/sensors/round_half_away.hpp"
#include "tests/bits_of.hpp"

namespace packsim {
namespace {

using test::bitsOf;

// RoundNearbyint as a part's SSE4.1 build takes it (the instruction roundsd).
__attribute__((target("sse4.1"))) double roundNative(double v) { return RoundNearbyint::of(v); }
const bool kHasSse41 = __builtin_cpu_supports("sse4.1") != 0;

// Same bits as std::nearbyint (NaN: a NaN): roundHalfEven, and RoundNearbyint's SSE4.1
// build where the CPU has it.
void expectSameAsNearbyint(double v) {
  const double want = std::nearbyint(v), got = roundHalfEven(v), native = kHasSse41 ? roundNative(v) : want;
  if (std::isnan(want)) {
    EXPECT_TRUE(std::isnan(got)) << v;
    EXPECT_TRUE(std::isnan(native)) << v;
    return;
  }
  EXPECT_EQ(bitsOf(got), bitsOf(want)) << std::hexfloat << v << " -> " << got << ", nearbyint " << want;
  EXPECT_EQ(bitsOf(native), bitsOf(want)) << std::hexfloat << v << " -> " << native << " (roundsd), nearbyint " << want;
}

TEST(RoundHalfEven, MatchesNearbyintOnTiesEdgesAndSpecials) {
  ASSERT_EQ(std::fegetround(), FE_TONEAREST);
  const double inf = std::numeric_limits<double>::infinity();
  const double edges[] = {0.0, -0.0, 0.5, -0.5, 1.5, -1.5, 2.5, -2.5, 0.49999999999999994, -0.49999999999999994,
                          0x1p52, -0x1p52, 0x1p52 - 0.5, -(0x1p52 - 0.5), 0x1p52 - 1.5, 0x1p51 + 0.5, 0x1p53, 0x1p53 + 2,
                          1e300, -1e300, std::numeric_limits<double>::denorm_min(), -std::numeric_limits<double>::min(),
                          std::numeric_limits<double>::max(), inf, -inf, std::numeric_limits<double>::quiet_NaN()};
  for (double v : edges) expectSameAsNearbyint(v);
  for (int n = -100000; n <= 100000; ++n) {  // every half-integer tie and its neighbours
    const double tie = n + 0.5;
    expectSameAsNearbyint(tie);
    expectSameAsNearbyint(std::nextafter(tie, -inf));
    expectSameAsNearbyint(std::nextafter(tie, inf));
  }
}

TEST(RoundHalfEven, MatchesNearbyintOnRandomDoubles) {
  std::mt19937_64 gen(32);
  std::uniform_real_distribution<double> codes(-70000.0, 70000.0);  // an ADC's code range and beyond
  for (int k = 0; k < 2000000; ++k) expectSameAsNearbyint(codes(gen));
  for (int k = 0; k < 2000000; ++k) {  // any bit pattern: every exponent, sign, NaN payload
    const uint64_t b = gen();
    double v;
    std::memcpy(&v, &b, sizeof v);
    expectSameAsNearbyint(v);
  }
}

void expectSameAsLlround(double v) { EXPECT_EQ(roundHalfAway(v), std::llround(v)) << std::hexfloat << v; }

TEST(RoundHalfAway, MatchesLlroundOnTiesEdgesAndRandomValues) {
  const double inf = std::numeric_limits<double>::infinity();
  const double edges[] = {0.0, -0.0, 0.5, -0.5, 1.5, -1.5, 2.5, -2.5, 0.49999999999999994, -0.49999999999999994,
                          1.0, -1.0, 0x1p52, -0x1p52, 0x1p52 - 0.5, -(0x1p52 - 0.5), 0x1p52 - 1.5, 0x1p51 + 0.5,
                          0x1p53, 0x1p53 + 2, 0x1p62, -0x1p62, std::numeric_limits<double>::denorm_min(),
                          -std::numeric_limits<double>::min()};
  for (double v : edges) expectSameAsLlround(v);
  for (int n = -100000; n <= 100000; ++n) {  // every half-integer tie and its neighbours
    const double tie = n + 0.5;
    expectSameAsLlround(tie);
    expectSameAsLlround(std::nextafter(tie, -inf));
    expectSameAsLlround(std::nextafter(tie, inf));
  }
  std::mt19937_64 gen(33);
  std::uniform_real_distribution<double> ms(-1e10, 1e10);  // a run's milliseconds and beyond
  for (int k = 0; k < 1000000; ++k) expectSameAsLlround(ms(gen));
  for (int k = 0; k < 10000; ++k) {  // a 10 ms tick's times in ms, as the host's clock rounds them
    const double t_s = k * 0.01;
    expectSameAsLlround(t_s * 1e3);
  }
}

TEST(ByteCopy, CopiesAndClearsExactlyTheBytesAskedFor) {
  std::mt19937 gen(5);
  for (size_t n = 0; n <= 1100; n += (n < 80 ? 1 : 37)) {
    for (size_t off = 0; off < 3; ++off) {
      std::vector<uint8_t> src(n + 8), dst(n + 8, 0xA5), want(n + 8, 0xA5);
      for (uint8_t& b : src) b = static_cast<uint8_t>(gen());
      for (size_t i = 0; i < n; ++i) want[off + i] = src[i];
      copyBytes(dst.data() + off, src.data(), n);
      EXPECT_EQ(dst, want) << "copy of " << n << " bytes at offset " << off;
      for (size_t i = 0; i < n; ++i) want[off + i] = 0;
      zeroBytes(dst.data() + off, n);
      EXPECT_EQ(dst, want) << "clear of " << n << " bytes at offset " << off;
    }
  }
}

TEST(ByteCopy, CopyValuesCopiesExactlyTheValuesAskedFor) {
  std::mt19937_64 gen(6);
  for (size_t n = 0; n <= 20; ++n) {
    std::vector<double> src(n + 2), dst(n + 2, -7.5), want(n + 2, -7.5);
    for (double& v : src) v = static_cast<double>(gen() >> 11) * 0x1.0p-40 - 1000.0;
    if (n > 0) src[0] = -0.0;
    for (size_t i = 0; i < n; ++i) want[i] = src[i];
    copyValues(dst.data(), src.data(), n);
    for (size_t i = 0; i < n + 2; ++i) ASSERT_EQ(bitsOf(dst[i]), bitsOf(want[i])) << "n " << n << " at " << i;
  }
}

// Every count up to 32 cells, values on, just inside and just outside both thresholds,
// infinities and NaN at every position: the same bits as the plain loop.
TEST(WindowMasks, MatchesThePlainLoopForEveryCountAndEdge) {
  const double lo = 2.5, hi = 4.25;
  const double specials[] = {lo, hi, std::nextafter(lo, 0.0), std::nextafter(lo, 5.0), std::nextafter(hi, 0.0),
                             std::nextafter(hi, 5.0), 3.7, -0.0, 0.0,
                             std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::quiet_NaN()};
  std::mt19937_64 rng(455);
  std::uniform_int_distribution<size_t> pick(0, std::size(specials) - 1);
  for (int n = 0; n <= 32; ++n) {
    for (int trial = 0; trial < 200; ++trial) {
      std::vector<double> v(static_cast<size_t>(n) + 1);  // one past n: must not be looked at
      for (double& x : v) x = specials[pick(rng)];
      v.back() = 100.0;
      const size_t at = static_cast<size_t>(trial) % 2;  // an unaligned start too
      std::vector<double> buf(at, 0.0);
      buf.insert(buf.end(), v.begin(), v.end());
      uint32_t o = 0xDEAD, u = 0xBEEF, oRef = 0, uRef = 0;
      windowMasks(buf.data() + at, n, lo, hi, o, u);
      windowMasksScalar(buf.data() + at, n, lo, hi, oRef, uRef);
      ASSERT_EQ(o, oRef) << "n " << n << " trial " << trial;
      ASSERT_EQ(u, uRef) << "n " << n << " trial " << trial;
    }
  }
  uint32_t o = 1, u = 1;
  windowMasks(nullptr, 0, lo, hi, o, u);  // no cells: no bits
  EXPECT_EQ(o, 0u);
  EXPECT_EQ(u, 0u);
}

// Every code's position against thresholds at, around and between the ends of the
// 16-bit range (the vector compare offsets them by 0x8000): the plain loop's bits.
TEST(WindowMasks, CodesMatchThePlainLoop) {
  const uint16_t edges[] = {0, 1, 0x7FFE, 0x7FFF, 0x8000, 0x8001, 0xFFFE, 0xFFFF, 1234, 52000};
  std::mt19937_64 rng(0x455);
  std::uniform_int_distribution<size_t> pickEdge(0, std::size(edges) - 1);
  std::uniform_int_distribution<unsigned> any(0, 0xFFFF);
  for (int trial = 0; trial < 20000; ++trial) {
    uint16_t code[17];
    for (uint16_t& c : code) c = trial % 2 ? edges[pickEdge(rng)] : static_cast<uint16_t>(any(rng));
    const uint16_t lo = edges[pickEdge(rng)], hi = trial % 3 ? edges[pickEdge(rng)] : static_cast<uint16_t>(any(rng));
    const uint16_t* at = code + trial % 2;  // unaligned too
    uint32_t o = 0xDEAD, u = 0xBEEF, oRef = 0, uRef = 0;
    codeWindowMasks16(at, lo, hi, o, u);
    codeWindowMasks16Scalar(at, lo, hi, oRef, uRef);
    ASSERT_EQ(o, oRef) << "trial " << trial << " lo " << lo << " hi " << hi;
    ASSERT_EQ(u, uRef) << "trial " << trial << " lo " << lo << " hi " << hi;
  }
}

// Every length up to 40, each element equal, changed, +0.0 against -0.0 (equal), NaN on
// either side (unequal): what the plain compare-and-copy loop copies and answers.
TEST(TakeOver, MatchesTheCompareAndCopyLoop) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double values[] = {1.0, 0.25, 0.0, -0.0, nan, 1.0};
  std::mt19937_64 rng(12);
  std::uniform_int_distribution<size_t> pick(0, std::size(values) - 1);
  std::uniform_int_distribution<int> byte(0, 3), changeAt(0, 9);
  for (size_t n = 0; n <= 40; ++n) {
    for (int trial = 0; trial < 300; ++trial) {
      std::vector<double> src(n), dst(n);
      std::vector<uint8_t> srcB(n), dstB(n);
      for (size_t i = 0; i < n; ++i) {
        src[i] = values[pick(rng)];
        dst[i] = changeAt(rng) == 0 ? values[pick(rng)] : src[i];  // mostly equal, as ticks are
        srcB[i] = static_cast<uint8_t>(byte(rng));
        dstB[i] = changeAt(rng) == 0 ? static_cast<uint8_t>(byte(rng)) : srcB[i];
      }
      bool want = false, wantB = false;
      for (size_t i = 0; i < n; ++i) want |= dst[i] != src[i], wantB |= dstB[i] != srcB[i];
      const bool got = takeOverDoubles(dst.data(), src.data(), n), gotB = takeOverBytes(dstB.data(), srcB.data(), n);
      ASSERT_EQ(got, want) << "n " << n << " trial " << trial;
      ASSERT_EQ(gotB, wantB) << "n " << n << " trial " << trial;
      for (size_t i = 0; i < n; ++i) ASSERT_EQ(bitsOf(dst[i]), bitsOf(src[i])) << "n " << n << " at " << i;
      ASSERT_EQ(dstB, srcB) << "n " << n;
    }
  }
}

// The kept reply order of a mask, after masks in any order (a change, the same mask
// again, back to an earlier one), is the bit scan's: the set bits, highest first.
TEST(ReplySlots, MatchesTheBitScanAfterEveryChange) {
  std::mt19937 gen(455);
  ReplySlots kept;
  std::vector<uint32_t> masks = {0u, 0xFFFFFFFFu, 0x80000001u, 1u, 0x0FFF07C0u, 0x0FFF07C0u, 0u};
  for (int k = 0; k < 2000; ++k) masks.push_back(k % 3 == 0 ? masks[masks.size() - 1] : static_cast<uint32_t>(gen()));
  for (uint32_t mask : masks) {
    kept.select(mask);
    std::vector<unsigned> plain;
    for (int b = 31; b >= 0; --b)
      if ((mask >> b) & 1u) plain.push_back(static_cast<unsigned>(b));
    ASSERT_EQ(kept.count(), plain.size()) << std::hex << mask;
    for (size_t i = 0; i < plain.size(); ++i) ASSERT_EQ(kept.slots()[i], plain[i]) << std::hex << mask;
  }
}

// The documented algorithm, independently: 53-bit uniforms u1 in (0, 1), u2 in [0, 1),
// r = sqrt(-2 ln u1), the pair r·cos(2πu2), r·sin(2πu2), used in that order.
TEST(StandardNormal, IsBoxMullerOnTheSeedsMersenneTwisterBitForBit) {
  for (uint64_t seed : {uint64_t{1}, uint64_t{0x536A}, uint64_t{20261126}}) {
    Rng rng(seed);
    std::mt19937_64 ref(seed);
    for (int k = 0; k < 500000; ++k) {
      const double u1 = (static_cast<double>(ref() >> 11) + 0.5) * 0x1.0p-53;
      const double u2 = static_cast<double>(ref() >> 11) * 0x1.0p-53;
      const double r = std::sqrt(-2.0 * std::log(u1)), a = 6.283185307179586 * u2;
      const double first = r * std::cos(a), second = r * std::sin(a);
      const double got1 = standardNormal(rng), got2 = standardNormal(rng);
      ASSERT_EQ(bitsOf(got1), bitsOf(first)) << "seed " << seed << " pair " << k;
      ASSERT_EQ(bitsOf(got2), bitsOf(second)) << "seed " << seed << " pair " << k;
      if (k % 1000 == 0) ASSERT_EQ(rng(), ref()) << "a raw draw between pairs";  // the engines stay in step
    }
  }
}

// Frames of every length around the short-frame limit, each asked again, after a change of
// one byte anywhere (the overlapping words of the key must all see it), after a longer
// frame and after one of another length with the same leading bytes: each CRC the same as
// computing it.
TEST(FrameCrcMemo, MatchesTheCrcComputedEveryTime) {
  FrameCrcMemo<uint8_t, bms::crcCrc8> memo8;
  FrameCrcMemo<uint16_t, bms::crcCrc16> memo16;
  std::mt19937 gen(3);
  uint8_t buf[40];
  auto ask = [&](const uint8_t* p, size_t n) {
    EXPECT_EQ(memo8.of(p, n), bms::crcCrc8(p, n)) << n;
    EXPECT_EQ(memo16.of(p, n), bms::crcCrc16(p, n)) << n;
  };
  for (int round = 0; round < 200; ++round) {
    for (uint8_t& b : buf) b = static_cast<uint8_t>(gen());
    for (size_t n = 0; n <= 20; ++n) {
      ask(buf, n);
      ask(buf, n);  // the same frame again: the kept CRC
      for (size_t i = 0; i < n; ++i) {
        buf[i] ^= static_cast<uint8_t>(1u << (gen() % 8));  // one bit of one byte
        ask(buf, n);
        ask(buf, n);
      }
      ask(buf, n + 1);  // the same bytes and one more
      ask(buf, 30);     // a long frame passes by
      ask(buf, n);
    }
  }
}

// A thermistor input's conversion through its cache (the last ideal code, and without
// noise the range of temperatures its last code spans) against Thermistor::code computed
// every time, and its comparator's answer (idealBelow) against idealCode's: slow drifts through many codes both ways (a node warming and cooling),
// steps walking across a rounding point in ulps, jumps, the rails, NaN and the pole at
// -273.15 °C, for several dividers; with noise, the same draws from the same stream.
TEST(ThermistorCodeCache, ConvertsAsTheThermistorEveryTime) {
  std::vector<Thermistor> ntcs(4);
  ntcs[1].beta_K = 3950.0, ntcs[1].pullup_ohm = 4700.0;
  ntcs[2].bits = 16, ntcs[2].r25_ohm = 100000.0, ntcs[2].beta_K = 4250.0;
  ntcs[3].noise_codes_rms = 0.7;
  std::mt19937_64 gen(12);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const Thermistor& ntc : ntcs) {
    ThermistorCodeCache kept;
    Rng a(5), b(5);
    auto expectSame = [&](double temp_C) {
      ASSERT_EQ(kept.code(ntc, temp_C, a), ntc.code(temp_C, b)) << temp_C << " bits " << ntc.bits;
      // The comparator's question at thresholds around the code (its window's edges and
      // just inside and outside them), far off, and NaN.
      const double x = ntc.idealCode(temp_C), c = std::nearbyint(x);
      for (double thr : {c - 0.5, c + 0.5, std::nextafter(c - 0.5, 0.0), std::nextafter(c + 0.5, 1e9),
                         std::nextafter(c - 0.5, 1e9), std::nextafter(c + 0.5, 0.0), c, x, c - 7.0, c + 7.0,
                         std::numeric_limits<double>::quiet_NaN()})
        ASSERT_EQ(kept.idealBelow(ntc, temp_C, thr), x < thr) << temp_C << " threshold " << thr;
    };
    double t = 25.0;
    for (int k = 0; k < 200000; ++k) {  // drifts of 1e-5 .. 1e-3 K a step, turning now and then
      const double step = (k / 20000 % 2 ? -1.0 : 1.0) * std::pow(10.0, -5.0 + 2.0 * u(gen));
      t += step;
      expectSame(t);
    }
    for (int k = 0; k < 2000; ++k) expectSame(-60.0 + 200.0 * u(gen));  // jumps
    // Across a rounding point in ulps: the temperature where the code is c + 0.5, found by
    // bisection, and the doubles around it.
    for (int c : {100, 2047, 3000}) {
      if (c >= ntc.fullScaleCode()) continue;
      double lo = -80.0, hi = 200.0;  // code(lo) > c + 0.5 > code(hi)
      for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (ntc.idealCode(mid) > c + 0.5 ? lo : hi) = mid;
      }
      double x = lo;
      for (int i = 0; i < 64; ++i) x = std::nextafter(x, -1e9);
      for (int i = 0; i < 128; ++i, x = std::nextafter(x, 1e9)) expectSame(x);
      for (int i = 0; i < 128; ++i, x = std::nextafter(x, -1e9)) expectSame(x);
    }
    for (double x : {-273.15, std::nextafter(-273.15, 0.0), -273.0, -300.0, 1e6, -1e6, 25.0,
                     std::numeric_limits<double>::quiet_NaN(), 25.0, std::numeric_limits<double>::infinity(), 25.0})
      expectSame(x);
    ASSERT_EQ(a(), b()) << "the noise streams stay in step";
  }
}

}  // namespace
}  // namespace packsim

// BalancePauses keeps its pauses in a ring and looks again only at what changed since
// it last dropped the ended ones. The expectation here is the plain list it replaced:
// every pause in a vector, the ended ones removed at every add, the oldest erased when
// full. Both must give the same conducting share, bit for bit, in every order of adds
// and asks, also past kMaxPauses pauses without an ask.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "models/afe/balance_pause.hpp"

namespace packsim {
namespace {

class PlainPauses {
 public:
  void add(double from_s, double to_s, uint32_t cells) {
    if (!(to_s > from_s) || cells == 0) return;
    pauses_.erase(std::remove_if(pauses_.begin(), pauses_.end(), [&](const P& p) { return p.to_s <= asked_s_; }),
                  pauses_.end());
    if (pauses_.size() >= BalancePauses::kMaxPauses) pauses_.erase(pauses_.begin());
    if (!pauses_.empty() && pauses_.back().to_s > from_s) pauses_.back().to_s = std::max(pauses_.back().from_s, from_s);
    pauses_.push_back({from_s, to_s, cells});
  }
  double conductingShare(int cell, double t0_s, double t1_s) {
    asked_s_ = std::max(asked_s_, t0_s);
    if (!(t1_s > t0_s)) return 1.0;
    double open_s = 0.0;
    for (const P& p : pauses_)
      if ((p.cells >> cell) & 1u) open_s += std::max(0.0, std::min(p.to_s, t1_s) - std::max(p.from_s, t0_s));
    return 1.0 - std::min(open_s, t1_s - t0_s) / (t1_s - t0_s);
  }
  size_t size() const { return pauses_.size(); }

 private:
  struct P {
    double from_s, to_s;
    uint32_t cells;
  };
  std::vector<P> pauses_;
  double asked_s_ = -std::numeric_limits<double>::infinity();
};

// Conversions every tick_s lasting conv_s (some cut short by the next, some restarted
// a little earlier from tick `early_from` on), asked every ask_every ticks (0: never)
// over a window that may reach back before earlier pauses.
void expectSameAsPlainList(uint32_t seed, int ticks, int ask_every, int early_from = 0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  BalancePauses ring;
  PlainPauses plain;
  double t = 0.0;
  for (int i = 0; i < ticks; ++i) {
    const double tick_s = 0.01 * (0.5 + u(rng));
    const double early = u(rng) < 0.1 ? 0.02 * u(rng) : 0.0;
    const double from = t - (i >= early_from ? early : 0.0);  // now and then before the last one ended
    const double to = from + (u(rng) < 0.05 ? 0.0 : 0.004 + 0.02 * u(rng));  // some empty
    const uint32_t cells = u(rng) < 0.05 ? 0u : static_cast<uint32_t>(rng()) & 0xFFFu;
    ring.add(from, to, cells);
    plain.add(from, to, cells);
    if (ask_every > 0 && i % ask_every == 0) {
      const double t0 = t - 0.05 * u(rng), t1 = t0 + 0.03 * u(rng);
      for (int c = 0; c < 12; ++c) ASSERT_EQ(ring.conductingShare(c, t0, t1), plain.conductingShare(c, t0, t1)) << "tick " << i;
    }
    t += tick_s;
  }
  // A window over the whole run: every pause kept counts.
  for (int c = 0; c < 12; ++c) EXPECT_EQ(ring.conductingShare(c, 0.0, t), plain.conductingShare(c, 0.0, t));
  for (int c = 0; c < 12; ++c) EXPECT_EQ(ring.conductingShare(c, t - 1.0, t), plain.conductingShare(c, t - 1.0, t));
}

TEST(BalancePauses, SameShareAsThePlainListWhenAskedEveryTick) { expectSameAsPlainList(1, 3000, 1); }

TEST(BalancePauses, SameShareAsThePlainListWhenAskedNowAndThen) {
  for (int every : {2, 7, 300, 1000}) expectSameAsPlainList(static_cast<uint32_t>(every), 3000, every);
}

TEST(BalancePauses, NeverAskedKeepsTheLastMaxPausesLikeThePlainList) { expectSameAsPlainList(5, 2000, 0); }

// Pauses added in time order (the host's conversions, each at or after the one before):
// the ring drops the ended ones from its front alone. The same shares as the plain list,
// and still after the first pause that begins before the last one (out of order: every
// pause looked at again from then on).
TEST(BalancePauses, InTimeOrderSameShareAsThePlainList) {
  for (int every : {1, 3, 300, 0}) expectSameAsPlainList(static_cast<uint32_t>(10 + every), 3000, every, 3000);
}

TEST(BalancePauses, OutOfOrderAfterALongInOrderRunSameShareAsThePlainList) {
  for (int every : {1, 5, 0}) expectSameAsPlainList(static_cast<uint32_t>(20 + every), 3000, every, 1500);
}

TEST(BalancePauses, APauseFullyBeforeTheWindowDoesNotCount) {
  BalancePauses p;
  p.add(0.0, 0.004, 0b1);
  EXPECT_EQ(p.conductingShare(0, 0.0, 0.01), 1.0 - 0.004 / 0.01);
  EXPECT_EQ(p.conductingShare(1, 0.0, 0.01), 1.0);
  p.add(0.01, 0.014, 0b1);
  EXPECT_EQ(p.conductingShare(0, 0.01, 0.02), 1.0 - (0.014 - 0.01) / (0.02 - 0.01));
}

}  // namespace
}  // namespace packsim

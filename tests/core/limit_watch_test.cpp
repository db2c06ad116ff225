// LimitWatch (core/sim/limit_watch.hpp) on a scripted truth, tick by tick: which
// episodes open, close and become limit_unseen events, against times worked out by hand.
// Several episodes overlap (cells 2 and 3), one opens while another is open, one is cut
// short by the protection's own delay, one ends when the BMS sees it, and a row that is
// active keeps a new one from opening; a cell's later episode is reported only when longer.
#include <gtest/gtest.h>

#include <bms/bms_faults.hpp>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/sim/limit_watch.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

// `cells` simple cells at a 100 ms tick, their under-voltage (3.0 V) and over-temperature
// (60 C) rows without a delay.
Scenario undelayedLimits(int cells) {
  return test::scenarioFromYaml(test::simpleCellYaml(cells) +
                                "bms: {tick_ms: 100, protections: {cell_undervoltage: {threshold_V: 3.0, delay_ms: 0}, "
                                "overtemperature: {threshold_C: 60, delay_ms: 0}}}\n"
                                "load: {current_A: 1}\nrun: {duration_s: 20}\n");
}

TEST(LimitWatch, EpisodesOpenCloseAndReportAgainstAHandWrittenTruth) {
  const Scenario s = test::scenarioFromYaml(
      test::simpleCellYaml(3) +
      "bms: {tick_ms: 100, protections: {cell_undervoltage: {threshold_V: 3.0, delay_ms: 500}}}\n"
      "load: {current_A: 1}\nrun: {duration_s: 20}\n");
  const double tick_s = 0.1;
  // What the BMS takes by design: delay + one read-out period (at least a tick) + a tick.
  const double allowed_s = 0.5 + std::max(s.bms.readout.period_s, tick_s) + tick_s;
  ASSERT_LT(allowed_s, 1.0);  // the 0.2 s dip below is within it, the 2 s ones are not
  LimitWatch w(s, 3, 1);
  std::vector<std::pair<double, std::string>> events;
  const LimitWatch::EventSink sink = [&](double t, const std::string& d) { events.emplace_back(t, d); };
  const uint32_t uvBit = 1u << static_cast<int>(bms::FaultId::CellUnderVoltage);
  for (int k = 0; k <= 120; ++k) {
    const double t = k * tick_s;
    std::vector<double> v = {3.7, 3.7, 3.7};
    const std::vector<double> temp = {25.0, 25.0, 25.0};
    if (k >= 10 && k < 50) v[1] = k == 30 ? 2.8 : 2.9;  // cell 2: 1.0 s .. 5.0 s, lowest 2.8 V at 3.0 s
    if (k >= 20 && k < 22) v[2] = 2.95;                 // cell 3: 0.2 s, within the delay
    if (k >= 60) v[0] = 2.9;                            // cell 1: from 6.0 s to the end
    const bool active = k >= 80 && k < 100;             // the BMS sees it from 8.0 s to 10.0 s
    w.tick(t, v, temp, 1.0, active ? uvBit : 0u, sink);
  }
  w.finish(13.0, sink);
  ASSERT_EQ(events.size(), 3u);
  const std::string uv = std::string(bms::faultName(bms::FaultId::CellUnderVoltage)) + ": ";
  EXPECT_DOUBLE_EQ(events[0].first, 5.0);
  EXPECT_EQ(events[0].second, uv + "cell 2 more than 0.55 mV below the 3.000 V limit from 1.00 s, back within it at 5.00 s, never seen "
                                   "by the BMS (4.00 s) (min 2.8000 V)");
  EXPECT_DOUBLE_EQ(events[1].first, 8.0);
  EXPECT_EQ(events[1].second, uv + "cell 1 more than 0.55 mV below the 3.000 V limit from 6.00 s, unseen by the BMS for 2.00 "
                                   "s (min 2.9000 V)");
  // Below the limit at 9 s too, but the row is active: the next episode opens at 10 s.
  // It is reported for being longer than the one reported before (2 s) for this cell.
  EXPECT_DOUBLE_EQ(events[2].first, 13.0);
  EXPECT_EQ(events[2].second, uv + "cell 1 more than 0.55 mV below the 3.000 V limit from 10.00 s, unseen by the BMS to "
                                   "the end of the run (3.00 s) (min 2.9000 V)");
  EXPECT_EQ(w.shortExcursions(), 1);
  EXPECT_DOUBLE_EQ(w.longestUnseen_s(), 4.0);
  EXPECT_EQ(w.longestUnseen(), events[0].second);
}

// A value nearer the limit than half the BMS's reading step reads as the limit itself
// (the firmware's whole mV, rounded, of a 100 uV code: 0.5 + 0.05 mV here; its 0.1 C):
// a cell 0.5 mV under 3.000 V, or 0.04 C over 60 C, for 3 s is no episode; 0.6 mV under,
// or 0.06 C over, is. At a slow discharge the truth spends seconds in that band (system
// C's 0.2C bench discharge: 1 s of a 3 s 'unseen' that the BMS could not have read).
TEST(LimitWatch, WithinHalfTheReadingStepOfTheLimitIsNoEpisode) {
  const Scenario s = undelayedLimits(2);
  for (const bool beyond : {false, true}) {
    LimitWatch w(s, 2, 1);
    std::vector<std::pair<double, std::string>> events;
    const LimitWatch::EventSink sink = [&](double t, const std::string& d) { events.emplace_back(t, d); };
    for (int k = 0; k <= 40; ++k) {
      std::vector<double> v = {3.7, 3.7}, temp = {25.0, 25.0};
      if (k >= 10 && k < 40) {  // 1.0 s .. 4.0 s
        v[0] = beyond ? 3.0 - 0.6e-3 : 3.0 - 0.5e-3;
        temp[1] = beyond ? 60.06 : 60.04;
      }
      w.tick(k * 0.1, v, temp, 1.0, 0u, sink);
    }
    ASSERT_EQ(events.size(), beyond ? 2u : 0u) << beyond;
    if (beyond) {
      EXPECT_NE(events[0].second.find("cell 1 more than 0.55 mV below the 3.000 V limit from 1.00 s"), std::string::npos)
          << events[0].second;
      EXPECT_NE(events[1].second.find("cell 2 more than 0.05 C above the 60 C limit from 1.00 s"), std::string::npos)
          << events[1].second;
    }
  }
}

// The scan for a value past a limit (taken as the values' extremes once a tick) skips a
// NaN as the comparison with the threshold does: a cell past the limit beside a NaN one,
// before or after it in the list, still opens its episode; overtemperature too.
TEST(LimitWatch, AValuePastTheLimitIsFoundBesideANaN) {
  const Scenario s = undelayedLimits(3);
  for (int nanAt : {0, 2}) {
    LimitWatch w(s, 3, 1);
    std::vector<std::pair<double, std::string>> events;
    const LimitWatch::EventSink sink = [&](double t, const std::string& d) { events.emplace_back(t, d); };
    for (int k = 0; k <= 40; ++k) {
      std::vector<double> v = {3.7, 3.7, 3.7}, temp = {25.0, 25.0, 25.0};
      v[static_cast<size_t>(nanAt)] = temp[static_cast<size_t>(nanAt)] = NAN;
      if (k >= 10 && k < 30) v[1] = 2.9, temp[1] = 70.0;  // cell 2: 1.0 s .. 3.0 s
      w.tick(k * 0.1, v, temp, 1.0, 0u, sink);
    }
    ASSERT_EQ(events.size(), 2u) << "NaN at cell " << nanAt + 1;
    EXPECT_DOUBLE_EQ(events[0].first, 3.0);
    EXPECT_NE(events[0].second.find("cell 2 more than 0.55 mV below the 3.000 V limit from 1.00 s"), std::string::npos) << events[0].second;
    EXPECT_NE(events[1].second.find("cell 2 more than 0.05 C above the 60 C limit from 1.00 s"), std::string::npos) << events[1].second;
  }
}

// Extremes taken one value at a time (RunTracker::tick's pass) and over a vector (SSE2,
// two at a time) agree, a NaN skipped wherever it stands.
TEST(LimitWatch, ExtremesTakenOneByOneMatchTheVectorPass) {
  const std::vector<std::vector<double>> cases = {
      {}, {3.2}, {NAN}, {3.1, NAN, 2.9}, {NAN, 4.2, 3.3, -0.0, 0.0}, {2.5, 2.5, 1e300, -1e300, NAN, NAN, 7.0}};
  for (const std::vector<double>& v : cases) {
    LimitWatch::Extremes one, all;
    for (double x : v) one.take(x);
    all.take(v);
    EXPECT_EQ(one.lo, all.lo) << v.size();
    EXPECT_EQ(one.hi, all.hi) << v.size();
  }
}

// A tick given the cells' extremes (RunTracker::tick takes them in its own pass) raises
// the same events at the same times as one that takes them itself.
TEST(LimitWatch, KnownExtremesGiveTheSameEpisodes) {
  const Scenario s = undelayedLimits(3);
  LimitWatch plain(s, 3, 1), given(s, 3, 1);
  std::vector<std::pair<double, std::string>> a, b;
  const LimitWatch::EventSink sinkA = [&](double t, const std::string& d) { a.emplace_back(t, d); };
  const LimitWatch::EventSink sinkB = [&](double t, const std::string& d) { b.emplace_back(t, d); };
  for (int k = 0; k <= 60; ++k) {
    std::vector<double> v = {3.7, 3.6, 3.5}, temp = {25.0, 26.0, 27.0};
    if (k >= 10 && k < 30) v[1] = 2.9 - 0.001 * k;
    if (k >= 20 && k < 45) temp[2] = 61.0 + k;
    if (k == 35) v[0] = NAN;
    LimitWatch::CellExtremes ext;
    for (size_t c = 0; c < v.size(); ++c) ext.volts.take(v[c]), ext.temps.take(temp[c]);
    const uint32_t active = k >= 40 ? ~0u : 0u;
    plain.tick(k * 0.1, v, temp, 1.0, active, sinkA);
    given.tick(k * 0.1, v, temp, 1.0, active, sinkB, &ext);
  }
  plain.finish(6.0, sinkA);
  given.finish(6.0, sinkB);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a, b);
  EXPECT_EQ(plain.shortExcursions(), given.shortExcursions());
}

}  // namespace
}  // namespace packsim

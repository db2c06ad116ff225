// The balancing policy (bms/bms_balance) driven tick by tick with chosen readings.
#include <bms/bms_balance.hpp>
#include <bms/bms_config.hpp>
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

namespace {

struct Policy {
  bms::Config cfg;
  bms::BalanceState st{};
  bms::Telemetry tm{};
  uint32_t mask[bms::kBalanceWords]{};
  uint8_t arms = 0;
  uint32_t now_ms = 0;

  explicit Policy(uint16_t cells, uint8_t therms = 0) : cfg(bms::defaultConfig(cells, therms)) {
    cfg.balance.enabled = true;
    cfg.balance.when = bms::BalanceWhen::Always;
    cfg.balance.period_ms = 1000;
    bms::balanceReset(st);
  }
  void cells(const std::vector<uint16_t>& mv) {
    uint16_t lo = 65535, hi = 0;
    for (size_t i = 0; i < mv.size(); ++i) {
      tm.cellVoltage_mV[i] = mv[i];
      lo = mv[i] < lo ? mv[i] : lo;
      hi = mv[i] > hi ? mv[i] : hi;
    }
    tm.minCell_mV = lo;
    tm.maxCell_mV = hi;
  }
  // One tick 1 s later; returns the mask as a bit per cell.
  // fresh: the cells are a new read-out (every tick here unless said otherwise).
  std::vector<int> tick(bool permitted = true, bool charging = false, bool fresh = true) {
    bms::balanceStep(cfg, st, tm, permitted, charging, fresh, now_ms, mask, arms);
    now_ms += 1000;
    std::vector<int> on;
    for (uint16_t c = 0; c < cfg.cellCount; ++c) on.push_back(bms::balanceBit(mask, c) ? 1 : 0);
    return on;
  }
};

using V = std::vector<int>;

TEST(BalancePolicy, StartsAboveStartDeltaAndStopsBelowStopDelta) {
  Policy p(4);  // start 50 mV, stop 10 mV (defaults)
  p.cells({3700, 3740, 3700, 3700});
  EXPECT_EQ(p.tick(), (V{0, 0, 0, 0})) << "40 mV is below the 50 mV start";
  p.cells({3700, 3760, 3700, 3700});
  EXPECT_EQ(p.tick(), (V{0, 1, 0, 0}));
  p.cells({3700, 3730, 3700, 3700});  // inside the hysteresis band: keeps going
  EXPECT_EQ(p.tick(), (V{0, 1, 0, 0}));
  p.cells({3700, 3709, 3700, 3700});
  EXPECT_EQ(p.tick(), (V{0, 0, 0, 0}));
  EXPECT_EQ(p.st.status, bms::BalanceStatus::Balanced);
  p.cells({3700, 3730, 3700, 3700});  // below start again: stays off
  EXPECT_EQ(p.tick(), (V{0, 0, 0, 0}));
}

// A spread of exactly the stop delta ends balancing: no cell is more than stopDelta above
// the minimum, so none could be chosen. It stays off until the spread passes the start
// delta again; it used to stay active with nothing chosen, report "balanced", and start
// again at 11 mV (system C's bench charge, scenarios/balance/bench_6s_balancing.yaml,
// started again 19 times in the 300 s after it first reported balanced, as the reading's
// noise crossed the stop delta).
TEST(BalancePolicy, ASpreadAtTheStopDeltaStopsUntilTheStartDelta) {
  Policy p(4);  // start 50 mV, stop 10 mV (defaults)
  p.cells({3700, 3760, 3700, 3700});
  EXPECT_EQ(p.tick(), (V{0, 1, 0, 0}));
  p.cells({3700, 3710, 3700, 3700});
  EXPECT_EQ(p.tick(), (V{0, 0, 0, 0}));
  EXPECT_EQ(p.st.status, bms::BalanceStatus::Balanced);
  for (const uint16_t high : {3711, 3720, 3750}) {  // up to the start delta: stays off
    p.cells({3700, high, 3700, 3700});
    EXPECT_EQ(p.tick(), (V{0, 0, 0, 0})) << high;
    EXPECT_EQ(p.st.status, bms::BalanceStatus::Balanced) << high;
  }
  p.cells({3700, 3751, 3700, 3700});
  EXPECT_EQ(p.tick(), (V{0, 1, 0, 0}));
  EXPECT_EQ(p.st.status, bms::BalanceStatus::Balancing);
}

TEST(BalancePolicy, NeverBalancesACellBelowTheMinimumVoltage) {
  Policy p(3);
  p.cfg.balance.minCell_mV = 3300;
  p.cells({3200, 3290, 3350});
  EXPECT_EQ(p.tick(), (V{0, 0, 1})) << "3.29 V is above min + stop but below the 3.3 V floor";
}

TEST(BalancePolicy, PausesOnBoardTemperatureAndResumesBelowTheResumeLevel) {
  Policy p(2, 3);
  p.cfg.therm.cell = 0b011;
  p.cfg.therm.board = 0b100;  // channel 2 is the board (70 C pause, 60 C resume)
  p.cfg.therm.perBoard = 1;
  p.cells({3700, 3800});
  p.tm.temperature_dC[2] = 650;
  EXPECT_EQ(p.tick(), (V{0, 1}));
  p.tm.temperature_dC[2] = 705;
  EXPECT_EQ(p.tick(), (V{0, 0}));
  EXPECT_EQ(p.st.status, bms::BalanceStatus::BoardHot);
  p.tm.temperature_dC[2] = 650;  // between resume and pause: still paused
  EXPECT_EQ(p.tick(), (V{0, 0}));
  p.tm.temperature_dC[2] = 595;
  EXPECT_EQ(p.tick(), (V{0, 1}));
  p.tm.temperature_dC[2] = INT16_MIN;  // board thermistor open: fail safe
  EXPECT_EQ(p.tick(), (V{0, 0}));
}

TEST(BalancePolicy, NoTwoAdjacentCellsPicksTheHighestFirst) {
  Policy p(5);
  p.cells({3800, 3820, 3810, 3700, 3790});
  EXPECT_EQ(p.tick(), (V{1, 1, 1, 0, 1}));
  p.cfg.balance.noAdjacent = true;
  EXPECT_EQ(p.tick(), (V{0, 1, 0, 0, 1})) << "cell 2 (highest) blocks 1 and 3; cell 5 is free";
}

TEST(BalancePolicy, OnlyWhileChargingOrAtRestAsConfigured) {
  Policy p(2);
  p.cells({3700, 3800});
  p.cfg.balance.when = bms::BalanceWhen::Charging;
  EXPECT_EQ(p.tick(true, false), (V{0, 0}));
  EXPECT_EQ(p.st.status, bms::BalanceStatus::NotAllowed);
  EXPECT_EQ(p.tick(true, true), (V{0, 1}));
  p.cfg.balance.when = bms::BalanceWhen::Rest;
  p.cfg.balance.rest_ms = 3000;
  p.tm.packCurrent_mA = 5000;
  EXPECT_EQ(p.tick(), (V{0, 0}));
  p.tm.packCurrent_mA = 50;  // rest starts now; needs 3 s
  EXPECT_EQ(p.tick(), (V{0, 0}));
  EXPECT_EQ(p.tick(), (V{0, 0}));
  EXPECT_EQ(p.tick(), (V{0, 0}));
  EXPECT_EQ(p.tick(), (V{0, 1}));
  EXPECT_EQ(p.tick(false), (V{0, 0})) << "a fault (not permitted) stops it at once";
}

// A tick on which balancing is not permitted (its own short path in balanceStep): the
// mask and the output clear at once, the status is Disabled, the monitor timer is not
// re-armed, the spread's hysteresis still moves (a spread that fell to the stop delta
// meanwhile ends the episode), and once permitted again the policy decides on that very
// tick, not a decision period later.
TEST(BalancePolicy, ANotPermittedTickClearsAtOnceAndTheNextPermittedTickDecides) {
  Policy p(2);
  p.cfg.balanceTime_s = 10;
  p.cfg.balance.period_ms = 5000;  // decisions 5 s apart while permitted
  p.cells({3700, 3800});
  EXPECT_EQ(p.tick(), (V{0, 1}));
  const uint8_t armed = p.arms;
  EXPECT_EQ(p.tick(false), (V{0, 0}));
  EXPECT_EQ(p.st.status, bms::BalanceStatus::Disabled);
  EXPECT_EQ(p.arms, armed) << "nothing balances: no re-arm";
  EXPECT_TRUE(p.st.active) << "the spread is still 100 mV";
  p.cells({3700, 3705});           // the spread fell below the stop delta while not permitted
  EXPECT_EQ(p.tick(false), (V{0, 0}));
  EXPECT_FALSE(p.st.active) << "the hysteresis moves on a not-permitted tick too";
  EXPECT_EQ(p.arms, armed);
  p.cells({3700, 3800});           // permitted again 3 s after the last decision
  EXPECT_EQ(p.tick(), (V{0, 1})) << "decides at once, not at the 5 s period";
  EXPECT_EQ(p.st.status, bms::BalanceStatus::Balancing);
}

TEST(BalancePolicy, HoldsTheMaskBetweenDecisionsAndReArmsTheTimerEveryHalfPeriod) {
  Policy p(2);
  p.cfg.balanceTime_s = 10;  // re-arm every 5 s
  p.cfg.balance.period_ms = 3000;
  p.cells({3700, 3800});
  EXPECT_EQ(p.tick(), (V{0, 1}));
  p.cells({3800, 3700});  // flipped, but the next decision is due only at 3 s
  EXPECT_EQ(p.tick(), (V{0, 1}));
  EXPECT_EQ(p.tick(), (V{0, 1}));
  EXPECT_EQ(p.tick(), (V{1, 0}));
  std::vector<uint32_t> armedAt;
  uint8_t last = p.arms;
  for (int i = 0; i < 20; ++i) {
    p.tick();
    if (p.arms != last) armedAt.push_back(p.now_ms - 1000), last = p.arms;
  }
  ASSERT_GE(armedAt.size(), 3u);
  for (size_t i = 1; i < armedAt.size(); ++i) EXPECT_EQ(armedAt[i] - armedAt[i - 1], 5000u);
}

// averageReadings = 4: the policy waits for a full block and compares each cell's mean.
// A single reading 12 mV high (noise) on a balanced cell does not start it; a cell whose
// mean is 60 mV above the others does.
TEST(BalancePolicy, DecidesOnTheBlockMeanOfAverageReadings) {
  Policy p(3);
  p.cfg.balance.averageReadings = 4;
  p.cells({3700, 3700, 3700});
  for (int k = 0; k < 3; ++k) EXPECT_EQ(p.tick(), (V{0, 0, 0})) << "no full block yet";
  EXPECT_EQ(p.st.status, bms::BalanceStatus::Disabled);
  p.cells({3700, 3760, 3700});  // one spike: mean 3715, 15 mV < the 50 mV start
  EXPECT_EQ(p.tick(), (V{0, 0, 0}));
  EXPECT_EQ(p.st.status, bms::BalanceStatus::Balanced);
  p.cells({3700, 3760, 3700});
  for (int k = 0; k < 3; ++k) EXPECT_EQ(p.tick(), (V{0, 0, 0})) << "held: the next block is not full";
  EXPECT_EQ(p.tick(), (V{0, 1, 0})) << "mean 3760: 60 mV above";
  p.cfg.balance.averageReadings = 1;  // single readings: the same spike starts it at once
  p.cells({3700, 3760, 3700});
  EXPECT_EQ(p.tick(), (V{0, 1, 0}));
}

// With a read-out slower than the control tick the same reading is seen on many ticks;
// only new read-outs fill the block: 4 read-outs, however many ticks lie between them.
TEST(BalancePolicy, OnlyNewReadOutsFillTheAveragingBlock) {
  Policy p(3);
  p.cfg.balance.averageReadings = 4;
  p.cells({3700, 3760, 3700});
  for (int readout = 0; readout < 3; ++readout) {
    EXPECT_EQ(p.tick(true, false, true), (V{0, 0, 0}));
    for (int k = 0; k < 9; ++k) EXPECT_EQ(p.tick(true, false, false), (V{0, 0, 0})) << "the held reading again";
  }
  EXPECT_EQ(p.st.status, bms::BalanceStatus::Disabled) << "3 read-outs: no block yet, whatever the tick count";
  EXPECT_EQ(p.tick(true, false, true), (V{0, 1, 0})) << "the 4th read-out completes the block";
}

// Two boards of two cells, one board thermistor each (channels 0 and 1): a hot board
// stops its own cells at once and the other board goes on; with every board hot the
// status is the board pause.
TEST(BalancePolicy, EachBoardPausesOnlyItsOwnCells) {
  Policy p(4, 2);
  p.cfg.therm.cell = 0;
  p.cfg.therm.board = 0b11;  // one on each board
  p.cfg.therm.perBoard = 1;
  p.cfg.balance.boardCount = 2;
  p.cfg.balance.cellsPerBoard = 2;
  p.cells({3800, 3700, 3800, 3700});
  p.tm.temperature_dC[0] = 500;
  p.tm.temperature_dC[1] = 500;
  EXPECT_EQ(p.tick(), (V{1, 0, 1, 0}));
  p.tm.temperature_dC[0] = 705;  // board 1 hot
  EXPECT_EQ(p.tick(), (V{0, 0, 1, 0}));
  EXPECT_EQ(p.st.status, bms::BalanceStatus::Balancing);
  p.tm.temperature_dC[1] = 705;  // both hot
  EXPECT_EQ(p.tick(), (V{0, 0, 0, 0}));
  EXPECT_EQ(p.st.status, bms::BalanceStatus::BoardHot);
  p.tm.temperature_dC[1] = 595;  // board 2 resumes below 60 C; board 1 (65 C) is still in its band
  p.tm.temperature_dC[0] = 650;
  EXPECT_EQ(p.tick(), (V{0, 0, 1, 0}));
  p.tm.temperature_dC[1] = 500;
  p.cells({3800, 3700, 3700, 3700});  // only board 1's cell needs it, and board 1 is hot
  EXPECT_EQ(p.tick(), (V{0, 0, 0, 0}));
  EXPECT_EQ(p.st.status, bms::BalanceStatus::BoardHot) << "the cell that needs it sits on a paused board";
}

}  // namespace

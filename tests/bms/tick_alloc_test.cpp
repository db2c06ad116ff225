// A BMS tick allocates nothing: the firmware runs from fixed-size structs. Counts every
// global operator new while the core steps through init, precharge, normal driving, a
// fault, the error state and a reset.
#include <bms/bms_core.hpp>
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "fake_stack.hpp"

namespace {
std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};
}  // namespace

void* operator new(std::size_t n) {
  if (g_counting.load()) ++g_allocations;
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace {

TEST(Core, TickAllocatesNothing) {
  bms::Config cfg = bms_test::config(12, 2);
  cfg.precharge.enabled = true;
  cfg.soc.estimator = bms::SocEstimator::Ekf;  // both estimators run every tick either way
  for (float& r0 : cfg.soc.ekf.r0_mOhm) r0 = 10.0f;
  cfg.soc.ekf.r1_mOhm = 5.0f;
  cfg.soc.ekf.r0ArrheniusK = 2000.0f;  // R0 follows the two thermistors
  for (uint16_t g = 0; g < 12; ++g) cfg.therm.nearest[g] = static_cast<uint8_t>(g / 6);  // channels 0, 1: cells
  bms_test::Rig rig;
  auto& [s, in, out] = rig;
  bms_test::FakeStack st(12, 2);
  // Every container of the test is built before counting starts.
  g_allocations = 0;
  g_counting = true;
  uint32_t t = 0;
  bool sawPrecharge = false, sawNormal = false, sawError = false, backToNormal = false;
  for (int k = 0; k < 3000; ++k, t += cfg.tickPeriod_ms) {
    st.cell_mV[3] = (k > 1500 && k < 1700) ? 2500 : 3700;  // an under-voltage on the way
    in.resetRequest = k == 2000;
    in.busVoltageCode = static_cast<uint16_t>(k > 20 ? 44400 : 0);  // 1 mV codes: 12 x 3.7 V
    in.now_ms = t;
    st.fill(cfg, s);
    bms::step(cfg, s, in, out);
    sawPrecharge = sawPrecharge || out.state == bms::State::Precharge;
    sawNormal = sawNormal || out.state == bms::State::Normal;
    sawError = sawError || out.state == bms::State::Error;
    backToNormal = backToNormal || (sawError && out.state == bms::State::Normal);
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  // …and the run did go through every state on the way.
  EXPECT_TRUE(sawPrecharge);
  EXPECT_TRUE(sawNormal);
  EXPECT_TRUE(sawError);
  EXPECT_TRUE(backToNormal);
}

}  // namespace

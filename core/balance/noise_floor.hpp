// The smallest stop threshold the balancing firmware can honour with its measurement
// noise. With no imbalance at all, N channels read with independent errors of standard
// deviation σ show a spread max − min whose expectation is d2(N)·σ, where
//
//   d2(N) = ∫ [1 − Φ(x)^N − (1 − Φ(x))^N] dx      (the mean range of N standard normals:
//                                                   d2(2) = 1.128, d2(36) = 4.24, d2(110) = 5.08)
//
// σ of one compared reading: the ADC noise and the quantisation (LSB²/12) averaged over
// the firmware's `average_readings` (and the monitor's hardware oversampling, already in
// the ADC noise), plus the per-channel offset and gain errors (drawn once; averaging
// does not remove them; the gain error at v_max_V). A stop threshold below d2(N)·σ means
// the firmware may never see itself balanced and bleeds cells that are already balanced.
#pragma once
#include <string>

#include "core/scenario/scenario.hpp"

namespace packsim {

// Expected range (max − min) of n independent standard normal samples.
double expectedRangeOfNormals(int n);

struct BalanceNoiseFloor {
  int channels = 0;
  double sigma_V = 0.0;           // of one compared reading
  double expected_spread_V = 0.0; // d2(channels)·sigma_V
  int readings_needed = 0;        // smallest average_readings whose spread is below stop_delta (0: none up to the limit)
};

BalanceNoiseFloor balanceNoiseFloor(const Scenario& s);
// The config_warning text when bms.balancing.stop_delta_mV is below the expected noise
// spread, else "".
std::string balanceNoiseWarning(const Scenario& s);

}  // namespace packsim

// The simulator side of the BMS boundary: builds the firmware configuration from the
// scenario (nominal datasheet scaling, SI thresholds -> firmware units) and samples
// the plant's truth into the raw codes the core reads. Noise, quantisation and gain
// errors are added here, never inside bms/.
#pragma once
#include <bms/bms_config.hpp>
#include <bms/bms_hal.hpp>

#include "core/scenario/scenario.hpp"
#include "core/sim/plant.hpp"
#include "models/sensors/adc.hpp"

namespace packsim {

bms::Config makeBmsConfig(const Scenario& s);

// Fills the measurement fields of `in` from the plant signals at one tick.
void sampleSensors(const Scenario& s, const Plant& plant, const PlantSignals& sig, Rng& rng, bms::Inputs& in);

}  // namespace packsim

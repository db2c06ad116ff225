// HardwareSim's balancing hardware, stepped once per tick:
//   - passive: each series group's bleed switch as its board's monitor ICs hold it (the
//     mask the firmware wrote, the part's own timer), into the plant's inputs
//   - active (hardware.active_balancer): the converters' controller deciding from the
//     module voltages the BMS reports over CAN and the bus voltage it reads itself
//     (models/balance/active_balancer.hpp), with the bus precharge
#pragma once
#include <bms/bms_hal.hpp>

#include <vector>

#include "core/scenario/scenario.hpp"
#include "core/sim/hw_status.hpp"
#include "core/sim/plant.hpp"

namespace packsim {

class HwSensors;

class HwBalancing {
 public:
  explicit HwBalancing(const Scenario& s);

  // True when an input of the plant changed.
  bool tick(double t, const HwSensors& sensors, const bms::Outputs& out, const PlantSignals& sig, PlantInputs& pin);
  // The active balancer's safe-state fields of the status.
  void report(HardwareStatus& st) const;

 private:
  const Scenario& s_;
  std::vector<double> moduleV_;  // active balancer: module voltages received from the BMS
  std::vector<uint8_t> on_;      // scratch: each group's switch this tick
  std::vector<double> duty_;     // scratch: the share of the tick it conducts
  ActiveBalancerCommand cmd_;
};

}  // namespace packsim

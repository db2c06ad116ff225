// The thermistor channels as wired, built once by the loader (thermistorTable) and read
// by everything that needs to know where a channel sits: the hardware simulation (the
// node each channel reads), the monitor boards (whose inputs it takes), the firmware
// image (bms::ThermistorMap: cell, FET and board channels, the channel nearest each
// group), the result file (/measured thermistor_groups) and the warnings.
//
//   channels  hardware.thermistors in wiring order (each on a series group's first cell,
//             or on the FETs' thermal node), then each balancing board's board_thermistors
//   nearest   per series group the cell channel nearest it (the lower one on a tie)
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <bms/bms_config.hpp>

#include "models/balance/passive_balancer.hpp"

namespace packsim {

// Where one thermistor of hardware.thermistors sits: on a cell, or on a thermal node of
// its own (the power FETs' board: hardware.discharge_fet / charge_fet `thermal_node`).
struct ThermistorSite {
  int cell = -1;     // 0-based series position; -1 on a node
  std::string node;  // a thermal.nodes name; empty on a cell
  bool onCell() const { return node.empty(); }
};

enum class ThermSite : uint8_t { Cell, Fet, Board };

struct ThermistorChannel {
  ThermSite site = ThermSite::Cell;
  int group = -1;    // Cell: the series group (0-based) on whose first cell it sits; Board: the
                     // board's first group; Fet: -1
  int board = -1;    // Board: the balancing board (0-based)
  std::string node;  // Fet: the thermal node's name
};

struct ThermistorTable {
  std::vector<ThermistorChannel> channels;  // in channel (wiring) order
  std::vector<int> nearest;                 // per series group its nearest Cell channel; -1: none

  int count() const { return static_cast<int>(channels.size()); }
  const ThermistorChannel& operator[](int k) const { return channels[static_cast<size_t>(k)]; }
};

// The table of a pack of `series` groups with these sites and balancing boards.
ThermistorTable thermistorTable(const std::vector<ThermistorSite>& sites, const PassiveBalancerConfig& balancing,
                                int series);

// The firmware's copy (the configuration image): the cell, FET and board channels, the
// board channels per board, every group's nearest channel (bms::kMaxThermistors: none).
void setThermistorMap(bms::ThermistorMap& map, const ThermistorTable& t);

}  // namespace packsim

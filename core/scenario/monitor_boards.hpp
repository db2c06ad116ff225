// How the series string is split over monitor boards (hardware.afe.devices_per_board),
// each board a stack of its own on its own bus, read by its own host MCU; and where
// each thermistor channel is wired.
//
//   boards      devices [b·dpb, (b+1)·dpb) and their cells; one board holds every
//               device when devices_per_board is 0
//   channels    the scenario's thermistor channels keep their numbers (the cell
//               thermistors in `hardware.thermistors` order, then the balancing boards'). One board:
//               the first devices·inputs channels sit on the devices' inputs, the rest on
//               the host MCU's ADC. Several boards: a channel belongs to the board of the
//               cell it sits on (a balancing board's thermistors to that board) and takes
//               the next free input of its devices; a member board has no ADC of its
//               own, so its channels must fit its inputs (board 0, the pack host, puts
//               the rest on its ADC)
//   the host    boardScenario(): the scenario as one board's host is flashed with: its
//               cells, devices and thermistors (local numbers), its balancing board
#pragma once
#include <string>
#include <vector>

#include "core/scenario/scenario.hpp"

namespace packsim {

struct MonitorBoard {
  int index = 0;
  int firstCell = 0, cells = 0;      // series positions
  int firstDevice = 0, devices = 0;  // global device indices
  std::vector<int> afeChannels;      // global thermistor channels on its devices' inputs, in input order
  std::vector<int> mcuChannels;      // global channels on its host MCU's ADC (the pack host only)
};

// The boards of a scenario's hardware. Throws std::invalid_argument naming the board
// whose thermistors do not fit its inputs.
std::vector<MonitorBoard> monitorBoards(const HardwareConfig& hw, int series);

// The scenario as board b's host is flashed with (several boards only).
Scenario boardScenario(const Scenario& s, const MonitorBoard& b);

}  // namespace packsim

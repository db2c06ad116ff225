#include "core/scenario/monitor_boards.hpp"

#include <algorithm>
#include <stdexcept>

namespace packsim {

namespace {

// The board a thermistor channel sits on, by the cell (or balancing board) it measures;
// one on a thermal node (the FETs') belongs to the pack host's board.
int boardOfChannel(const ThermistorChannel& ch, const std::vector<MonitorBoard>& boards) {
  const int cell = std::max(0, ch.group);
  for (const MonitorBoard& b : boards)
    if (cell >= b.firstCell && cell < b.firstCell + b.cells) return b.index;
  return 0;
}

}  // namespace

std::vector<MonitorBoard> monitorBoards(const HardwareConfig& hw, int series) {
  const MonitorConfig& a = hw.afe;
  const int perBoard = a.devices_per_board > 0 ? a.devices_per_board : a.devices;
  std::vector<MonitorBoard> boards;
  for (int d = 0; d < a.devices; d += perBoard) {
    MonitorBoard b;
    b.index = static_cast<int>(boards.size());
    b.firstDevice = d;
    b.devices = std::min(perBoard, a.devices - d);
    b.firstCell = d * a.cells_per_device;
    b.cells = std::min(b.devices * a.cells_per_device, series - b.firstCell);
    boards.push_back(b);
  }
  const int count = hw.thermistors.count();
  const size_t inputs = static_cast<size_t>(a.thermistors_per_device);
  if (boards.size() == 1) {
    MonitorBoard& b = boards.front();
    for (int k = 0; k < count; ++k)
      (b.afeChannels.size() < inputs * static_cast<size_t>(b.devices) ? b.afeChannels : b.mcuChannels).push_back(k);
    return boards;
  }
  for (int k = 0; k < count; ++k) {
    MonitorBoard& b = boards[static_cast<size_t>(boardOfChannel(hw.thermistors[k], boards))];
    if (b.afeChannels.size() < inputs * static_cast<size_t>(b.devices)) {
      b.afeChannels.push_back(k);
    } else if (b.index == 0) {
      b.mcuChannels.push_back(k);
    } else {
      throw std::invalid_argument("monitor board " + std::to_string(b.index + 1) + " (cells " +
                                  std::to_string(b.firstCell + 1) + "-" + std::to_string(b.firstCell + b.cells) +
                                  ") has more thermistors than its " + std::to_string(b.devices) + " devices have inputs (" +
                                  std::to_string(inputs * static_cast<size_t>(b.devices)) +
                                  "); its host has no ADC of its own");
    }
  }
  return boards;
}

Scenario boardScenario(const Scenario& s, const MonitorBoard& b) {
  Scenario bs = s;
  bs.pack.series = b.cells;
  HardwareConfig& hw = bs.hardware;
  hw.afe.devices = b.devices;
  hw.afe.devices_per_board = 0;
  // Its thermistors in wiring order: inputs first, then (the pack host) its ADC; a
  // balancing board's channels stay after the cell ones, as in the global numbering.
  const std::vector<ThermistorSite>& sites = s.hardware.thermistor_sites;
  hw.thermistor_sites.clear();
  int boardTherms = 0;
  for (const std::vector<int>* list : {&b.afeChannels, &b.mcuChannels})
    for (int k : *list) {
      if (k >= static_cast<int>(sites.size())) {
        ++boardTherms;
        continue;
      }
      ThermistorSite site = sites[static_cast<size_t>(k)];
      if (site.onCell()) site.cell -= b.firstCell;
      hw.thermistor_sites.push_back(site);
    }
  if (hw.balancing.present) {
    hw.balancing.boards = 1;
    hw.balancing.cells_per_board = 0;
    hw.balancing.board_thermistors = boardTherms;
  }
  hw.thermistors = thermistorTable(hw.thermistor_sites, hw.balancing, bs.pack.series);
  return bs;
}

}  // namespace packsim

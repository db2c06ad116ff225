#include "core/sim/read_coverage.hpp"

#include <algorithm>
#include <cstdio>

#include "core/scenario/number_ranges.hpp"

#include <bms/packsim_fw.h>

namespace packsim {

namespace {

// 0-based indices as 1-based ranges: "7-24", "3, 5-6".
std::string ranges(std::vector<int> zeroBased) {
  for (int& i : zeroBased) ++i;
  return numberRanges(zeroBased);
}

std::string plural(size_t n, const char* one, const char* many) { return n == 1 ? one : many; }

}  // namespace

UnreadInputs unreadInputs(const MonitorChainPath& chain, const MonitorBoard& board) {
  UnreadInputs u;
  const MonitorChain::ReadCoverage& read = chain.readCoverage();
  const int perDevice = std::max(chain.thermistorsPerDevice(), 0);
  for (int d = 0; d < chain.devices(); ++d) {
    const size_t di = static_cast<size_t>(d);
    const uint32_t cells = di < read.cells.size() ? read.cells[di] : 0u;
    const uint32_t therms = di < read.thermistors.size() ? read.thermistors[di] : 0u;
    const size_t groups = u.groups.size(), channels = u.channels.size();
    for (int c = 0; c < chain.cellsOf(d); ++c)
      if (((cells >> c) & 1u) == 0) u.groups.push_back(board.firstCell + chain.firstCell(d) + c);
    for (int k = 0; k < perDevice; ++k) {
      const size_t j = di * static_cast<size_t>(perDevice) + static_cast<size_t>(k);
      if (j >= board.afeChannels.size()) break;  // an input with no thermistor wired
      if (((therms >> k) & 1u) == 0) u.channels.push_back(board.afeChannels[j]);
    }
    if (u.groups.size() > groups) u.cellDevices.push_back(board.firstDevice + d);
    if (u.channels.size() > channels) u.thermistorDevices.push_back(board.firstDevice + d);
  }
  std::sort(u.channels.begin(), u.channels.end());
  return u;
}

namespace {

// Where thermistor channels sit: "groups 12, 18, 24" when every one sits on a cell, else
// each with its site.
std::string sites(const Scenario& s, const std::vector<int>& channels) {
  bool cells = true;
  for (int k : channels) cells = cells && s.hardware.thermistors[k].site == ThermSite::Cell;
  std::string where = cells ? plural(channels.size(), "group ", "groups ") : "";
  for (size_t i = 0; i < channels.size(); ++i) {
    const ThermistorChannel& ch = s.hardware.thermistors[channels[i]];
    where += i ? ", " : "";
    where += ch.site == ThermSite::Cell    ? (cells ? "" : "group ") + std::to_string(ch.group + 1)
             : ch.site == ThermSite::Board ? "board " + std::to_string(ch.board + 1)
                                           : "FET node " + ch.node;
  }
  return where;
}

}  // namespace

UnreadReport unreadReport(const Scenario& s, const std::vector<MonitorBoard>& boards,
                          const std::vector<const MonitorChainPath*>& chains, double end_s) {
  UnreadReport report;
  std::vector<std::string>& out = report.notes;
  char in[64];
  std::snprintf(in, sizeof in, "%.2f", end_s);
  const std::string part = s.hardware.afe.model;
  for (size_t b = 0; b < boards.size() && b < chains.size(); ++b) {
    const UnreadInputs u = unreadInputs(*chains[b], boards[b]);
    report.groups += static_cast<int>(u.groups.size());
    const std::string board = boards.size() > 1 ? " (board " + std::to_string(b + 1) + ")" : "";
    auto devices = [&](const std::vector<int>& d) {
      return part + " " + plural(d.size(), "device ", "devices ") + ranges(d) + " of " + std::to_string(s.hardware.afe.devices) +
             board;
    };
    if (!u.groups.empty())
      out.push_back(plural(u.groups.size(), "series group ", "series groups ") + ranges(u.groups) + " of " +
                    std::to_string(s.pack.series) + " (on " + devices(u.cellDevices) + "): the firmware never read " +
                    plural(u.groups.size(), "its", "their") + " cell voltage in the run's " + in +
                    " s; the BMS could not see " + plural(u.groups.size(), "it", "them"));
    if (!u.channels.empty())
      out.push_back(plural(u.channels.size(), "thermistor channel ", "thermistor channels ") + ranges(u.channels) +
                    " (at " + sites(s, u.channels) + "; on " + devices(u.thermistorDevices) + "): the firmware never read " +
                    plural(u.channels.size(), "it", "them") + " in the run's " + in + " s");
  }
  return report;
}

std::vector<std::string> unreadMcuThermistors(const Scenario& s, const std::vector<MonitorBoard>& boards,
                                              const std::vector<uint64_t>& read, double end_s) {
  std::vector<std::string> out;
  char in[64];
  std::snprintf(in, sizeof in, "%.2f", end_s);
  for (size_t b = 0; b < boards.size() && b < read.size(); ++b) {
    std::vector<int> never, inputs;
    const std::vector<int>& mcu = boards[b].mcuChannels;
    for (size_t n = 0; n < mcu.size() && n < 64; ++n)
      if (!(read[b] >> n & 1u)) never.push_back(mcu[n]), inputs.push_back(PSFW_ADC_THERMISTOR0 + static_cast<int>(n));
    if (never.empty()) continue;
    const std::string board = boards.size() > 1 ? " of board " + std::to_string(b + 1) : "";
    out.push_back(plural(never.size(), "thermistor channel ", "thermistor channels ") + ranges(never) + " (at " +
                  sites(s, never) + "; on the MCU's own ADC" + board + ", " +
                  plural(inputs.size(), "channel ", "channels ") + numberRanges(inputs) +
                  " from PSFW_ADC_THERMISTOR0 = 16): the firmware never read " + plural(never.size(), "it", "them") +
                  " in the run's " + in + " s");
  }
  return out;
}

}  // namespace packsim

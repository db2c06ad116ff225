// The monitor inputs a firmware never read in a run: series groups whose cell voltage,
// and thermistor channels whose temperature, no read of the monitor ICs delivered from
// the start to the end (each part notes what the MCU read of each device:
// MonitorChain::readCoverage). A firmware configured for fewer cells or devices than the
// pack has -- a user's firmware told `cell_count: 6` on a 24s pack -- runs without an
// error and guards only what it reads: the run says which groups it never saw. A read a
// device did not hear (silent, unaddressed, beyond a broken link) does not count. The
// thermistors on the MCU's own ADC count once the firmware read their channel.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/scenario/monitor_boards.hpp"
#include "core/scenario/scenario.hpp"
#include "core/sim/monitor_chain_path.hpp"

namespace packsim {

struct UnreadInputs {
  std::vector<int> groups;    // series groups (0-based) whose cell voltage was never read
  std::vector<int> channels;  // thermistor channels (0-based, hardware.thermistors order) never read
  std::vector<int> cellDevices, thermistorDevices;  // the devices (0-based, the pack's) with such inputs
};

// One board's chain.
UnreadInputs unreadInputs(const MonitorChainPath& chain, const MonitorBoard& board);

// The run's `monitor_unread` event details (none when everything was read): one for the
// cells and one for the thermistors, per board; and the series groups never read over
// every board. `end_s`: the run's length.
struct UnreadReport {
  std::vector<std::string> notes;
  int groups = 0;
};
UnreadReport unreadReport(const Scenario& s, const std::vector<MonitorBoard>& boards,
                          const std::vector<const MonitorChainPath*>& chains, double end_s);

// The thermistors on the boards' own MCU ADCs the firmware never read: `read[b]` is board
// b's host's mask (bit n: PSFW_ADC_THERMISTOR0 + n, thermistor channel
// boards[b].mcuChannels[n]); one `monitor_unread` detail per board with any.
std::vector<std::string> unreadMcuThermistors(const Scenario& s, const std::vector<MonitorBoard>& boards,
                                              const std::vector<uint64_t>& read, double end_s);

}  // namespace packsim

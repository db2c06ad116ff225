#include "core/scenario/thermistor_table.hpp"

#include <cstdlib>

namespace packsim {

ThermistorTable thermistorTable(const std::vector<ThermistorSite>& sites, const PassiveBalancerConfig& balancing,
                                int series) {
  ThermistorTable t;
  for (const ThermistorSite& s : sites) {
    ThermistorChannel c;
    if (s.onCell()) {
      c.group = s.cell;
    } else {
      c.site = ThermSite::Fet;  // the loader admits only the FETs' node
      c.node = s.node;
    }
    t.channels.push_back(c);
  }
  for (int b = 0; b < balancing.boards; ++b)
    for (int i = 0; i < balancing.board_thermistors; ++i) {
      ThermistorChannel c;
      c.site = ThermSite::Board;
      c.board = b;
      c.group = b * balancing.cells_per_board;
      t.channels.push_back(c);
    }
  t.nearest.assign(static_cast<size_t>(series > 0 ? series : 0), -1);
  for (int g = 0; g < series; ++g) {
    int& best = t.nearest[static_cast<size_t>(g)];
    for (int ch = 0; ch < t.count(); ++ch)
      if (t[ch].site == ThermSite::Cell && (best < 0 || std::abs(t[ch].group - g) < std::abs(t[best].group - g)))
        best = ch;
  }
  return t;
}

void setThermistorMap(bms::ThermistorMap& map, const ThermistorTable& t) {
  map.cell = map.fet = map.board = 0;
  map.perBoard = 0;
  for (int k = 0; k < t.count() && k < bms::kMaxThermistors; ++k) {
    const uint64_t bit = uint64_t{1} << k;
    switch (t[k].site) {
      case ThermSite::Cell: map.cell |= bit; break;
      case ThermSite::Fet: map.fet |= bit; break;
      case ThermSite::Board:
        map.board |= bit;
        if (t[k].board == 0) ++map.perBoard;  // every board has as many
        break;
    }
  }
  for (int g = 0; g < bms::kMaxCells; ++g) {
    const int ch = g < static_cast<int>(t.nearest.size()) ? t.nearest[static_cast<size_t>(g)] : -1;
    map.nearest[g] = static_cast<uint8_t>(ch < 0 || ch >= bms::kMaxThermistors ? bms::kMaxThermistors : ch);
  }
}

}  // namespace packsim

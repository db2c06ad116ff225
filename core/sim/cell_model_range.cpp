#include "core/sim/cell_model_range.hpp"

#include <cstdio>
#include <utility>

#include "core/sim/summary_text.hpp"

namespace packsim {

namespace {

std::string degrees(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g C", v);
  return buf;
}

// The cell's curves tabled over temperature, by their key under pack.cell.
std::vector<std::pair<std::string, const Curve*>> temperatureTables(const CellParams& c) {
  std::vector<std::pair<std::string, const Curve*>> all = {{"ocv_V", &c.ocv_V}, {"r0_ohm", &c.r0_ohm}};
  if (c.has_r0_charge) all.emplace_back("r0_charge_ohm", &c.r0_charge_ohm);
  if (c.has_entropic) all.emplace_back("docv_dT_V_per_K", &c.docv_dT_V_per_K);
  if (c.has_hysteresis) all.emplace_back("hysteresis.max_V", &c.hysteresis_max_V);
  for (size_t k = 0; k < c.rc.size(); ++k) {
    if (!c.rc[k].variable) continue;
    const std::string pair = "rc_pairs[" + std::to_string(k) + "].";
    all.emplace_back(pair + "r_ohm", &c.rc[k].r_curve);
    all.emplace_back(pair + (c.rc[k].by_tau ? "tau_s" : "c_F"), c.rc[k].by_tau ? &c.rc[k].tau_curve : &c.rc[k].c_curve);
  }
  std::vector<std::pair<std::string, const Curve*>> tables;
  for (const auto& e : all)
    if (e.second->kind == Curve::Kind::Table2D && !e.second->temps_C().empty()) tables.push_back(e);
  return tables;
}

// The data bound on one side: the tightest grid end over the tables, and every table
// that ends there.
CellModelRange::Bound dataBound(const std::vector<std::pair<std::string, const Curve*>>& tables, bool above) {
  double edge = above ? 1e300 : -1e300;
  for (const auto& [key, curve] : tables) {
    const double e = above ? curve->temps_C().back() : curve->temps_C().front();
    edge = above ? std::min(edge, e) : std::max(edge, e);
  }
  std::string names;
  int count = 0;
  for (const auto& [key, curve] : tables)
    if ((above ? curve->temps_C().back() : curve->temps_C().front()) == edge)
      names += std::string(count++ ? ", " : "") + "pack.cell." + key;
  CellModelRange::Bound b;
  b.temp_C = edge;
  b.above = above;
  b.what = std::string(above ? "the top" : "the bottom") + " of the temperature data of " + names + ": beyond it " +
           (count > 1 ? "they hold their " : "it holds its ") + degrees(edge) +
           " row, so the cell no longer follows its data";
  return b;
}

}  // namespace

CellModelRange::CellModelRange(const CellParams& cell) {
  const auto tables = temperatureTables(cell);
  if (!tables.empty()) {
    bounds_.push_back(dataBound(tables, false));
    bounds_.push_back(dataBound(tables, true));
  }
  Bound heat;
  heat.temp_C = kSelfHeatingOnset_C;
  heat.what = "where a lithium-ion cell starts to heat itself (the SEI breaks down; separators melt at 130-165 C), "
              "which the equivalent circuit does not model: the cell's temperature and voltage from here on are not "
              "physical";
  bounds_.push_back(heat);
  tighten();
}

void CellModelRange::tighten() {
  lo_C_ = -1e300;
  hi_C_ = 1e300;
  for (const Bound& b : bounds_) {
    if (b.noted) continue;
    if (b.above) hi_C_ = std::min(hi_C_, b.temp_C);
    else lo_C_ = std::max(lo_C_, b.temp_C);
  }
}

void CellModelRange::passed(const std::vector<double>& cell_C, int parallel, const Sink& event) {
  for (Bound& b : bounds_) {
    if (b.noted) continue;
    for (size_t c = 0; c < cell_C.size(); ++c) {
      const double T = cell_C[c];
      if (b.above ? !(T > b.temp_C) : !(T < b.temp_C)) continue;
      char at[48];
      std::snprintf(at, sizeof at, " at %.2f C: ", T);
      event(cellName(static_cast<int>(c) + 1, parallel) + at + (b.above ? "above " : "below ") + degrees(b.temp_C) +
            ", " + b.what);
      b.noted = true;
      break;
    }
  }
  tighten();
}

}  // namespace packsim

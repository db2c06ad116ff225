// Where the cell model stops standing for a real cell, judged on the truth each tick:
// - the span of the cell's temperature data: a table over temperature is held at its
//   first or last row beyond its grid, so past it the curves stop following the cell;
// - the onset of self-heating, kSelfHeatingOnset_C: above it a lithium-ion cell's own
//   exothermic reactions (the SEI breaks down first; separators melt at 130-165 C, then
//   the electrolyte and cathode react) drive its temperature, and no equivalent circuit
//   has them. 80 C is the low end of the onsets accelerating-rate calorimetry gives for
//   NMC, NCA and LFP cells (80-120 C): a safety tool takes the earliest.
// One `cell_model_range` event per bound, the first tick any cell passes it.
#pragma once
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "models/cell/ecm.hpp"

namespace packsim {

constexpr double kSelfHeatingOnset_C = 80.0;

class CellModelRange {
 public:
  using Sink = std::function<void(const std::string& detail)>;
  explicit CellModelRange(const CellParams& cell);

  // The tick's coldest and hottest cell (lo_C, hi_C) of cell_C (storage order, `parallel`
  // cells a group): within every bound, nothing; else an event per bound newly passed.
  template <class F>
  void tick(double lo_C, double hi_C, const std::vector<double>& cell_C, int parallel, F&& event) {
    if (lo_C >= lo_C_ && hi_C <= hi_C_) return;  // the usual tick: no Sink built
    passed(cell_C, parallel, Sink(std::forward<F>(event)));
  }

  struct Bound {
    double temp_C = 0.0;
    bool above = true;  // a maximum (else a minimum)
    std::string what;   // what passing it means, after "above/below <temp> C"
    bool noted = false;
  };
  const std::vector<Bound>& bounds() const { return bounds_; }

 private:
  void passed(const std::vector<double>& cell_C, int parallel, const Sink& event);
  void tighten();  // lo_C_ / hi_C_ from the bounds not yet noted

  std::vector<Bound> bounds_;
  double lo_C_ = -1e300, hi_C_ = 1e300;
};

}  // namespace packsim

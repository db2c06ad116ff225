#include "core/scenario/curve_domain.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace packsim {

namespace {

constexpr double kCheckTemps_C[] = {-40.0, 85.0};  // Arrhenius factor: the ends of the range checked
constexpr int kSocSamples = 2000;

std::vector<double> checkTemps(const Curve& c) {
  if (c.kind == Curve::Kind::Table2D) return c.temps_C();
  if (c.arrhenius_K != 0.0) return {kCheckTemps_C[0], c.ref_temp_C, kCheckTemps_C[1]};
  return {kReferenceTemp_C};
}

// SOC samples: a uniform grid plus every table breakpoint that falls inside [0, 1].
std::vector<double> socSamples(const Curve& c, double q_Ah) {
  std::vector<double> s;
  for (int i = 0; i <= kSocSamples; ++i) s.push_back(static_cast<double>(i) / kSocSamples);
  for (double x : c.xs()) {
    const double soc = c.axis == CurveAxis::Soc ? x : 1.0 - x / q_Ah;
    if (soc > 0.0 && soc < 1.0) s.push_back(soc);
  }
  std::sort(s.begin(), s.end());
  s.erase(std::unique(s.begin(), s.end()), s.end());
  return s;
}

// Whether x lies where a table is held flat (beyond its first or last point).
bool heldFlat(const Curve& c, double x) {
  if (c.xs().empty()) return false;
  return x <= c.xs().front() || x >= c.xs().back();
}

std::string where(const Curve& c, double soc, double q_Ah, double t_C, bool showTemp) {
  char buf[128];
  if (c.axis == CurveAxis::Discharged_Ah)
    std::snprintf(buf, sizeof buf, "SOC %.4g (%.4g Ah discharged)", soc, (1.0 - soc) * q_Ah);
  else
    std::snprintf(buf, sizeof buf, "SOC %.4g", soc);
  std::string w = buf;
  if (showTemp) {
    std::snprintf(buf, sizeof buf, " at %.4g C", t_C);
    w += buf;
  }
  return w;
}

std::string num(double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

std::optional<std::string> curveDomainError(const Curve& c, CurveRule rule, double q_Ah, double max_abs) {
  // A plain number for the OCV is an ideal constant source (test rigs, what-ifs): it
  // has no slope to check. Every polynomial and table must rise.
  if (rule == CurveRule::Ocv && c.isConstant()) {
    if (!(c.coeffs()[0] > 0.0) || !std::isfinite(c.coeffs()[0])) return "must be > 0 V and finite, is " + num(c.coeffs()[0]);
    return std::nullopt;
  }
  const std::vector<double> temps = checkTemps(c);
  const std::vector<double> socs = socSamples(c, q_Ah);
  const bool showTemp = c.dependsOnTemperature();
  for (double t_C : temps) {
    double prev = 0.0, prevSoc = 0.0;
    for (size_t i = 0; i < socs.size(); ++i) {
      const double soc = socs[i];
      const double y = c.eval(soc, q_Ah, t_C);
      // Where the sample is, in words: formed only for an error (the loader checks every
      // curve of every cell at hundreds of samples; formatting each cost more than the check).
      auto at = [&] { return where(c, soc, q_Ah, t_C, showTemp); };
      if (!std::isfinite(y)) return "is not finite (" + num(y) + ") at " + at();
      if (std::fabs(y) > max_abs && (c.arrhenius_K == 0.0 || t_C == c.ref_temp_C))
        return "reaches " + num(y) + " at " + at() + "; allowed [-" + num(max_abs) + ", " + num(max_abs) + "]";
      switch (rule) {
        case CurveRule::Positive:
        case CurveRule::NonNegative: {
          auto bad = [&](double v) { return rule == CurveRule::Positive ? !(v > 0.0) : !(v >= 0.0); };
          if (!bad(y)) break;
          // Report the whole failing stretch: from this SOC up to the last failing sample.
          size_t j = i;
          while (j + 1 < socs.size() && bad(c.eval(socs[j + 1], q_Ah, t_C))) ++j;
          return std::string("must be ") + (rule == CurveRule::Positive ? "> 0" : ">= 0") + " over SOC 0..1 but is " +
                 num(y) + " at " + at() + (j > i ? " (and up to " + where(c, socs[j], q_Ah, t_C, false) + ")" : "");
        }
        case CurveRule::Ocv:
          if (!(y > 0.0)) return "must be > 0 V over SOC 0..1 but is " + num(y) + " V at " + at();
          if (i > 0) {
            const bool flat = heldFlat(c, c.axisValue(soc, q_Ah)) && heldFlat(c, c.axisValue(prevSoc, q_Ah));
            if (y < prev || (y == prev && !flat))
              return std::string("must rise strictly with SOC but ") + (y < prev ? "falls" : "stays flat") + " from " +
                     num(prev) + " V at " + where(c, prevSoc, q_Ah, t_C, showTemp) + " to " + num(y) + " V at " + at();
          }
          break;
        case CurveRule::Finite:
          break;
      }
      prev = y;
      prevSoc = soc;
    }
  }
  return std::nullopt;
}

}  // namespace packsim

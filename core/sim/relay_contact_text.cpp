#include "core/sim/relay_contact_text.hpp"

#include "core/text_fmt.hpp"

namespace packsim {

// The relay contact as the events record it: open until a relay_contact event says otherwise.
bool contactClosedBefore(const RunResult& r, double t) {
  bool closed = false;
  for (const Event& e : r.events)
    if (e.kind == "relay_contact" && e.time_s < t - 1e-9) closed = e.detail == "closed";
  return closed;
}

// What the relay contact did from time t on (a command, a trip, the FAULT line): from
// the relay_contact events, never from what was commanded.
std::string contactFrom(const RunResult& r, double t) {
  const Event* lastBefore = nullptr;  // the contact's state before t: its last event then
  const Event* openedFrom = nullptr;  // the first opening at or after t
  for (const Event& e : r.events) {
    if (e.kind != "relay_contact") continue;
    if (e.time_s < t - 1e-9) lastBefore = &e;
    else if (!openedFrom && e.detail == "opened") openedFrom = &e;
  }
  // A reset (or the firmware itself) may close it again after: the load then ran on,
  // which "opened at" alone would hide.
  auto closedAgain = [&](double from_s, const char* word) {
    for (const Event& e : r.events)
      if (e.kind == "relay_contact" && e.time_s > from_s + 1e-9 && e.detail == "closed")
        return std::string("; ") + word + " at " + fmt("%.2f", e.time_s) + " s";
    return std::string();
  };
  if (!lastBefore) return "the relay contact was open (never closed before)" + closedAgain(t - 1e-9, "it closed");
  if (lastBefore->detail == "opened")
    return "the relay contact had opened at " + fmt("%.2f", lastBefore->time_s) + " s" + closedAgain(t - 1e-9, "closed again");
  if (openedFrom)
    return "the relay contact opened at " + fmt("%.2f", openedFrom->time_s) + " s" + closedAgain(openedFrom->time_s, "closed again");
  return "the relay contact stayed closed to the end";
}

bool contactOpenFrom(const RunResult& r, double t) {
  if (!contactClosedBefore(r, t)) return true;
  for (const Event& e : r.events)
    if (e.kind == "relay_contact" && e.time_s >= t - 1e-9 && e.detail == "opened") return true;
  return false;
}

}  // namespace packsim

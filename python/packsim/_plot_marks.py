"""What every time plot of packsim.plot shares: the run's trips and fault injections as
vertical lines with labels that do not overlap, and the BMS protection limits as
horizontal lines."""
from __future__ import annotations

import numpy as np

from .result import Result

# Event kinds marked on every time plot, with their colour: injections (what the
# scenario did) and trips (what the BMS or the hardware did about it).
MARKED = {"fault_injected": "C4", "fault_latched": "C3", "relay_contact": "k", "fuse": "C1",
          "monitor_fault_line": "C5"}
LANES = 4  # label rows under the top of the axes


def marked_events(r: Result) -> list[dict]:
    """The events marked on the plots: injections, latched faults, contact/fuse/FAULT
    line moves (relay_contact only when it opened)."""
    out = []
    for ev in r.events:
        if ev["kind"] not in MARKED:
            continue
        if ev["kind"] == "relay_contact" and "open" not in str(ev["detail"]):
            continue
        out.append(ev)
    return out


LABEL_GID = "packsim-event-label"


def mark_events(ax, r: Result, scale: float, *, labels: bool = True) -> list:
    """Draw the marked events on ax (time axis in s / scale) and label them without
    overlap: call it last, when everything else of the figure is drawn. Labels go into
    the first of LANES rows under the top of the axes where they overlap no other label
    (measured with the figure's renderer after its layout is settled); an event with no
    free row keeps its line without a label. Returns the label Texts."""
    evs = sorted(marked_events(r), key=lambda e: e["time_s"])
    for ev in evs:
        ax.axvline(ev["time_s"] / scale, color=MARKED[ev["kind"]], lw=0.8, ls="--", alpha=0.7)
    if not labels or not evs:
        return []
    fig = ax.figure
    fig.draw_without_rendering()  # the layout, so that label sizes are the final ones
    renderer = fig._get_renderer()
    frame = ax.get_window_extent(renderer)
    placed = [t.get_window_extent(renderer) for t in ax.texts if t.get_gid() == LABEL_GID]
    texts = []
    for ev in evs:
        x = ev["time_s"] / scale
        text = f"{ev['kind'].replace('_', ' ')}: {ev['detail']}"[:40]
        # right of the line in the first free row, else left of it
        for side, lane in [(s, k) for s in ("left", "right") for k in range(LANES)]:
            t = ax.annotate(text, (x, 1.0 - 0.1 * lane), xycoords=("data", "axes fraction"),
                            xytext=(2 if side == "left" else -2, -2), textcoords="offset points", va="top", ha=side,
                            fontsize=6.5, color=MARKED[ev["kind"]], gid=LABEL_GID,
                            bbox=dict(boxstyle="square,pad=0.1", fc="white", ec="none", alpha=0.8))
            t.set_in_layout(False)
            bb = t.get_window_extent(renderer)
            inside = bb.x0 >= frame.x0 - 1 and bb.x1 <= frame.x1 + 1 and bb.y0 >= frame.y0 - 1
            if inside and not any(bb.overlaps(p) for p in placed):
                placed.append(bb)
                texts.append(t)
                break
            t.remove()
    return texts


def limit(r: Result, name: str) -> float | None:
    """A protection threshold of /bms (limit_<name>), None when that protection is off."""
    v = r.attrs.get("bms", {}).get(f"limit_{name}")
    return None if v is None else float(v)


def draw_limits(ax, r: Result, names: list[tuple[str, str, float]]) -> None:
    """Horizontal lines at the named limits: (limit name, label, sign). They are named in
    the legend (call before the legend is made), never as text on the curves."""
    for name, label, sign in names:
        v = limit(r, name)
        if v is None:
            continue
        ax.axhline(sign * v, color="C3", lw=1.0, ls=":", alpha=0.9, label=f"{label} limit {sign * v:g}")

"""The plots tell what happened: the BMS timeline draws what the hardware did next to
what the firmware commanded (the hung-MCU scenario's relay opened at ~576 s although the
firmware never commanded it open), injections and trips are marked on every time plot
with labels that do not overlap, limits are drawn, extreme and faulted cells stand out."""
from __future__ import annotations

import itertools

import numpy as np
import pytest

import packsim
from packsim import plot
from packsim._plot_marks import LABEL_GID


@pytest.fixture(scope="module")
def host_dead():
    return packsim.run("a_host_dead_unsupervised")  # the IC's link supervision off


def _bars(fig, label):
    """[(start, end)] of the bars drawn in the timeline row labelled `label`."""
    ax = fig.axes[1]
    for coll in ax.collections:
        if coll.get_label() == label:
            out = []
            for path in coll.get_paths():
                xs = path.vertices[:, 0]
                out.append((float(xs.min()), float(xs.max())))
            return sorted(out)
    raise AssertionError(f"no timeline row {label!r}; rows: {[c.get_label() for c in ax.collections]}")


def test_timeline_shows_the_relay_contact_open_while_commanded_closed(host_dead):
    # The MCU hangs at 300 s with the relay command held; the monitor's FAULT line opens
    # the relay when cell 5's thermistor passes the comparator's 65 C, some 230-330 s after
    # the heating starts at 320 s (the scenario's design; the events table records the
    # moment, about 576 s).
    opened = [e["time_s"] for e in host_dead.events if e["kind"] == "relay_contact" and e["detail"] == "opened"]
    assert len(opened) == 1 and 320.0 + 230.0 < opened[0] < 320.0 + 330.0
    fig = plot.bms_timeline(host_dead)
    _, _, scale = plot._time(host_dead)
    end = host_dead.time_s[-1] / scale
    contact = _bars(fig, "relay: contact (hardware)")
    commanded = _bars(fig, "relay: commanded")
    dt = np.median(np.diff(host_dead.time_s)) / scale
    assert len(contact) == 1 and abs(contact[0][1] - opened[0] / scale) <= dt
    assert commanded[-1][1] >= end - dt  # the firmware still commands it closed
    fault_line = _bars(fig, "monitor fault line (hardware)")
    assert abs(fault_line[0][0] - opened[0] / scale) <= dt


def test_every_time_plot_marks_the_injections_and_trip_with_non_overlapping_labels(host_dead):
    injected = [e["time_s"] for e in host_dead.events if e["kind"] == "fault_injected"]
    assert len(injected) == 2
    figs = [plot.cells(host_dead, "voltage"), plot.cells(host_dead, "temperature"), plot.current_soc(host_dead),
            plot.bms_timeline(host_dead), plot.measured_vs_truth(host_dead)]
    for fig in figs:
        fig.canvas.draw()
        renderer = fig._get_renderer()
        # every injection has a vertical line in the first axes
        ax = fig.axes[0]
        scale = plot._time(host_dead)[2]
        xs = [line.get_xdata()[0] for line in ax.lines if line.get_linestyle() == "--"]
        for t in injected:
            assert any(abs(x - t / scale) < 1e-9 for x in xs), (fig.axes[0].get_title(), t)
        labels = [t for a in fig.axes for t in a.texts if t.get_gid() == LABEL_GID]
        assert labels, fig.axes[0].get_title()
        boxes = [t.get_window_extent(renderer) for t in labels]
        for a, b in itertools.combinations(boxes, 2):
            assert not a.overlaps(b), fig.axes[0].get_title()


def test_limits_are_drawn_at_the_scenario_thresholds(simple_yaml):
    r = packsim.run(simple_yaml, {"bms.protections.cell_undervoltage.threshold_V": 3.8})
    assert r.attrs["bms"]["limit_cell_undervoltage_V"] == 3.8
    fig = plot.cells(r, "voltage")
    ys = [line.get_ydata()[0] for line in fig.axes[0].lines if line.get_linestyle() == ":"]
    assert 3.8 in ys and 4.25 in ys  # and the default over-voltage limit
    assert "under-voltage limit 3.8" in fig.axes[0].get_legend_handles_labels()[1]


def test_extreme_and_faulted_cells_stand_out():
    r = packsim.run("a_hot_cell")
    fig = plot.cells(r, "temperature")
    labels = fig.axes[0].get_legend_handles_labels()[1]
    hottest = int(np.argmax(r["truth/cell_temp_C"].max(axis=0))) + 1
    assert hottest == 5  # the scenario heats cell 5
    assert any(lbl.startswith("cell 5 (fault injected") and "max" in lbl for lbl in labels), labels
    assert any(lbl.endswith("(min)") for lbl in labels) and "other cells" in labels


def test_a_parallel_packs_marked_cells_are_named_with_their_group():
    # The summary and the events name a cell of a parallel pack with its group, "cell 74
    # (group 19)"; the plot said "cell 21 (min)" for a 12s2p pack, leaving the reader to
    # work out which series group -- the unit the BMS measures -- it sits in.
    r = packsim.run("eco_marathon_12s", {"pack.parallel": 2, "load.laps": 1})
    v = r["truth/cell_voltage_V"]
    lo, hi = int(np.argmin(v.min(axis=0))), int(np.argmax(v.max(axis=0)))
    labels = plot.cells(r, "voltage").axes[0].get_legend_handles_labels()[1]
    assert f"cell {lo + 1} (group {lo // 2 + 1}, min)" in labels, labels
    assert f"cell {hi + 1} (group {hi // 2 + 1}, max)" in labels, labels
    heat = plot.cells(r, "voltage", line_limit=4)  # the heat-map's annotations
    assert f"cell {lo + 1} (group {lo // 2 + 1}, min)" in [t.get_text() for t in heat.axes[0].texts]

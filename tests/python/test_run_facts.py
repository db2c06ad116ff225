"""The lines a run page says first (packsim.run_facts), each against a result built so
that a wrong reading of the file would say something else: the trip from the events
(not the summary), the margin from the data with its sign, place and time, a parallel
pack's cell named with its group, an open thermistor ignored, charge current negative,
a protection switched off absent, and the energy account from the summary."""
from __future__ import annotations

import numpy as np
import pytest

from packsim import run_facts
from packsim.result import Result, _EVENT_DTYPE
from packsim.run_figure import display_indices, group_deviation

N = 11  # samples, 1 s apart
SERIES, PARALLEL = 2, 2


def _result(events=(), bms_limits=None, summary=None, **override) -> Result:
    t = np.arange(N, dtype=float)
    v = np.full((N, SERIES * PARALLEL), 3.7)
    temp = np.full((N, SERIES * PARALLEL), 25.0)
    cur = np.full(N, 2.0)
    mv = np.full((N, SERIES), 3700, dtype=np.uint16)
    dc = np.full((N, 2), 250, dtype=np.int16)
    ma = np.full(N, 2000, dtype=np.int32)
    ds = {"time_s": t, "truth/cell_voltage_V": v, "truth/cell_temp_C": temp, "truth/pack_current_A": cur,
          "measured/cell_voltage_mV": mv, "measured/temperature_dC": dc, "measured/current_mA": ma}
    ds.update(override)
    ev = np.array([(float(a), k, d) for a, k, d in events], dtype=_EVENT_DTYPE)
    ds["events"] = ev
    limits = {"limit_cell_overvoltage_V": 4.2, "limit_cell_undervoltage_V": 3.0, "limit_overtemperature_C": 60.0,
              "limit_undertemperature_C": -20.0, "limit_overcurrent_discharge_A": 30.0,
              "limit_overcurrent_charge_A": 5.0} if bms_limits is None else bms_limits
    attrs = {"": {"scenario_name": "made"}, "bms": dict(limits), "summary": dict(summary or {}),
             "measured": {"thermistor_groups": "1,2"}}
    return Result(ds, attrs)


def _margin(r: Result, limit: str) -> run_facts.Margin:
    return next(m for m in run_facts.margins(r) if m.channel.limit == limit)


def test_no_latched_fault_is_no_trip_even_if_the_summary_says_otherwise():
    r = _result(summary={"tripped": 1, "trip_reason": "overtemperature", "trip_time_s": 3.0},
                events=[(0.0, "bms_state", "init"), (4.0, "fault_active", "overtemperature: 61 C")])
    v = run_facts.verdict(r)
    assert not v.tripped and v.headline.startswith("NO TRIP") and v.trip_time_s is None


def test_the_first_latched_fault_is_the_trip_with_the_reading_at_that_sample():
    v = np.full((N, 4), 3.7)
    v[6, 2] = 2.95  # truth: cell 3 below 3.0 V at t = 6 s
    mv = np.full((N, SERIES), 3700, dtype=np.uint16)
    mv[6, 1] = 2980  # the BMS read group 2 at 2.980 V
    r = _result(events=[(6.0, "fault_active", "cell_undervoltage: min 2.980 V < 3.000 V"),
                        (6.0, "fault_latched", "cell_undervoltage"), (6.0, "relay_contact", "opened"),
                        (8.0, "fault_latched", "overtemperature"), (9.0, "relay_contact", "closed")],
                **{"truth/cell_voltage_V": v, "measured/cell_voltage_mV": mv})
    out = run_facts.verdict(r)
    assert out.tripped and out.protection == "cell_undervoltage" and out.trip_time_s == 6.0
    assert out.headline == "TRIPPED at 6.00 s: cell_undervoltage"
    text = "\n".join(out.lines)
    assert "the BMS's reason: cell_undervoltage: min 2.980 V < 3.000 V" in text
    assert "measured lowest cell voltage 2.98 V" in text and "the truth was 2.95 V" in text
    assert "then latched at 8.00 s: overtemperature" in text
    assert "6.00 s: relay contact opened" in text and "closed" not in text  # only what opened


def test_unread_groups_a_relay_that_never_closed_and_a_profile_end_are_in_the_verdict():
    note = "series groups 7-12 of 12 (on bq76pl536a device 2 of 2): the firmware never read their cell voltage"
    r = _result(summary={"relay_closed": 0, "charge_delivered_Ah": 0.0},
                events=[(10.0, "monitor_unread", note), (4.0, "load_end", "the profile's 1 lap of 4 s ended")])
    text = "\n".join(run_facts.verdict(r).lines)
    assert f"10.00 s: monitor unread: {note}" in text
    assert "4.00 s: load end: the profile's 1 lap of 4 s ended" in text
    assert "the relay never closed in the run: 0.000 Ah delivered" in text
    closed = _result(summary={"relay_closed": 1}, events=[(0.2, "relay_contact", "closed")])
    assert not any("never closed" in line for line in run_facts.verdict(closed).lines)


def test_a_cell_beyond_the_cell_model_is_in_the_verdict():
    note = "cell 5 at 80.00 C: above 80 C, where a lithium-ion cell starts to heat itself"
    text = "\n".join(run_facts.verdict(_result(events=[(763.5, "cell_model_range", note)])).lines)
    assert f"763.50 s: cell model range: {note}" in text
    assert not any("cell model range" in line for line in run_facts.verdict(_result()).lines)


def test_a_false_fault_is_in_the_verdict():
    note = ("cell_overvoltage at 121.50 s: no cell's true voltage came within 10.0 mV of the 4.250 V limit in the "
            "0.80 s before (the highest at the fault 4.036 V, cell 73 (group 19)): the BMS acted on a reading, not on "
            "the cells")
    text = "\n".join(run_facts.verdict(_result(events=[(121.5, "false_fault", note)])).lines)
    assert f"121.50 s: false fault: {note}" in text


def test_a_charge_the_bms_ended_is_in_the_verdict_with_the_truth_then():
    note = ("disabled by the BMS: the highest cell, cell 5 (group 3), at 4.149 V under 4.00 A of charge, "
            "mean SOC 0.728 (truth)")
    r = _result(events=[(0.4, "charger", "enabled by the BMS"), (667.2, "charger", note)])
    lines = run_facts.verdict(r).lines
    assert f"667.20 s: charger {note}" in lines
    assert not any("enabled by the BMS" in line for line in lines)
    assert not any("charger" in line for line in run_facts.verdict(_result()).lines)


def test_a_power_load_the_pack_could_not_give_is_in_the_verdict():
    note = "10.00-15.00 s: the pack gave less power than the load asked (at most 2101 W while up to 9000 W was asked)"
    text = "\n".join(run_facts.verdict(_result(events=[(15.0, "load_limited", note)])).lines)
    assert f"15.00 s: load limited: {note}" in text


def test_a_scripted_fault_without_effect_is_in_the_verdict():
    note = ("welded_relay (line 12, active from 10.000 s to the end): the relay contact was open the whole time: "
            "a weld holds a closed contact, and the relay never closed while welded")
    text = "\n".join(run_facts.verdict(_result(events=[(60.13, "fault_no_effect", note)])).lines)
    assert f"60.13 s: fault no effect: {note}" in text


def test_margin_sign_place_time_and_time_past_the_limit():
    v = np.full((N, 4), 3.7)
    v[7, 2] = 4.25  # cell 3 = group 2 in a 2s2p pack, past 4.2 V for one sample
    v[8, 2] = 4.21
    r = _result(**{"truth/cell_voltage_V": v})
    m = _margin(r, "cell_overvoltage_V")
    assert m.limit == 4.2
    assert m.truth.value == 4.25 and m.truth.margin == pytest.approx(-0.05)
    assert m.truth.time_s == 7.0 and m.truth.where == "cell 3 (group 2)"
    assert m.truth.past_s == pytest.approx(2.0)
    assert m.measured.margin == pytest.approx(0.5) and m.measured.past_s == 0.0  # the BMS never saw it
    assert m.tripped_s is None
    low = _margin(r, "cell_undervoltage_V")
    assert low.truth.value == 3.7 and low.truth.margin == pytest.approx(0.7)


def test_an_open_thermistor_is_no_reading_and_the_thermistor_is_named_with_its_group():
    dc = np.full((N, 2), 250, dtype=np.int16)
    dc[3:, 0] = -32768  # open from 3 s
    dc[5, 1] = 300
    r = _result(**{"measured/temperature_dC": dc})
    cold = _margin(r, "undertemperature_C")
    assert cold.measured.value == 25.0  # not -3276.8
    hot = _margin(r, "overtemperature_C")
    assert hot.measured.value == 30.0 and hot.measured.where == "thermistor 2 (group 2)"
    assert hot.measured.time_s == 5.0


def test_charge_current_is_negative_and_a_switched_off_protection_has_no_row():
    cur = np.full(N, 2.0)
    cur[4] = -6.0
    r = _result(bms_limits={"limit_overcurrent_charge_A": 5.0}, **{"truth/pack_current_A": cur})
    rows = run_facts.margins(r)
    assert [m.channel.limit for m in rows] == ["overcurrent_charge_A"]
    assert rows[0].limit == -5.0 and rows[0].truth.value == -6.0 and rows[0].truth.margin == pytest.approx(-1.0)
    assert run_facts.margins(_result(bms_limits={})) == []


def test_latched_time_per_protection_comes_from_the_events():
    r = _result(events=[(3.0, "fault_latched", "overtemperature"), (5.0, "fault_latched", "overtemperature")])
    assert _margin(r, "overtemperature_C").tripped_s == 3.0
    assert _margin(r, "cell_overvoltage_V").tripped_s is None


def test_energy_account_is_the_summary_and_only_what_it_holds():
    r = _result(summary={"energy_delivered_Wh": 12.5, "energy_stranded_Wh": 0.25})
    rows = run_facts.energy(r)
    assert [(label, wh) for label, wh, _ in rows] == [("delivered at the terminals, net", 12.5),
                                                      ("stranded by imbalance", 0.25)]


def test_group_deviation_is_from_the_mean_of_the_groups_of_parallel_cells():
    soc = np.tile(np.array([0.5, 0.7, 0.8, 0.8]), (N, 1))  # groups: 0.6 and 0.8, mean 0.7
    r = _result(**{"truth/cell_soc": soc})
    d = group_deviation(r, "truth/cell_soc")
    assert d.shape == (N, SERIES)
    np.testing.assert_allclose(d[0], [-0.1, 0.1])


def test_display_decimation_keeps_every_spike():
    y = np.zeros(200_000)
    y[123_457] = 5.0
    y[7] = -3.0
    idx = display_indices(y, 1000)
    assert idx.size <= 2 * 1000 + 2
    assert 123_457 in idx and 7 in idx and idx[0] == 0 and idx[-1] == y.size - 1
    assert np.array_equal(display_indices(np.arange(50.0), 1000), np.arange(50))


def test_unseen_limits_of_one_parallel_group_are_one_verdict_line():
    # A 4p group's cells share its voltage: their four identical limit_unseen events (but
    # the cell number) are one line naming cells 37-40; another group's, another time's
    # and a temperature event (its own cell) stay lines of their own, in the run's order.
    def uv(cell, group, t_from="1700.16"):
        return (f"cell_undervoltage: cell {cell} (group {group}) more than 0.55 mV below the 3.000 V limit "
                f"from {t_from} s, unseen by the BMS for 4.65 s (min 2.9981 V)")
    events = [(1704.81, "limit_unseen", uv(c, 10)) for c in (37, 38, 39, 40)]
    events += [(1704.81, "limit_unseen", uv(45, 12)),
               (1710.0, "limit_unseen", uv(37, 10, "1705.00")),
               (1720.0, "limit_unseen", "overtemperature: cell 5 (group 2) more than 0.05 C above the 60 C limit "
                                        "from 1700.00 s, unseen by the BMS to the end of the run (20.00 s) (max 61.0 C)"),
               (1720.0, "limit_unseen", "overtemperature: cell 7 (group 2) more than 0.05 C above the 60 C limit "
                                        "from 1700.00 s, unseen by the BMS to the end of the run (20.00 s) (max 62.0 C)")]
    lines = [line for line in run_facts.verdict(_result(events=events)).lines if "limit unseen" in line]
    assert lines == [
        "1704.81 s: limit unseen: " + uv(37, 10).replace("cell 37 (group 10)", "cells 37-40 (group 10)"),
        "1704.81 s: limit unseen: " + uv(45, 12),
        "1710.00 s: limit unseen: " + uv(37, 10, "1705.00"),
        "1720.00 s: limit unseen: " + events[-2][2],
        "1720.00 s: limit unseen: " + events[-1][2],
    ]


def test_a_trip_whose_relay_contact_never_opened_says_so():
    """A welded relay: the trip latched but the contact stayed closed and the load went on
    drawing. The page listed only what opened, so it read as an isolated pack; the
    summary's TRIP line said "the relay contact stayed closed to the end"."""
    cur = np.full(N, 9.0)
    events = [(0.02, "relay_contact", "closed"), (2.0, "fault_injected", "welded_relay"),
              (2.21, "fault_active", "overcurrent_discharge: current 33.978 A > 30.000 A for 200 ms"),
              (2.21, "fault_latched", "overcurrent_discharge"), (2.21, "relay", "open")]
    text = "\n".join(run_facts.verdict(_result(events=events, **{"truth/pack_current_A": cur})).lines)
    assert ("the relay contact stayed closed after the trip, to the run's end at 10.00 s "
            "(welded_relay injected at 2.00 s); the pack current at the end: 9 A") in text
    opened = events + [(2.22, "relay_contact", "opened")]
    assert not any("stayed closed" in line for line in run_facts.verdict(_result(events=opened)).lines)
    never_closed = [e for e in events if e[1] != "relay_contact"]  # open before the trip: nothing stayed closed
    assert not any("stayed closed" in line for line in run_facts.verdict(_result(events=never_closed)).lines)


def test_a_trip_between_two_samples_names_the_sample_it_quotes():
    """Samples 1 s apart, an over-current injected at 5.005 s trips at 5.21 s: the sample
    at 5 s predates it, and was quoted as "at the trip the BMS measured highest pack
    current 9.998 A" against a 40 A limit."""
    events = [(5.005, "fault_injected", "overcurrent +35 A"),
              (5.21, "fault_active", "overcurrent_discharge: current 45.002 A > 30.000 A for 200 ms"),
              (5.21, "fault_latched", "overcurrent_discharge"), (5.22, "relay_contact", "opened")]
    text = "\n".join(run_facts.verdict(_result(events=events)).lines)
    assert "at the trip" not in text
    assert ("at the last recorded sample before the trip (5.00 s, 0.21 s earlier) the BMS measured highest pack "
            "current 2 A; the truth was 2 A; limit 30 A") in text


def test_a_hung_host_is_in_the_verdict():
    """NO TRIP from a pack host that hung at 10 s says nothing of the rest of the run."""
    events = [(10.0, "fault_injected", "host_dead"), (12.0, "fault_injected", "host_dead board 2")]
    text = "\n".join(run_facts.verdict(_result(events=events)).lines)
    assert "10.00 s: the pack host's MCU hung (host_dead): no BMS decision after it while it lasted" in text
    assert "12.00 s" not in text  # a monitor board's MCU: the host's comm loss says it

"""The protection table's names and texts reach the result exactly as before the table
existed (issue 15): the fault bit names of /bms, the fault events, the latched bits and
the trip reason of a short run, against the strings the hand-written code produced."""
from __future__ import annotations

import numpy as np

import packsim

# /bms fault_bits as written before the table: bit i is the i-th name.
FAULT_BITS = ["cell_overvoltage", "cell_undervoltage", "overcurrent_discharge", "overcurrent_charge",
              "overtemperature", "overtemperature_charge", "undertemperature", "undertemperature_charge",
              "board_overtemperature", "comm_loss", "cell_sum_plausibility", "thermistor_fault",
              "current_sensor_fault", "estop", "monitor_fault", "relay_welded", "precharge_failed",
              "temperature_warning", "cell_imbalance",
              "fet_overtemperature"]  # appended later (a thermistor on the FETs): the others keep their bits

# The info and warning tiers switched on; a 20 mV channel offset makes the spread, the
# 25 °C pack is above the 20 °C warning, the E-switch trips the pack.
EXTRA = """\
bms:
  protections:
    cell_imbalance: {enabled: true, threshold_V: 0.005, delay_ms: 300}
    temperature_warning: {enabled: true, threshold_C: 20, delay_ms: 2000}
faults:
  - {kind: channel_offset, group: 2, offset_mV: 20, at_s: 5}
  - {kind: estop, switch: external, at_s: 12}
"""


def test_fault_names_events_and_bits_as_before(simple_yaml):
    r = packsim.run(simple_yaml.replace("run: {duration_s: 600}", "run: {duration_s: 30}") + EXTRA)
    assert r.fault_names == FAULT_BITS
    faults = [(e["time_s"], e["kind"], e["detail"]) for e in r.events if e["kind"].startswith("fault_")
              and e["kind"] != "fault_injected"]
    # The warning's 2 s debounce starts at power-up, once the firmware has addressed and
    # read its monitor stack over the bus (a few ms): it fires at the 2.01 s tick.
    faults = [(round(t, 6), k, d) for t, k, d in faults]
    assert faults == [
        (2.01, "fault_active", "temperature_warning: max temperature 25.000 C > 20.000 C for 2000 ms"),
        # 20 mV of offset plus the conversion noise of the part's own draw (22 mV with the
        # frame-level monitor model of earlier versions)
        (5.3, "fault_active", "cell_imbalance: cell spread 21 mV > 5 mV for 300 ms"),
        (12.0, "fault_active", "estop: E-switch pulled"),
        (12.0, "fault_latched", "estop"),
    ]
    assert r.summary["trip_reason"] == "estop"
    latched = np.asarray(r["bms/fault_latched"])
    active = np.asarray(r["bms/fault_active"])
    assert latched[-1] == 1 << FAULT_BITS.index("estop")
    expected_active = sum(1 << FAULT_BITS.index(n) for n in ("estop", "temperature_warning", "cell_imbalance"))
    assert active[-1] == expected_active

"""packsim.show and `packsim show`: every value with its origin, the warnings, and a YAML
form that runs to the same results."""
from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np

import packsim

USER_PACK = """name: user_pack
pack: {series: 24, parallel: 4, initial_soc: 0.9, cell: {preset: ncr18650_3p1Ah}}
load: {current_A: 60}
run: {duration_s: 1}
"""


def test_show_returns_values_with_origins_and_warnings(simple_yaml):
    shown = packsim.show(simple_yaml, {"pack.cell.capacity_Ah": 3.0})
    values = shown["values"]
    assert values["pack.cell.capacity_Ah"] == {"value": "3.0", "origin": "--set pack.cell.capacity_Ah=3.0",
                                               "stated": True}
    assert values["pack.parallel"]["origin"] == "default"
    assert values["pack.series"]["origin"].startswith("<string>:")
    assert isinstance(shown["warnings"], list)


def test_user_pack_sensor_range_is_derived_and_said(tmp_path):
    shown = packsim.show(USER_PACK, base_dir=str(tmp_path))
    gain = shown["values"]["hardware.current_sense.amp_gain"]
    assert gain["origin"] == "default (a +/-75 A range: 1.25 x the load's peak 60 A, on the 5 mOhm shunt)"
    assert not gain["stated"]
    assert any("overcurrent_discharge.threshold_A = 30 (default)" in w for w in shown["warnings"])
    # The default thermistors sit on groups 1, 7, 13, 19, each on its group's first cell:
    # cells 1, 25, 49, 73 of 96. Without cell-to-cell conductances (the default) no other
    # cell is watched.
    reach = [w for w in shown["warnings"] if w.startswith("hardware.thermistors.at_groups")]
    assert len(reach) == 1 and "cells 2-24, 26-48, 50-72, 74-96" in reach[0] and "no heat flows" in reach[0]
    # Linked by 0.5 W/K (against 0.04 W/K to ambient), cells more than 4 from all of them go
    # unseen: the last thermistor (cell 73) reaches to 77, so cells 78-96.
    linked = packsim.show(USER_PACK, {"thermal.cell_to_cell_W_per_K": 0.5}, base_dir=str(tmp_path))
    reach = [w for w in linked["warnings"] if w.startswith("hardware.thermistors.at_groups")]
    assert len(reach) == 1 and "cells 6-20, 30-44, 54-68, 78-96" in reach[0]


def test_show_yaml_runs_to_the_same_results(default_scenario):
    over = {"load.laps": 1}
    shown = packsim.show(default_scenario, over)
    base = str(Path(default_scenario).parent)
    a = packsim.run(default_scenario, over)
    b = packsim.run(shown["yaml"], base_dir=base)
    np.testing.assert_array_equal(a["truth/cell_voltage_V"], b["truth/cell_voltage_V"])
    assert a.summary == b.summary


def test_cli_show_formats(cli, default_scenario):
    text = subprocess.run([str(cli), "show", default_scenario], capture_output=True, text=True, check=True).stdout
    assert "\npack\n" in text and "warnings  none" in text
    js = subprocess.run([str(cli), "show", default_scenario, "--format", "json"], capture_output=True, text=True,
                        check=True).stdout
    data = json.loads(js)
    assert data["values"]["pack.series"]["value"] == "12"
    assert data["warnings"] == []
    bad = subprocess.run([str(cli), "show", default_scenario, "--format", "xml"], capture_output=True, text=True)
    assert bad.returncode == 2

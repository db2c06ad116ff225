"""A Monte Carlo's random inputs (core/batch/drawn_inputs.hpp, docs/batch.md): each case's
drawn cell values in summary.csv and its result file, the same for the same seed, and the
sweep report's sensitivity of each output to each of them (Spearman rank correlation).

The constructed Monte Carlo draws the capacity spread only: a 4s1p pack discharged past
its weakest cell's limit. The lowest cell voltage and the energy stranded by imbalance must
follow the drawn capacity of the weakest group; the inputs that are not drawn (resistance,
initial SOC, self-discharge) are the same in every case and have no sensitivity."""
from __future__ import annotations

import csv

import h5py
import numpy as np
import pytest

import packsim
from packsim import sweep_figure

pytest.importorskip("scipy")

BASE = """\
name: mc_capacity
seed: 3
pack:
  series: 4
  initial_soc: 0.9
  spread: {capacity_rel_sd: 0.05}
  cell:
    capacity_Ah: 0.5
    ocv_V: {poly: [0.8, 3.4]}
    r0_ohm: 0.02
    rc_pairs: [{r_ohm: 0.01, c_F: 1000}]
    heat_capacity_J_per_K: 40
    g_ambient_W_per_K: 0.1
    v_min_V: 3.45
hardware:
  cell_adc: {lsb_uV: 100, bits: 16, noise_mV_rms: 0}
  thermistors: {at_groups: [1]}
  current_sense: {shunt_ohm: 0.001, amp_gain: 20, noise_A_rms: 0}
ambient: {temp_C: 25}
load: {current_A: 2.0}
run: {duration_s: 900, solver: fast}
"""
NOT_DRAWN = ("drawn_r0_scale_max", "drawn_r0_scale_rel_sd", "drawn_initial_soc_min", "drawn_initial_soc_max",
             "drawn_self_discharge_max_A")


def _ranks(v):
    return np.argsort(np.argsort(v)).astype(float)


@pytest.fixture(scope="module")
def mc(tmp_path_factory):
    d = tmp_path_factory.mktemp("mc")
    (d / "base.yaml").write_text(BASE)
    runs = []
    for out in ("a", "b"):
        res = packsim.batch({"base": "base.yaml", "output_dir": out,
                             "monte_carlo": {"samples": 10, "master_seed": 5}}, base_dir=str(d))
        assert res.ok, res.errors
        runs.append(res)
    return d, runs


def _csv(res):
    with open(res.csv_path, newline="") as f:
        return list(csv.DictReader(f))


def test_same_seed_same_drawn_values_and_the_file_holds_every_cell(mc):
    _, (a, b) = mc
    rows_a, rows_b = _csv(a), _csv(b)
    drawn = [k for k in rows_a[0] if k.startswith("drawn_")]
    assert drawn[:3] == ["drawn_capacity_min_Ah", "drawn_capacity_max_Ah", "drawn_capacity_rel_sd"]
    assert [[r[k] for k in drawn] for r in rows_a] == [[r[k] for k in drawn] for r in rows_b]
    assert len({r["drawn_capacity_min_Ah"] for r in rows_a}) == len(rows_a)  # every sample its own draw
    for k in NOT_DRAWN:
        assert len({r[k] for r in rows_a}) == 1
    for i, row in enumerate(rows_a):
        with h5py.File(a.paths[i]) as fa, h5py.File(b.paths[i]) as fb:
            cap = fa["inputs/cell_capacity_Ah"][()]
            assert np.array_equal(cap, fb["inputs/cell_capacity_Ah"][()])
            assert cap.shape == (4,)
            # the figures are of these cells (4s1p: a group is a cell), and the run used them:
            # each cell's SOC fell by the charge delivered over its own drawn capacity
            assert float(row["drawn_capacity_min_Ah"]) == pytest.approx(cap.min(), rel=1e-9)
            assert float(row["drawn_capacity_rel_sd"]) == pytest.approx(cap.std() / cap.mean(), rel=1e-8)
            assert int(row["drawn_weakest_group"]) == int(np.argmin(cap)) + 1
            soc = fa["truth/cell_soc"][()]
            limit = np.searchsorted(fa["time_s"][()], float(row["limit_time_s"]))
            q = (soc[0] - soc[limit]) * cap  # Ah out of each cell up to the limit
            assert np.ptp(q) < 1e-6 * q.mean()  # one series current: the same charge from every cell
            assert np.argmin(soc[limit]) == int(np.argmin(cap))  # the weakest cell reached the limit
    pytest.importorskip("xarray")
    tree = a.load(0).to_xarray()  # the group as the file holds it, on the cells' dimension
    with h5py.File(a.paths[0]) as fa:
        assert np.array_equal(tree["inputs/cell_capacity_Ah"].values, fa["inputs/cell_capacity_Ah"][()])
        assert tree["inputs"].attrs["drawn_capacity_min_Ah"] == fa["inputs"].attrs["drawn_capacity_min_Ah"]
    assert tree["inputs/cell_capacity_Ah"].dims == ("cell",)


def test_sensitivity_names_the_capacity_and_not_an_input_that_was_not_drawn(mc):
    d, (a, _) = mc
    t = sweep_figure.read(d / "a")
    assert t.monte_carlo
    assert "drawn_capacity_min_Ah" in t.drawn and "drawn_capacity_rel_sd" in t.drawn
    for k in NOT_DRAWN:
        assert k not in t.drawn and t.left_out[k] == "not drawn: the same in every case"
    assert t.left_out["drawn_weakest_group"] == "identifier"
    assert not any(o.startswith("drawn_") for o in t.outputs)
    sens = {s.output: s for s in sweep_figure.sensitivity(t)}
    for s in sens.values():
        assert not set(NOT_DRAWN) & set(s.rho)
    low, stranded = sens["min_cell_V"], sens["energy_stranded_Wh"]
    # the weakest cell is the lowest: the lowest voltage rises with the smallest drawn capacity
    assert low.strongest in ("drawn_capacity_min_Ah", "drawn_charge_min_Ah", "drawn_headroom_min_Ah")
    assert low.rho["drawn_capacity_min_Ah"] > 0.9 and low.p_value["drawn_capacity_min_Ah"] < 1e-3
    # energy left in the other cells when the weakest reaches its limit: more, the weaker it is
    assert stranded.rho["drawn_capacity_min_Ah"] < -0.6 and stranded.rho["drawn_capacity_rel_sd"] > 0.6
    # Spearman is Pearson's correlation of the ranks (no ties here): an independent computation
    x, y = t.column("drawn_capacity_min_Ah"), t.column("energy_stranded_Wh")
    assert stranded.rho["drawn_capacity_min_Ah"] == pytest.approx(np.corrcoef(_ranks(x), _ranks(y))[0, 1])


def test_the_report_shows_the_sensitivity_table_and_each_output_against_each_input(mc, tmp_path):
    pytest.importorskip("plotly")
    d, _ = mc
    t = sweep_figure.read(d / "a")
    figs = dict(sweep_figure.figures(t))
    heat = figs["sensitivity to the inputs"]
    assert list(heat.data[0].x) == t.drawn and list(heat.data[0].y) == t.outputs
    scatter = figs["min_cell_V against the inputs"]
    assert len(scatter.data) == len(t.drawn)  # one trace per random input
    assert [tr.visible for tr in scatter.data].count(True) == 1
    assert scatter.data[0].name == sweep_figure.sensitivity(t)[t.outputs.index("min_cell_V")].strongest
    assert len(scatter.layout.updatemenus[0].buttons) == len(t.drawn)
    page = packsim.report(d / "a", tmp_path / "mc.html")
    text = open(page, encoding="utf-8").read()
    assert 'id="sensitivity"' in text
    assert "Not drawn (spread 0, the same in every case): drawn_r0_scale_max" in text
    row = text[text.index("<td>min_cell_V</td>"):]
    assert row.startswith("<td>min_cell_V</td><td>drawn_capacity_min_Ah</td><td>+1.00</td>")

"""packsim.balance_time mirrors `packsim balance-time`: the same table for the same
arguments, an analytic column that is the closed form, simulated times that grow with
the resistor, the plot from Python and the CLI, and clear errors for bad arguments.
The bench preset's firmware balances only on the charger: at rest these runs state
``when="always"`` (``--when always``)."""
from __future__ import annotations

import subprocess

import numpy as np
import pytest

import packsim
from packsim import plot


def _same(a, b) -> bool:
    """Equal results, NaN (no board node) equal to NaN."""
    return repr(a) == repr(b)


def test_same_table_as_the_cli(cli):
    done = subprocess.run([str(cli), "balance-time", "--resistor", "22,33,47", "--when", "always"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    bt = packsim.balance_time(resistor=[22, 33, 47], when="always")
    assert str(bt) == done.stdout
    assert bt.when == "always" and bt.when_overridden and "set by --when" in done.stdout
    assert bt.scenario == "bench_6s_balancing" and bt.resistor_ohm == [22.0, 33.0, 47.0]

    args = ["--preset", "motorcycle_110s_balancing", "--resistor", "33", "--delta-Ah", "0.5", "--cell-V", "3.9",
            "--high-cells", "2", "--analytic-only"]
    done = subprocess.run([str(cli), "balance-time", *args], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    bt = packsim.balance_time(preset="motorcycle_110s_balancing", resistor=33, delta_Ah=0.5, cell_V=3.9,
                              high_cells=2, simulate=False)
    assert str(bt) == done.stdout


def test_analytic_column_is_the_closed_form():
    bt = packsim.balance_time(resistor=[22, 47, 100], delta_Ah=0.4, cell_V=3.8, simulate=False)
    assert bt.delta_Ah == 0.4 and bt.cell_V == 3.8
    for w in bt.rows:
        assert not w.simulated and w.branch_ohm >= w.resistor_ohm  # plus the FET's Rds_on
        i = 3.8 / w.branch_ohm
        assert w.current_A == pytest.approx(i, rel=1e-12)
        assert w.power_W == pytest.approx(3.8 * i, rel=1e-12)
        assert w.const_I_all_h == pytest.approx(0.4 / i, rel=1e-12)


def test_analytic_columns_share_the_simulated_end_criterion_and_the_board_has_a_temperature_analytic_only():
    # 30 C ambient and a 0.08 W/K board node: T = T_amb + P/G needs no simulation
    over = {"ambient.temp_C": 30.0, "thermal.nodes": [{"name": "balancing_board", "heat_capacity_J_per_K": 30,
                                                       "g_ambient_W_per_K": 0.08}]}
    bt = packsim.balance_time(resistor=[22, 47], delta_Ah=0.2, cell_V=3.9, high_cells=2, simulate=False, **over)
    for w in bt.rows:
        # to the target, constant current and droop differ only by V_cell against the mean OCV
        # (a few %); all of ΔQ takes longer by the charge left within the target
        assert w.const_I_to_target_h == pytest.approx(w.droop_to_target_h, rel=0.03)
        assert w.const_I_to_target_h < w.const_I_all_h
        assert w.board_power_W == pytest.approx(2 * 3.9 ** 2 / w.branch_ohm, rel=1e-12)
        assert w.board_steady_C == pytest.approx(30.0 + w.board_power_W / 0.08, rel=1e-12)
    assert "board_steady_C" in str(bt) and f"{bt.rows[0].board_steady_C:.1f}" in str(bt)


def test_simulated_time_grows_with_the_resistor_and_removes_the_imbalance():
    bt = packsim.balance_time(resistor=[22, 47], delta_Ah=0.2, cell_V=3.9, when="always")
    assert bt.target_mV == 15.0  # default: 1.5 x the firmware's own 10 mV stop threshold
    sim = [w.true_h for w in bt.rows]
    assert all(w.simulated and w.end_reason == "both_known" for w in bt.rows), [w.firmware_note for w in bt.rows]
    assert sim[0] < sim[1]
    for w in bt.rows:
        # Same physics as the droop closed form, to within the decision latency and the
        # noise at the 10 mV stop; the spread left is a small part of what there was.
        assert w.true_h == pytest.approx(w.droop_to_target_h, rel=0.05)
        assert w.true_h == pytest.approx(w.const_I_to_target_h, rel=0.08)  # the same end criterion
        assert w.firmware_h >= w.true_h - 0.05
        assert w.final_spread_Ah < 0.2 * 0.25
        assert w.pack_useful_Ah + w.pack_wasted_Ah == pytest.approx(w.bled_Ah, rel=1e-12)
    assert sim[1] / sim[0] == pytest.approx(bt.rows[1].branch_ohm / bt.rows[0].branch_ohm, rel=0.2)


def test_charge_only_firmware_at_rest_says_why_it_never_started():
    bt = packsim.balance_time(resistor=47, delta_Ah=0.2, cell_V=3.9)
    (w,) = bt.rows
    assert w.end_reason == "not_started" and np.isnan(w.true_h) and np.isnan(w.firmware_h)
    assert "only while charging" in w.firmware_note and not w.within_limits


def test_scenario_text_and_overrides():
    path = packsim._core().preset_path("bench_6s_balancing")
    with open(path) as f:
        text = f.read()
    by_file = packsim.balance_time(path, resistor=33, simulate=False)
    by_preset = packsim.balance_time(preset="bench_6s_balancing", resistor=33, simulate=False)
    assert _same(by_file, by_preset)
    # Text resolves `extends`/CSV paths against base_dir, as packsim.run.
    import os
    by_text = packsim.balance_time(text, resistor=33, simulate=False, base_dir=os.path.dirname(path))
    assert _same(by_text, by_file)
    # Overrides reach the scenario: its own resistor and FET are used without resistor=.
    own = packsim.balance_time(path, simulate=False)
    assert own.resistor_ohm == [47.0]
    changed = packsim.balance_time(path, {"hardware.balancing": {"resistor_ohm": 68, "rds_on_ohm": 2.0}},
                                   simulate=False)
    (w,) = changed.rows
    assert (w.resistor_ohm, w.branch_ohm) == (68.0, 70.0)
    assert w.current_A == pytest.approx(changed.cell_V / 70.0, rel=1e-12)


def test_table_and_chart():
    bt = packsim.balance_time(resistor=[22, 33, 47, 68], delta_Ah=0.2, cell_V=3.9, when="always")
    pd = pytest.importorskip("pandas")
    df = bt.table
    assert isinstance(df, pd.DataFrame) and list(df.resistor_ohm) == [22.0, 33.0, 47.0, 68.0]
    assert {"firmware_h", "true_h", "pack_useful_Ah", "pack_wasted_Ah", "paused_fraction", "peak_board_C"} <= set(df.columns)
    fig = plot.balance_time(bt)
    ax, temp = fig.axes[0], fig.axes[1]
    analytic, droop, true = ax.lines[0], ax.lines[1], ax.lines[2]
    np.testing.assert_array_equal(analytic.get_xdata(), [22, 33, 47, 68])
    np.testing.assert_array_equal(analytic.get_ydata(), [w.const_I_to_target_h for w in bt.rows])
    np.testing.assert_array_equal(droop.get_ydata(), [w.droop_to_target_h for w in bt.rows])
    np.testing.assert_array_equal(true.get_ydata(), [w.true_h for w in bt.rows])
    np.testing.assert_array_equal(temp.lines[0].get_ydata(), [w.board_steady_C for w in bt.rows])
    np.testing.assert_array_equal(temp.lines[1].get_ydata(), [w.peak_board_C for w in bt.rows])
    with pytest.raises(TypeError, match="packsim.balance_time"):
        plot.balance_time({"rows": []})


def test_bad_arguments(simple_yaml):
    with pytest.raises(TypeError, match="resistor must be a number"):
        packsim.balance_time(resistor="22,33")
    with pytest.raises(ValueError, match="resistor must be > 0"):
        packsim.balance_time(resistor=[22, -1])
    with pytest.raises(ValueError, match="cell_V needs delta_Ah"):
        packsim.balance_time(cell_V=3.9)
    with pytest.raises(ValueError, match="not both"):
        packsim.balance_time(packsim.default_scenario(), preset="bench_6s_balancing")
    with pytest.raises(ValueError, match="did you mean 'bench_6s_balancing'"):
        packsim.balance_time(preset="bench_6s_balancng")
    with pytest.raises(TypeError, match="high_cells must be an int"):
        packsim.balance_time(high_cells=1.5)
    with pytest.raises(TypeError, match="simulate must be a bool"):
        packsim.balance_time(simulate="no")
    with pytest.raises(packsim.ScenarioError):
        packsim.balance_time(preset="bench_6s_balancing", **{"pack.cell.capacity_ah": 3})


def test_argument_errors_name_the_python_arguments():
    """The range errors came from the CLI's checks and named its flags: high_cells=0 was
    "--high-cells: must be within 1 .. 6", a word a Python user never wrote; a 0-d NumPy
    array as the resistor was "TypeError: iteration over a 0-d array", naming nothing."""
    import numpy as np
    with pytest.raises(ValueError, match=r"^high_cells: must be within 1 \.\. 6 \(the pack's series cells\)$"):
        packsim.balance_time(resistor=33, delta_Ah=0.2, high_cells=0, simulate=False)
    with pytest.raises(ValueError, match=r"^resistor: each value must be within 1 \.\. 10000 ohm"):
        packsim.balance_time(resistor=0.5, simulate=False)
    with pytest.raises(ValueError, match=r"^target_mV: must be within 0.1 \.\. 500 mV$"):
        packsim.balance_time(resistor=33, target_mV=900, simulate=False)
    one = packsim.balance_time(resistor=np.array(33.0), simulate=False)
    assert one.resistor_ohm == [33.0]


def test_cli_plot_writes_the_figure_and_its_table(cli, tmp_path):
    png = tmp_path / "bt.png"
    done = subprocess.run([str(cli), "balance-time", "--resistor", "22,47", "--analytic-only", "--plot", str(png)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert png.stat().st_size > 1000
    import csv
    with open(tmp_path / "bt.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [float(r["resistor_ohm"]) for r in rows] == [22.0, 47.0]
    bt = packsim.balance_time(resistor=[22, 47], simulate=False)
    assert [float(r["const_I_all_h"]) for r in rows] == pytest.approx([w.const_I_all_h for w in bt.rows], rel=1e-9)


def test_bad_when_names_the_choices():
    with pytest.raises(ValueError, match="charging, rest, charging_or_rest, always"):
        packsim.balance_time(when="sometimes")


def test_table_columns_match_docs_balancing_word_for_word():
    """The header of the balance-time table, in order, is the column list of
    docs/balancing.md ("Every column"), and every column there is in the header."""
    import re
    from pathlib import Path
    doc = (Path(__file__).resolve().parents[2] / "docs" / "balancing.md").read_text(encoding="utf-8")
    section = doc.split("## Every column", 1)[1].split("\n## ", 1)[0]
    documented = re.findall(r"^\| `([^`]+)` \|", section, re.M)
    bt = packsim.balance_time(resistor=47, delta_Ah=0.1, cell_V=3.9, simulate=False)
    header = next(line for line in str(bt).splitlines() if line.strip().startswith("R_ohm")).split()
    assert header == documented

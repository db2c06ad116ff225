"""Bad test data and failed fits: one FitError naming the file and line (or the reason),
and no preset written."""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import packsim
from fit_cells import pulse_frame
from packsim.fit import FitError, parse_soc_grid


def _pulses(rest: bool = True) -> pd.DataFrame:
    return pulse_frame(rest)


def _write(path, text: str):
    path.write_text(text)
    return str(path)


def test_unsorted_time_names_file_and_line(tmp_path):
    rows = "\n".join(f"{t},{1.0 if t > 20 else 0.0},4.0" for t in range(30))
    p = _write(tmp_path / "t.csv", "# a comment\ntime_s,current_A,voltage_V\n" + rows.replace("\n12,", "\n10,") + "\n")
    with pytest.raises(FitError, match=r"t\.csv:15: time_s 10 is not after the previous row's 11"):
        packsim.fit(p)


def test_missing_column_names_the_closest(tmp_path):
    p = _write(tmp_path / "m.csv", "time_s,current_A,Voltage_V\n" + "0,0,4\n" * 12)
    with pytest.raises(FitError, match=r"m\.csv:1: no column 'voltage_V'; did you mean 'Voltage_V'\?"):
        packsim.fit(p)


def test_bad_number_names_the_line(tmp_path):
    p = _write(tmp_path / "n.csv", "time_s,current_A,voltage_V\n" + "".join(f"{t},0,4\n" for t in range(5))
               + "5,0,four\n" + "".join(f"{t},0,4\n" for t in range(6, 12)))
    with pytest.raises(FitError, match=r"n\.csv:7: column 'voltage_V': 'four' is not a number"):
        packsim.fit(p)


def test_no_rest_is_refused():
    with pytest.raises(FitError, match=r"<DataFrame 0>: no rest .* no OCV information"):
        packsim.fit(_pulses(rest=False), rc_pairs=0, capacity_Ah=2.0)


def test_a_fit_that_does_not_converge_is_an_error():
    with pytest.raises(FitError, match=r"did not converge after 1 evaluations"):
        packsim.fit(_pulses(), rc_pairs=2, capacity_Ah=2.0, max_evaluations=1)


def test_the_same_pulses_with_rests_fit():
    f = packsim.fit(_pulses(), rc_pairs=1, capacity_Ah=2.0, soc_grid="0.9:0.05:1")
    assert f.files[0].rms_mV < 1.0
    assert f.r0_ohm(0.95) == pytest.approx(0.05, rel=0.02)
    assert f.temperatures[0].rc_tau_s[0] == pytest.approx(20.0, rel=0.05)


@pytest.mark.parametrize("kwargs, message", [
    ({"rc_pairs": 7}, r"rc_pairs: 7 is not an integer in \[0, 4\]"),
    ({"form": "spline"}, r"form 'spline' is not one of table, poly"),
    ({"capacity_Ah": -1.0}, r"capacity_Ah: -1.0 is not a number in \(0, 1e5\)"),
    ({"soc_grid": "1:0.1:0"}, r"soc_grid: needs at least 2 strictly increasing values"),
    ({"initial_soc": [1.0, 0.5]}, r"initial_soc: 2 values for 1 tests"),
    ({"columns": {"volts": "V"}}, r"columns: unknown column 'volts'"),
])
def test_bad_arguments(kwargs, message):
    with pytest.raises(FitError, match=message):
        packsim.fit(_pulses(), **kwargs)


def test_soc_grid_text():
    assert parse_soc_grid("0:0.25:1").tolist() == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert parse_soc_grid("0,0.5,1").tolist() == [0.0, 0.5, 1.0]
    with pytest.raises(FitError, match="start:step:stop"):
        parse_soc_grid("0:x:1")


def test_save_writes_nothing_partial(tmp_path):
    f = packsim.fit(_pulses(), rc_pairs=0, capacity_Ah=2.0)
    with pytest.raises(FitError, match="no such folder"):
        f.save(tmp_path / "missing" / "cell.yaml")
    f.save(tmp_path / "cell.yaml")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cell.yaml"]


def test_poly_r0_negative_somewhere_is_refused():
    # R0 falling steeply over the 0.1 Ah the pulses cover: a straight line through it goes
    # negative before the 2 Ah cell is empty, and must not be written
    df = _pulses()
    x_Ah = np.concatenate(([0.0], np.cumsum(df.current_A.to_numpy()[:-1]))) / 3600.0
    df = df.assign(voltage_V=df.voltage_V + 0.05 * df.current_A - (0.05 - 0.4 * x_Ah) * df.current_A)
    with pytest.raises(FitError, match=r"R0 polynomial is not positive over 0..2 Ah"):
        packsim.fit(df, rc_pairs=1, capacity_Ah=2.0, form="poly", poly_order=1)


def test_discharge_logged_negative():
    df = _pulses()
    flipped = packsim.fit(df.assign(current_A=-df.current_A), rc_pairs=1, capacity_Ah=2.0, invert_current=True)
    assert flipped.yaml == packsim.fit(df, rc_pairs=1, capacity_Ah=2.0).yaml


def test_dataframe_gives_the_same_fit_as_the_csv(tmp_path):
    df = _pulses()
    df.to_csv(tmp_path / "p.csv", index=False)
    from_csv = packsim.fit(str(tmp_path / "p.csv"), rc_pairs=1, capacity_Ah=2.0)
    from_df = packsim.fit([df.rename(columns={"voltage_V": "U"})], rc_pairs=1, capacity_Ah=2.0,
                          columns={"voltage_V": "U"})
    assert from_df.files[0].name == "<DataFrame 0>"
    assert from_df.yaml.split("capacity_Ah")[1] == from_csv.yaml.split("capacity_Ah")[1]


def test_capacity_measured_is_the_charge_removed_over_the_initial_soc():
    df = _pulses()
    removed_Ah = float(df.current_A.sum()) / 3600.0
    with pytest.warns(packsim.FitWarning, match="no test is a full discharge"):  # pulses stop short of empty
        f = packsim.fit(df, rc_pairs=0)
    assert f.capacity_Ah == pytest.approx(removed_Ah, rel=0.01)
    assert "measured" in f.summary()
    with pytest.warns(packsim.FitWarning):
        half = packsim.fit(df, rc_pairs=0, initial_soc=0.5)
    assert half.capacity_Ah == pytest.approx(2 * f.capacity_Ah, rel=1e-12)


def test_charge_only_data_names_the_sign_convention(tmp_path):
    df = _pulses()
    df.assign(current_A=-df.current_A).to_csv(tmp_path / "neg.csv", index=False)
    with pytest.raises(FitError, match=r"neg\.csv:\d+: the SOC counted from the current reaches 1\.05\d, above 1: "
                                       r"positive current discharges"):
        packsim.fit(str(tmp_path / "neg.csv"), capacity_Ah=0.5)

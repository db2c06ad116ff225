"""packsim.fit checks magnitudes against the cell: a current in mA read as A is an error
naming the column (by its name, or by the capacity or C-rate it would imply); a capacity
the data cannot determine (an HPPC stops short of empty) is a warning asking for
capacity_Ah or a full discharge; a full constant-current discharge measures it silently."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import packsim
from fit_cells import KNOWN_CELL, cc_segments, hppc_segments, pulse_frame, simulate, write_test_csv


@pytest.fixture(scope="module")
def hppc_and_cc(tmp_path_factory):
    folder = tmp_path_factory.mktemp("magnitudes")
    hppc = write_test_csv(simulate(KNOWN_CELL, hppc_segments(5.0, rest_s=600.0)), folder / "hppc.csv")
    # C/2 until the cell is empty (SOC 0.02), then a rest
    cc = write_test_csv(simulate(KNOWN_CELL, cc_segments(2.5, 0.98 * 7200.0)), folder / "cc.csv", seed=2)
    return str(hppc), str(cc)


def test_a_column_named_in_mA_is_an_error_naming_it(tmp_path):
    df = pulse_frame().rename(columns={"current_A": "current_mA"})
    df["current_mA"] *= 1000.0
    df.to_csv(tmp_path / "ma.csv", index=False)
    with pytest.raises(packsim.FitError, match=r"ma\.csv: column 'current_mA' is read as current_A, but its name "
                                               r"says mA: .*convert the column to A"):
        packsim.fit(str(tmp_path / "ma.csv"), columns={"current_A": "current_mA"})
    with pytest.raises(packsim.FitError, match=r"column 'Time\(ms\)' is read as time_s, but its name says ms"):
        packsim.fit(pulse_frame().rename(columns={"time_s": "Time(ms)"}), columns={"time_s": "Time(ms)"})


def test_milliamperes_under_an_ampere_name_are_caught_by_magnitude(hppc_and_cc, tmp_path):
    hppc, cc = hppc_and_cc
    data = np.loadtxt(cc, delimiter=",", skiprows=1)
    data[:, 1] *= 1000.0  # logged in mA, in a column called I
    np.savetxt(tmp_path / "cc_mA.csv", data, delimiter=",", header="time_s,I,voltage_V,temp_C", comments="")
    cc_mA = str(tmp_path / "cc_mA.csv")
    # measured capacity: thousands of Ah
    with pytest.raises(packsim.FitError, match=r"cc_mA\.csv: column 'I' \(read as current_A\) removes 4,9\d\d Ah, "
                                               r"more than any single cell holds"):
        packsim.fit(cc_mA, columns={"current_A": "I"})
    # given capacity: a C-rate of a thousand
    with pytest.raises(packsim.FitError, match=r"cc_mA\.csv:\d+: column 'I' \(read as current_A\) reaches 25\d\d A, "
                                               r"50\d C of the given capacity_Ah 5 Ah \(at most 100 C is plausible\): is the current in mA"):
        packsim.fit(cc_mA, columns={"current_A": "I"}, capacity_Ah=5.0)
    # and the other way round: a capacity in mAh
    with pytest.raises(packsim.FitError, match=r"0\.001 C of the given capacity_Ah 5000 Ah: is capacity_Ah in mAh"):
        packsim.fit(hppc, capacity_Ah=5000.0)


def test_hppc_alone_warns_that_the_capacity_is_undetermined(hppc_and_cc):
    hppc, _ = hppc_and_cc
    with pytest.warns(packsim.FitWarning, match=r"the capacity 4\.\d+ Ah is from the charge .*hppc\.csv removed, but no "
                                                r"test is a full discharge.*give --capacity-Ah / capacity_Ah"):
        f = packsim.fit(hppc, rc_pairs=1)
    assert f.capacity_Ah == pytest.approx(0.9 * 5.0, rel=0.02)  # nine 10 % steps: 10 % short
    assert len(f.warnings) == 1


def test_a_full_discharge_measures_the_capacity_without_warning(hppc_and_cc):
    hppc, cc = hppc_and_cc
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        f = packsim.fit([hppc, cc], rc_pairs=1)
    assert f.capacity_Ah == pytest.approx(0.98 * 5.0, rel=0.005)
    assert f.warnings == [] and cc in f.capacity_source


def test_a_capacity_from_a_test_not_started_full_says_what_was_removed(hppc_and_cc):
    # Was: with initial_soc 0.5 the line read "capacity 9.8 Ah (measured: the most charge
    # one test removed, cc.csv)" though the test removed 4.9 Ah: the capacity is that
    # charge over the initial SOC, and the line now says both.
    _, cc = hppc_and_cc
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        f = packsim.fit(cc, rc_pairs=1, initial_soc=0.5)
    removed = 0.98 * 5.0
    assert f.capacity_Ah == pytest.approx(removed / 0.5, rel=0.005)
    assert f.capacity_source.endswith(f"over its initial SOC, {cc}: {f.capacity_Ah * 0.5:.4g} Ah from SOC 0.5"), \
        f.capacity_source
    assert f"capacity {f.capacity_Ah:.4g} Ah ({f.capacity_source})" in f.summary()


def test_cli_prints_the_warning(cli, hppc_and_cc, tmp_path):
    import subprocess
    hppc, _ = hppc_and_cc
    p = subprocess.run([str(cli), "fit", hppc, "-o", str(tmp_path / "c.yaml"), "--rc-pairs", "1"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert p.stderr.count("packsim fit: warning: the capacity") == 1


def test_default_is_two_rc_pairs_as_the_worked_example():
    f = packsim.fit(pulse_frame(), capacity_Ah=2.0)
    assert f.rc_pairs == 2 and f.temperatures[0].rc_tau_s.size == 2

"""packsim.fit reads cycler exports as teams have them (python/packsim/_fit_cyclers.py):
Arbin, Maccor, Neware and BioLogic files written here to each format's documented header
(units in the header, each cycler's own sign convention, elapsed time as seconds or
hh:mm:ss text), from one test in closed form. Each gives the very fit the plain
time_s,current_A,voltage_V,temp_C CSV of the same test gives; a bad value or header is
one error naming the file, line and column."""
from __future__ import annotations

import numpy as np
import pytest

import packsim

T = np.arange(0.0, 900.0, 1.0)


def _test():
    """A 2 Ah cell, OCV 3.4 + 0.8·soc, R0 50 mΩ, one 20 mΩ / 20 s RC pair: 1 A discharge
    pulses, 0.5 A charge pulses, rests between; the current held between samples."""
    phase = T % 150
    i = np.where(phase < 30, 1.0, np.where((phase >= 70) & (phase < 85), -0.5, 0.0))
    soc = 1.0 - np.concatenate(([0.0], np.cumsum(i[:-1]))) / 3600.0 / 2.0
    v_rc = np.zeros_like(T)
    for k in range(1, T.size):
        v_rc[k] = v_rc[k - 1] * np.exp(-1 / 20) + 0.020 * (1 - np.exp(-1 / 20)) * i[k - 1]
    return i, 3.4 + 0.8 * soc - 0.05 * i - v_rc, 25.0 + 0.002 * T


def _clock(s: float, days: bool = False) -> str:
    d, s = divmod(int(s), 86400)
    h, s = divmod(s, 3600)
    m, s = divmod(s, 60)
    return f"{d}d {h:02d}:{m:02d}:{s:02d}.00" if days else f"{h + 24 * d:02d}:{m:02d}:{s:02d}"


def _state(i: float, charge: str, discharge: str, rest: str) -> str:
    return discharge if i > 0 else charge if i < 0 else rest


def write_plain(path):
    i, v, temp = _test()
    rows = ["time_s,current_A,voltage_V,temp_C"] + [f"{t:.1f},{a:.6f},{u:.6f},{c:.3f}" for t, a, u, c in zip(T, i, v, temp)]
    path.write_text("\n".join(rows) + "\n")
    return path


def write_arbin(path):  # MITS Pro CSV export: charge current positive, amperes
    i, v, temp = _test()
    head = ("Data_Point,Test_Time(s),Date_Time,Step_Time(s),Step_Index,Cycle_Index,Current(A),Voltage(V),"
            "Charge_Capacity(Ah),Discharge_Capacity(Ah),dV/dt(V/s),Aux_Temperature_1(C)")
    rows = [head] + [f"{k + 1},{t:.4f},11/25/2026 10:{int(t) // 60 % 60:02d}:{int(t) % 60:02d},{t % 150:.4f},"
                     f"{1 + int(t // 150)},1,{-a:.6f},{u:.6f},0,0,0,{c:.3f}"
                     for k, (t, a, u, c) in enumerate(zip(T, i, v, temp))]
    path.write_text("\n".join(rows) + "\n")
    return path


def write_maccor(path):  # text export: a preamble, tab-separated, |current| with a state column, d hh:mm:ss
    i, v, temp = _test()
    pre = ["Today's Date\t11/25/2026", "Date of Test:\t11/25/2026 10:00", "Filename:\tC:\\Data\\CELL1.001",
           "Procedure:\tHPPC.000\tPulses", "Comment/Barcode:\t"]
    head = "Rec#\tCyc#\tStep\tTestTime\tStepTime\tAmp-hr\tWatt-hr\tAmps\tVolts\tState\tES\tDPt Time\tTemp 1"
    rows = [f"{k + 1}\t0\t{1 + int(t // 150)}\t{_clock(t, days=True)}\t{_clock(t % 150, days=True)}\t0\t0\t"
            f"{abs(a):.6f}\t{u:.6f}\t{_state(a, 'C', 'D', 'R')}\t0\t11/25/2026 10:00:00\t{c:.3f}"
            for k, (t, a, u, c) in enumerate(zip(T, i, v, temp))]
    path.write_text("\n".join(pre + [head] + rows) + "\n", encoding="cp1252")
    return path


def write_neware(path):  # BTS CSV export: mA, signed (discharge negative), step types, h:mm:ss
    i, v, temp = _test()
    head = "DataPoint,Cycle Index,Step Index,Step Type,Time,Total Time,Current(mA),Voltage(V),Capacity(mAh),T1(℃)"
    rows = [head] + [f"{k + 1},1,{1 + int(t // 150)},{_state(a, 'CC Chg', 'CC DChg', 'Rest')},{_clock(t % 150)},"
                     f"{_clock(t)},{-1000 * a:.3f},{u:.6f},0,{c:.3f}"
                     for k, (t, a, u, c) in enumerate(zip(T, i, v, temp))]
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def write_biologic(path, decimal_comma: bool = False):  # EC-Lab .mpt: header count, tabs, mA, charge positive
    i, v, temp = _test()
    head = ("mode\tox/red\terror\tcontrol changes\tNs changes\tcounter inc.\tNs\ttime/s\tcontrol/mA\tEwe/V\t"
            "<I>/mA\tdQ/C\tTemperature/°C")
    pre = ["EC-Lab ASCII FILE", "Nb header lines : 6", "", "Galvanostatic Cycling with Potential Limitation", ""]
    rows = [f"1\t{1 if a < 0 else 0}\t0\t0\t0\t0\t0\t{t:.4f}\t{-1000 * a:.4f}\t{u:.6f}\t{-1000 * a:.4f}\t0\t{c:.3f}"
            for t, a, u, c in zip(T, i, v, temp)]
    if decimal_comma:
        rows = [r.replace(".", ",") for r in rows]
    path.write_text("\n".join(pre + [head] + rows) + "\n", encoding="latin-1")
    return path


WRITERS = {"Arbin": write_arbin, "Maccor": write_maccor, "Neware": write_neware, "BioLogic": write_biologic}


@pytest.fixture(scope="module")
def plain_fit(tmp_path_factory):
    return packsim.fit(str(write_plain(tmp_path_factory.mktemp("plain") / "plain.csv")), capacity_Ah=2.0,
                       rc_pairs=1)


@pytest.mark.parametrize("fmt", list(WRITERS))
def test_each_cycler_export_gives_the_plain_csv_fit(fmt, plain_fit, tmp_path):
    path = WRITERS[fmt](tmp_path / f"test.{'mpt' if fmt == 'BioLogic' else 'txt' if fmt == 'Maccor' else 'csv'}")
    f = packsim.fit(str(path), capacity_Ah=2.0, rc_pairs=1)
    g, ref = f.temperatures[0], plain_fit.temperatures[0]
    assert np.allclose(g.ocv_V, ref.ocv_V, rtol=0, atol=1e-6)
    assert np.allclose(g.r0, ref.r0, rtol=1e-5) and g.r0[-1] == pytest.approx(0.05, rel=0.02)  # at full, where the test is
    assert g.rc_tau_s == pytest.approx(ref.rc_tau_s, rel=1e-4) and g.rc_tau_s[0] == pytest.approx(20.0, rel=0.05)
    assert f.files[0].reader.startswith(f"{fmt} export")
    assert f.files[0].temp_C == pytest.approx(25.0)
    assert f"\n    {fmt} export: " in f.summary()


def test_biologic_with_a_decimal_comma(plain_fit, tmp_path):
    f = packsim.fit(str(write_biologic(tmp_path / "comma.mpt", decimal_comma=True)), capacity_Ah=2.0, rc_pairs=1)
    assert np.allclose(f.temperatures[0].ocv_V, plain_fit.temperatures[0].ocv_V, atol=1e-6)


def _error(path, **kw) -> str:
    with pytest.raises(packsim.FitError) as e:
        packsim.fit(str(path), capacity_Ah=2.0, rc_pairs=1, **kw)
    return str(e.value)


def test_errors_name_file_line_and_column(tmp_path):
    p = write_neware(tmp_path / "neware.csv")
    lines = p.read_text(encoding="utf-8").splitlines()
    lines[41] = lines[41].replace(lines[41].split(",")[7], "4.1x")  # line 42: a voltage that is not a number
    p.write_text("\n".join(lines) + "\n", encoding="utf-8")
    msg = _error(p)
    assert msg.startswith(f"{p}:42: ") and "column 'Voltage(V)'" in msg

    p = write_maccor(tmp_path / "maccor.txt")
    lines = p.read_text(encoding="cp1252").splitlines()
    lines[46] = lines[46].replace("\tR\t", "\tX\t")  # t = 40 s, a rest
    p.write_text("\n".join(lines) + "\n", encoding="cp1252")
    msg = _error(p)
    assert msg.startswith(f"{p}:47: column 'State': 'X' is not a Maccor state")

    p = write_arbin(tmp_path / "arbin.csv")
    p.write_text(p.read_text().replace("Current(A)", "Current(kA)", 1))
    assert _error(p) == (f"{p}:1: column 'Current(kA)': unit 'kA' is not one packsim fit reads for current "
                         "(A, mA, uA, µA)")

    p = write_arbin(tmp_path / "arbin_sign.csv")
    assert "Arbin export, whose sign packsim fit takes from the format" in _error(p, invert_current=True)

    p = tmp_path / "run.mpr"
    p.write_bytes(b"BIO-LOGIC MODULAR FILE\x1a" + bytes(64))
    assert "export it as text from EC-Lab" in _error(p)

    p = write_biologic(tmp_path / "short.mpt")
    p.write_text(p.read_text(encoding="latin-1").replace("Nb header lines : 6", "Nb header lines : 99999"),
                 encoding="latin-1")
    assert _error(p).startswith(f"{p}:2: 'Nb header lines : 99999' points past the file's")


def test_the_mA_current_of_a_neware_file_is_converted(tmp_path):
    from packsim._fit_data import read_test
    t = read_test(str(write_neware(tmp_path / "n.csv")), 0)
    i, _, _ = _test()
    assert np.allclose(t.current_A, i, atol=1e-9)  # mA -> A, discharge positive
    assert t.time_s[-1] == T[-1] and t.current_column == "Current(mA)"

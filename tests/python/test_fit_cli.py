"""`packsim fit` (the C++ command running the Python fitter) and `python -m packsim fit`:
the preset and report written on success, exit 2 and nothing written on bad input, and
a clear exit 2 without Python or SciPy. The package is found next to the executable."""
from __future__ import annotations

import os
import subprocess
import sys

import pytest
import yaml

import packsim
from fit_cells import pulse_frame


def _pulse_csv(path, rest: bool = True) -> str:
    pulse_frame(rest).to_csv(path, index=False)
    return str(path)


def _env(**changes):
    env = dict(os.environ)
    for k, v in changes.items():
        if v is None:
            env.pop(k, None)
        else:
            env[k] = v
    return env


def test_cli_writes_preset_and_report_without_pythonpath(cli, tmp_path):
    data = _pulse_csv(tmp_path / "pulses.csv")
    out, png = tmp_path / "cell.yaml", tmp_path / "fit.png"
    # no PYTHONPATH: the package is found next to the executable (<build>/python)
    p = subprocess.run([str(cli), "fit", data, "-o", str(out), "--capacity-Ah", "2", "--soc-grid", "0.9:0.05:1",
                        "--rc-pairs", "1", "--report", str(png)], capture_output=True, text=True, cwd=tmp_path,
                       env=_env(PYTHONPATH=None, PACKSIM_PYTHONPATH=None))
    assert p.returncode == 0, p.stderr
    assert "pulses.csv: 600 samples, RMS" in p.stdout
    cell = yaml.safe_load(out.read_text())
    assert cell["capacity_Ah"] == 2
    assert cell["rc_pairs"][0]["tau_s"] == pytest.approx(20.0, rel=0.05)
    assert png.stat().st_size > 10000


def test_cli_bad_input_exits_2_and_writes_nothing(cli, tmp_path):
    data = _pulse_csv(tmp_path / "norest.csv", rest=False)
    out = tmp_path / "cell.yaml"
    p = subprocess.run([str(cli), "fit", data, "-o", str(out), "--capacity-Ah", "2", "--report",
                        str(tmp_path / "fit.png")], capture_output=True, text=True)
    assert p.returncode == 2
    assert "norest.csv: no rest" in p.stderr
    assert sorted(f.name for f in tmp_path.iterdir()) == ["norest.csv"]


def test_cli_missing_output_folder_exits_2_before_fitting(cli, tmp_path):
    data = _pulse_csv(tmp_path / "pulses.csv")
    p = subprocess.run([str(cli), "fit", data, "-o", str(tmp_path / "no" / "cell.yaml")], capture_output=True, text=True)
    assert p.returncode == 2 and "no such folder" in p.stderr


@pytest.mark.parametrize("flags", [["-o", "{data}"], ["-o", "{out}", "--report", "{data}"],
                                   ["-o", "{out}", "--validate", "{held}", "--bpx", "{held}"],
                                   ["-o", "{out}", "--report", "{out}"]])
def test_cli_never_writes_over_its_own_test_data(cli, tmp_path, flags):
    # Was: `packsim fit pulses.csv -o pulses.csv` replaced the test with the preset and
    # `--report pulses.csv` with a PNG, exit 0; two options naming one file, the later won.
    data = _pulse_csv(tmp_path / "pulses.csv")
    held = _pulse_csv(tmp_path / "held.csv")
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    names = {"data": data, "held": held, "out": str(tmp_path / "cell.yaml")}
    p = subprocess.run([str(cli), "fit", data, "--capacity-Ah", "2", "--rc-pairs", "1",
                        *[f.format(**names) for f in flags]], capture_output=True, text=True)
    assert p.returncode == 2, p.stderr
    assert "is an input" in p.stderr or "name the same file" in p.stderr, p.stderr
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before


def test_cli_argument_errors_exit_2(cli, tmp_path):
    p = subprocess.run([str(cli), "fit", "-o", str(tmp_path / "x.yaml")], capture_output=True, text=True)
    assert p.returncode == 2 and "required: data" in p.stderr
    p = subprocess.run([str(cli), "fit", "a.csv", "-o", "x.yaml", "--form", "spline"], capture_output=True, text=True)
    assert p.returncode == 2 and "invalid choice: 'spline'" in p.stderr


def test_cli_without_python_exits_2(cli, tmp_path):
    p = subprocess.run([str(cli), "fit", "a.csv", "-o", "x.yaml"], capture_output=True, text=True,
                       env=_env(PACKSIM_PYTHON=str(tmp_path / "no-python")))
    assert p.returncode == 2
    assert "needs Python 3 with the packsim package, NumPy and SciPy: cannot run" in p.stderr


def test_cli_without_scipy_exits_2(cli, tmp_path):
    fake = tmp_path / "shadow" / "scipy"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text("raise ImportError('No module named scipy (hidden by the test)')\n")
    p = subprocess.run([str(cli), "fit", "a.csv", "-o", "x.yaml"], capture_output=True, text=True,
                       env=_env(PYTHONPATH=str(tmp_path / "shadow")))
    assert p.returncode == 2
    assert "needs Python 3 with the packsim package, NumPy and SciPy" in p.stderr
    assert "hidden by the test" in p.stderr


def test_python_m_packsim_fit(tmp_path):
    data = _pulse_csv(tmp_path / "pulses.csv")
    here = os.path.dirname(os.path.dirname(os.path.abspath(packsim.__file__)))
    p = subprocess.run([sys.executable, "-m", "packsim", "fit", data, "-o", str(tmp_path / "c.yaml"), "-q",
                        "--capacity-Ah", "2", "--rc-pairs", "0"], capture_output=True, text=True,
                       env=_env(PYTHONPATH=here, MPLBACKEND="Agg"))
    assert p.returncode == 0, p.stderr
    assert p.stdout == ""
    assert yaml.safe_load((tmp_path / "c.yaml").read_text())["capacity_Ah"] == 2
    p = subprocess.run([sys.executable, "-m", "packsim", "fitt"], capture_output=True, text=True,
                       env=_env(PYTHONPATH=here))
    assert p.returncode == 2 and "did you mean 'fit'" in p.stderr

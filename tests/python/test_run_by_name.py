"""Bundled scenarios by name from any folder (`packsim run NAME`, `packsim.run("NAME")`,
`packsim list`, `python -m packsim`) and one-off `--set` overrides that are the same
override paths as Python's."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

import packsim
from stored import assert_as_stored

SHORT = "bench_6s_ncr18650_2C"  # a bundled scenario that runs in about a second


def _outside_env() -> dict[str, str]:
    # Nothing points the program at the scenarios: it finds them itself.
    return {k: v for k, v in os.environ.items() if k not in ("PACKSIM_SCENARIOS", "PACKSIM_PYTHONPATH")}


def test_list_names_every_bundled_scenario_and_cell_with_its_description(cli, tmp_path):
    done = subprocess.run([str(cli), "list"], capture_output=True, text=True, cwd=tmp_path, env=_outside_env())
    assert done.returncode == 0, done.stderr
    root = Path(packsim.bundled_scenario_dir())
    scenario_files = [p for p in root.rglob("*.yaml") if p.parent.name != "cells"]
    cell_files = list((root / "cells").glob("*.yaml"))
    assert scenario_files and cell_files
    listed = {line.split()[0]: line.split(None, 1)[1] for line in done.stdout.splitlines()
              if line.startswith("  ") and len(line.split()) > 1}

    def leading_comment(p):
        text = []
        for line in p.read_text().splitlines():
            if not line.startswith("#") or not line.strip("# "):
                break
            text.append(line.strip("# "))
        return " ".join(text)

    for p in scenario_files + cell_files:
        desc = yaml.safe_load(p.read_text()).get("description") if p.parent.name != "cells" else None
        if desc:
            assert listed[p.stem] == desc, p.stem
        else:  # the leading comment's first sentence
            assert len(listed[p.stem]) > 20 and leading_comment(p).startswith(listed[p.stem]), p.stem
    # The Python view lists the same rows.
    rows = packsim.list_bundled()
    assert {r["name"] for r in rows if r["kind"] == "scenario"} == {p.stem for p in scenario_files}
    assert {r["name"] for r in packsim.list_bundled("cell")} == {p.stem for p in cell_files}


def test_run_by_name_from_another_folder_equals_running_the_file(cli, tmp_path):
    path = packsim.bundled_scenarios(f"{SHORT}.yaml")[0]
    done = subprocess.run([str(cli), "run", SHORT, "-o", "by_name.h5", "-q"], capture_output=True, text=True,
                          cwd=tmp_path, env=_outside_env())
    assert done.returncode == 0, done.stderr
    subprocess.run([str(cli), "run", path, "-o", str(tmp_path / "by_path.h5"), "-q"], check=True)
    by_name, by_path = packsim.load(tmp_path / "by_name.h5"), packsim.load(tmp_path / "by_path.h5")
    assert by_name.scenario_yaml == by_path.scenario_yaml and by_name.keys() == by_path.keys()
    for k in by_path.keys():
        if by_path[k].dtype.names is None:
            assert by_name[k].tobytes() == by_path[k].tobytes(), k
    # Python, from a folder holding no scenarios: the same run.
    here = os.getcwd()
    try:
        os.chdir(tmp_path)
        r = packsim.run(SHORT)
    finally:
        os.chdir(here)
    assert_as_stored(packsim.load(tmp_path / "by_name.h5"), r)


def test_unknown_name_suggests_the_closest(cli, tmp_path):
    done = subprocess.run([str(cli), "run", "motorcycle_110", "-q"], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 2 and "did you mean 'motorcycle_110s'" in done.stderr, done.stderr
    assert not list(tmp_path.rglob("*.h5"))
    with pytest.raises(ValueError, match="did you mean 'motorcycle_110s'"):
        packsim.run("motorcycle_110")
    with pytest.raises(FileNotFoundError):
        packsim.run("no_such_file.yaml")


def test_set_overrides_are_the_python_overrides(cli, tmp_path):
    path = packsim.bundled_scenarios("eco_marathon_12s.yaml")[0]
    out = tmp_path / "set.h5"
    done = subprocess.run([str(cli), "run", "eco_marathon_12s", "-o", str(out), "-q", "--set",
                           "pack.cell.capacity_Ah=2.5", "--set", "load.laps=2"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    f = packsim.load(out)
    r = packsim.run(path, {"pack.cell.capacity_Ah": 2.5, "load.laps": 2})
    assert f.scenario_yaml == r.scenario_yaml
    stored = yaml.safe_load(f.scenario_yaml)
    assert stored["pack"]["cell"]["capacity_Ah"] == 2.5 and stored["load"]["laps"] == 2
    assert_as_stored(f, r)
    # and the override changed the run
    assert f.n_samples < packsim.run(path).n_samples  # 2 laps of 10


@pytest.mark.parametrize("arg, needle", [("capacity_Ah", "expected KEY=VALUE"),
                                          ("pack.cell.capacty_Ah=4.5", "capacity_Ah")])
def test_bad_set_is_one_clear_error(cli, tmp_path, arg, needle):
    done = subprocess.run([str(cli), "run", SHORT, "-o", str(tmp_path / "x.h5"), "--set", arg],
                          capture_output=True, text=True)
    assert done.returncode == 2 and needle in done.stderr, done.stderr
    assert not list(tmp_path.iterdir())


def test_python_dash_m_packsim_runs_the_command(tmp_path):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    done = subprocess.run([sys.executable, "-m", "packsim", "list"], capture_output=True, text=True, cwd=tmp_path,
                          env=env)
    assert done.returncode == 0, done.stderr
    assert "motorcycle_110s" in done.stdout and "ncr18650_3p1Ah" in done.stdout


def test_python_dash_m_packsim_runs_the_python_commands_in_process(tmp_path):
    # export / report / plot are Python: `python -m packsim` runs them itself (the program
    # hands them to `python -m packsim.<module>`, so they must never go back to it).
    from packsim.__main__ import PYTHON_COMMANDS, main
    assert {"export", "report", "plot"} <= set(PYTHON_COMMANDS)
    src = tmp_path / "r.h5"
    packsim.run(SHORT).save(src)
    assert main(["export", str(src), "--format", "csv", "-o", str(tmp_path / "csv")]) == 0
    assert (tmp_path / "csv" / "samples.csv").is_file()

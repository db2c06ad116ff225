"""Seed corpora for the fuzz harnesses, from the bundled files (scripts/fuzz.sh).

Scenario inputs are file sets in the harness's format (tests/fuzz/fuzz_scenario.cpp):
a.yaml, then "#---" and b.yaml, then "#---" and cells/c.yaml; a bundled scenario that
extends another is rewritten to extend b.yaml holding that other one.
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCEN = ROOT / "scenarios"
SEP = "\n#---\n"


def write(out: pathlib.Path, harness: str, name: str, text: str) -> None:
    d = out / harness
    d.mkdir(parents=True, exist_ok=True)
    (d / f"seed_{name}").write_text(text)


def scenario_seeds(out: pathlib.Path) -> None:
    cells = sorted((SCEN / "cells").glob("*.yaml"))
    for f in sorted(SCEN.rglob("*.yaml")):
        if f.parent.name in ("cells", "profiles"):
            continue
        text = f.read_text()
        text = re.sub(r"csv: *\S+", "csv: profiles/lap.csv", text)
        m = re.search(r"^extends: *(\S+)", text, re.M)
        parts = [text]
        if m:
            base = (f.parent / m.group(1)).resolve()
            parts = [text.replace(m.group(0), "extends: b.yaml"),
                     re.sub(r"csv: *\S+", "csv: profiles/lap.csv", base.read_text())]
        rel = "_".join(f.relative_to(SCEN).with_suffix("").parts)
        write(out, "fuzz_scenario", rel, SEP.join(parts))
        write(out, "fuzz_overrides", rel, "seed=3\npack.cell.capacity_Ah=4.5\n" + SEP + parts[-1])
    # A preset cell block overridden field by field, and a cycle through b.yaml.
    write(out, "fuzz_scenario", "preset_c", "extends: base.yaml\npack: {cell: {preset: c, capacity_Ah: 4}}"
          + SEP + "" + SEP + cells[0].read_text())
    write(out, "fuzz_scenario", "cycle", "extends: b.yaml\n" + SEP + "extends: a.yaml\n")
    write(out, "fuzz_overrides", "paths", "pack.cell.rc_pairs[0].r_ohm=0.004\nbms.protections={}\nload.laps=3\n")
    for f in sorted((SCEN / "profiles").glob("*.csv")):
        write(out, "fuzz_csv_profile", f.stem, f.read_text())
    write(out, "fuzz_csv_profile", "power", "time_s,power_W\n0,10\n5,20\n")
    sweeps = list((ROOT / "examples").rglob("*sweep*.yaml")) + list((ROOT / "tests").rglob("*sweep*.yaml"))
    for f in sweeps:
        text = re.sub(r"^base: *\S+", "base: base.yaml", f.read_text(), flags=re.M)
        write(out, "fuzz_sweep", f.stem, text)
    write(out, "fuzz_sweep", "grid_zip_mc",
          "name: s\nbase: base.yaml\noutput_dir: out\nthreads: 2\n"
          "grid: {pack.cell.capacity_Ah: [4, 5], bms.tick_ms: [10, 100]}\n"
          "zip: {pack.initial_soc: [0.9, 0.8], ambient.temp_C: [20, 35]}\n"
          "monte_carlo: {samples: 3, master_seed: 7}\n")


if __name__ == "__main__":
    scenario_seeds(pathlib.Path(sys.argv[1]))

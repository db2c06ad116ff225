"""docs/results.md lists every dataset the writer produces (with its type), every enum
value and every fault bit: run each bundled scenario briefly and compare, so the page
cannot drift from the writer. Every row of the result-channel table
(core/sim/result_channels.hpp, packsim._packsim.result_channels()) has its line with
its shape, type and unit, and every documented dataset is a channel."""
from __future__ import annotations

import re
from pathlib import Path

import h5py
import pytest

import packsim
from h5_tree import datasets as h5_datasets

DOC = (Path(__file__).resolve().parents[2] / "docs" / "results.md").read_text()
ROWS = [line for line in DOC.splitlines() if line.startswith("| `/")]
CHANNELS = packsim._packsim.result_channels()
# The doc's shape column by the channel's second axis, and its spelling of units.
SHAPE = {"": "[n]", "cell": "[n, cells]", "series": "[n, series]", "thermistor": "[n, thermistors]",
         "device": "[n, devices]", "telemetry_byte": "[n, 33]"}
DOC_UNIT = {"degC": "°C", "0.1 degC": "0.1 °C"}


def _bundled():
    return [p for p in packsim.bundled_scenarios("**/*.yaml") if "/cells/" not in p]


def _row_of(path: str) -> str | None:
    for row in ROWS:
        if f"`/{path}`" in row.split("|")[1]:
            return row
    return None


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """Every dataset path -> (dtype, attrs), over all bundled scenarios run for 3 s."""
    out: dict[str, tuple] = {}
    kinds: set[str] = set()
    folder = tmp_path_factory.mktemp("doc")
    for i, scenario in enumerate(_bundled()):
        r = packsim.run(scenario, {"run.duration_s": 3})
        kinds |= {e["kind"] for e in r.events}
        f = folder / f"{i}.h5"
        r.save(f)
        with h5py.File(f, "r") as h:
            for path, o in h5_datasets(h):
                out[path] = (o.dtype, {a: o.attrs[a] for a in o.attrs})
            out["/bms attrs"] = (None, dict(h["bms"].attrs))
    return out, kinds


def test_every_dataset_is_documented_with_its_type(written):
    datasets, _ = written
    assert len(_bundled()) >= 10
    missing, wrong = [], []
    for path, (dtype, _) in datasets.items():
        if dtype is None:
            continue
        # the hard links of /time_s into each group are documented with the scales
        row = _row_of(path) or (_row_of("time_s") if path.endswith("/time_s") else None)
        if row is None and re.search(rf"`/{re.escape(path)}`", DOC):
            continue  # a dimension scale, listed in the layout table
        if row is None:
            missing.append(path)
        elif dtype.names is None and path.split("/")[0] != "time_s" and str(dtype) not in row:
            wrong.append(f"{path}: {dtype}")
    assert not missing, f"datasets missing from docs/results.md: {missing}"
    assert not wrong, f"types docs/results.md gets wrong: {wrong}"


def test_every_enum_value_and_fault_bit_is_documented(written):
    datasets, kinds = written
    for path, (_, attrs) in datasets.items():
        names = attrs.get("names")
        if names is None:
            continue
        names = names.decode() if isinstance(names, bytes) else str(names)
        for pair in names.split(","):
            assert f"`{pair}`" in _row_of(path), f"{path}: {pair} not in docs/results.md"
    bits = datasets["/bms attrs"][1]["fault_bits"]
    bits = bits.decode() if isinstance(bits, bytes) else str(bits)
    for i, name in enumerate(bits.split(",")):
        assert f"{i} `{name}`" in DOC, f"fault bit {i} {name} not in docs/results.md"
    events_row = _row_of("events")
    for kind in kinds:
        assert f"`{kind}`" in events_row, f"event kind {kind} not in docs/results.md"


def test_the_channel_table_is_complete_and_consistent():
    paths = [c["path"] for c in CHANNELS]
    assert len(paths) == len(set(paths)) >= 40
    for c in CHANNELS:
        group = c["path"].rsplit("/", 1)[0]
        assert group in ("", "/truth", "/measured", "/bms", "/hardware", "/vehicle"), c
        assert c["axis"] in SHAPE and c["long_name"], c


@pytest.mark.parametrize("channel", CHANNELS, ids=lambda c: c["path"])
def test_every_channel_is_documented_with_shape_type_and_unit(channel):
    row = _row_of(channel["path"][1:])
    assert row is not None, f"{channel['path']} missing from docs/results.md"
    cells = [c.strip() for c in row.split("|")]
    assert cells[2] == f"{SHAPE[channel['axis']]} {channel['dtype']}", row
    if channel["units"] is not None:
        unit = DOC_UNIT.get(channel["units"], channel["units"])
        assert re.match(rf"{re.escape(unit)}(?![A-Za-z0-9])", cells[3]), f"{channel['path']}: doc should start with {unit!r}"


def test_every_documented_dataset_is_a_channel():
    tables = {"/events", "/bus_trace", "/can_trace", "/summary", "/vehicle/stages", "/vehicle/laps"}  # tables and attributes, not time series
    known = {c["path"] for c in CHANNELS} | tables
    table = DOC.split("## Datasets", 1)[1].split("\n## ", 1)[0]  # not the dimension scales' table
    documented = {row.split("|")[1].strip().strip("`") for row in table.splitlines() if row.startswith("| `/")}
    assert len(documented) >= 40
    assert documented - known == set(), "docs/results.md lists datasets the channel table does not have"


def _names(result, path):
    raw = result.attrs[path]["names"]
    raw = raw.decode() if isinstance(raw, bytes) else str(raw)
    return {pair.split("=", 1)[1] for pair in raw.split(",")}


def test_event_details_use_the_names_of_the_enum_attributes():
    # bms/bms_names.hpp is the one spelling: events and `names` attributes agree.
    r = packsim.run(packsim.bundled_scenario_dir() + "/balance/bench_6s_balancing.yaml", {"run.duration_s": 30})
    states, phases, status = _names(r, "bms/state"), _names(r, "bms/precharge_phase"), _names(r, "bms/balance_status")
    seen = set()
    for e in r.events:
        if e["kind"] == "bms_state":
            assert set(e["detail"].split(" -> ")) <= states, e
        elif e["kind"] == "precharge":
            assert e["detail"].split(" (")[0] in phases, e
        elif e["kind"] == "balancing":
            assert e["detail"] in status, e
        else:
            continue
        seen.add(e["kind"])
    assert seen >= {"bms_state", "balancing"}

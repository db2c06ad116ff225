"""output.bus_trace from Python: the /bus_trace table of the result, as docs/results.md
describes it, and nothing of it without the key."""
from __future__ import annotations

from pathlib import Path

import pytest

import packsim

DOC = (Path(__file__).resolve().parents[2] / "docs" / "results.md").read_text()


def test_the_trace_is_a_documented_table_readable_from_python():
    r = packsim.run("formula_student_96s", {"run.duration_s": 0.5, "output.bus_trace": True})
    tr = r.bus_trace
    assert len(tr) > 10
    row = next(line for line in DOC.splitlines() if line.startswith("| `/bus_trace`"))
    for field in tr.dtype.names:  # every column is documented
        assert f"`{field}`" in row, field
    outs = [t for t in tr if t["direction"] == "out"]
    rdcva = [t for t in outs if t["what"] == "RDCVA"]
    assert rdcva and all(t["bytes"].startswith("00 04") for t in rdcva)  # the data sheet's command code
    assert set(tr["direction"]) == {"out", "in"}
    df = r.to_dataframe("bus_trace")
    assert list(df.columns) == list(tr.dtype.names) and len(df) == len(tr)


def test_without_the_key_there_is_no_trace():
    r = packsim.run("formula_student_96s", {"run.duration_s": 0.2})
    with pytest.raises(KeyError, match="output.bus_trace"):
        r.bus_trace

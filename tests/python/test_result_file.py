"""Results never overwrite an input (issue 28): ``Result.save`` refuses the scenario file
it was run from (ValueError naming both), as ``packsim run -o`` does (exit 2)."""
from __future__ import annotations

import pytest

import packsim


def test_save_refuses_the_scenario_file(tmp_path, simple_yaml):
    scenario = tmp_path / "s.yaml"
    scenario.write_text(simple_yaml)
    r = packsim.run(str(scenario))
    with pytest.raises(ValueError, match="is the scenario"):
        r.save(scenario)
    assert scenario.read_text() == simple_yaml
    r.save(tmp_path / "out.h5")
    assert packsim.load(tmp_path / "out.h5").summary["duration_s"] == r.summary["duration_s"]

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


def test_a_value_within_one_step_of_zero_is_stored_as_zero(tmp_path):
    """docs/results.md, "Storage and resolution": a float channel reads back within half
    its step of the simulated value, but for values within one step of 0, which read back
    as exactly 0 (HDF5's scale-offset filter stores its fill value, 0, for them). The
    documentation said "within half a step" for every value: a 7 µA load (0.7 of the
    10 µA step) reads back as 0 A, 7 µA off."""
    import h5py
    r = packsim.run("name: tiny\npack: {series: 2, cell: {preset: lipo_5Ah}}\n"
                    "load: {current_A: 0.000007}\nrun: {duration_s: 5}\n")
    r.save(tmp_path / "tiny.h5")
    held = r["truth/pack_current_A"]
    with h5py.File(tmp_path / "tiny.h5") as f:
        stored = f["truth/pack_current_A"][()]
        step = f["truth/pack_current_A"].attrs["resolution"]
    assert step == 1e-5 and held.max() == 7e-6
    assert (stored == 0.0).all()  # not 1e-5: more than half a step off where held is 7 µA


def test_each_groups_cells_carry_the_pack_and_balancing_current_recorded():
    """Kirchhoff at each series group's terminals, in the record: its cells' currents sum
    to the pack current plus its /truth/balance_current_A. With an active balancer whose
    supercap bus precharges from the whole stack (solar_4s3p_active, the first second:
    about 5.3 A from every group through 2.2 ohm), the cells carried 5.3 A while the pack
    and every balancing current read 0 A: the precharge current was in no dataset (found
    by the campaign's record oracle run on the bundled scenarios)."""
    import numpy as np
    r = packsim.run("solar_4s3p_active", {"output.interval_s": 1.0, "run.duration_s": 20})
    n = r.n_samples
    cells = np.asarray(r["truth/cell_current_A"]).reshape(n, 4, 3).sum(axis=2)
    pack = np.asarray(r["truth/pack_current_A"])[:, None]
    bal = np.asarray(r["truth/balance_current_A"])
    assert bal[1].min() > 5.0  # the precharge, drawn from every group alike
    np.testing.assert_allclose(cells, pack + bal, rtol=0, atol=1e-9)

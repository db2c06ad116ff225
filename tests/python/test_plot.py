"""packsim.plot draws every figure from a Result or a file, picks lines or a heatmap
by pack size, and draws the balancing map only when there is a balance mask."""
from __future__ import annotations

import numpy as np
import pytest

import packsim
from packsim import plot
from packsim.result import Result


def _with(r: Result, extra: dict) -> Result:
    d = r.datasets
    d.update(extra)
    return Result(d, r.attrs)


def test_plot_all_writes_pngs(race, tmp_path):
    paths = plot.plot_all(race, tmp_path)
    names = sorted(p.rsplit("_", 1)[-1] for p in paths)
    # the default race carries its balancing hardware (idle while racing): six figures
    assert len(paths) == 6 and any(p.endswith("_balancing.png") for p in paths), names
    for p in paths:
        with open(p, "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    assert any(p.endswith("_bms_timeline.png") for p in paths), names


def test_plot_all_names_a_bad_argument(race):
    # Was "expected str, bytes or os.PathLike object, not int" for the folder, and a dpi
    # of 0 reached matplotlib.
    with pytest.raises(TypeError, match="outdir must be a path, got int"):
        plot.plot_all(race, 5)
    with pytest.raises(ValueError, match="dpi must be >= 1, got 0"):
        plot.plot_all(race, ".", dpi=0)


def test_lines_for_small_packs_heatmap_for_large(race, simple_yaml):
    fig = plot.cells(race, "voltage")
    ax = fig.axes[0]
    cell_lines = [line for line in ax.lines if len(line.get_ydata()) == race.n_samples]
    assert len(cell_lines) == race.n_cells and not ax.images  # plus limit and event lines
    drawn = {line.get_ydata().tobytes() for line in cell_lines}
    assert race["truth/cell_voltage_V"][:, 4].copy().tobytes() in drawn
    big = packsim.run(simple_yaml, {"pack.series": 30, "hardware.thermistors.at_groups": [1, 30]})
    fig = plot.cells(big, "temperature")
    ax = fig.axes[0]
    assert not [line for line in ax.lines if len(line.get_ydata()) == big.n_samples] and len(ax.images) == 1
    assert ax.images[0].get_array().shape == (30, big.n_samples)
    with pytest.raises(ValueError, match="quantity must be one of"):
        plot.cells(race, "pressure")


def test_timeline_shows_actuators_and_faults(race):
    fig = plot.bms_timeline(race)
    labels = [t.get_text() for t in fig.axes[1].get_yticklabels()]
    assert {"relay: commanded", "discharge fet: commanded", "charge fet: commanded"} <= set(labels)
    assert {"relay: contact (hardware)", "discharge fet: conducting (hardware)"} <= set(labels)
    latched = [n for n, v in race.faults("latched").items() if v.any()]
    assert all(f"fault: {n}" in labels for n in latched)


def test_balancing_map_only_with_a_mask(race):
    without = race.datasets
    del without["bms/balance_mask"]
    assert plot.balancing(Result(without, race.attrs)) is None
    n = race.n_samples
    mask = np.zeros(n, dtype=np.uint32)
    mask[n // 2:] = 0b101  # cells 1 and 3 balance during the second half
    fig = plot.balancing(_with(race, {"bms/balance_mask": mask}))
    img = fig.axes[0].images[0].get_array()
    assert img.shape == (race.n_series, n)
    assert img[0, -1] and not img[1, -1] and img[2, -1] and not img[0, 0]
    duty = [b.get_width() for b in fig.axes[1].patches]
    assert duty[0] == pytest.approx(100.0 * (n - n // 2) / n) and duty[1] == 0.0


def test_plots_accept_a_file_path(race, tmp_path):
    p = tmp_path / "r.h5"
    race.save(p)
    assert plot.current_soc(p).axes
    with pytest.raises(TypeError):
        plot.current_soc(3)


def test_module_main(race, tmp_path, capsys):
    p = tmp_path / "r.h5"
    race.save(p)
    assert plot.main([str(p), "-o", str(tmp_path / "out"), "--dpi", "50"]) == 0
    assert len(capsys.readouterr().out.split()) == 6  # with the balancing map (system A has the hardware)
    assert plot.main([str(tmp_path / "missing.h5")]) == 2

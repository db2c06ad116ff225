"""The fit report figure: per test, measured and model voltage over time, and the residual."""
from __future__ import annotations

__all__ = ["report_figure"]


def report_figure(fit):
    """A matplotlib Figure (no pyplot state): two stacked axes per test."""
    try:
        from matplotlib.figure import Figure
    except ImportError as e:
        raise ImportError("the fit report needs matplotlib (pip install matplotlib)") from e
    n = len(fit.files)
    fig = Figure(figsize=(10.0, 4.2 * n), layout="constrained")
    axes = fig.subplots(2 * n, 1, squeeze=False, gridspec_kw={"height_ratios": [3, 1] * n})[:, 0]
    for k, f in enumerate(fit.files):
        top, bottom = axes[2 * k], axes[2 * k + 1]
        hours = f.time_s[-1] - f.time_s[0] > 3 * 3600
        t = (f.time_s - f.time_s[0]) / (3600.0 if hours else 1.0)
        at = "" if f.temp_C is None else f" at {f.temp_C:.1f} °C"
        top.plot(t, f.voltage_V, lw=1.0, label="measured")
        top.plot(t, f.model_V, lw=1.0, ls="--", label="model")
        top.set_ylabel("voltage (V)")
        top.set_title(f"{f.name}{at}: RMS {f.rms_mV:.2f} mV, max {f.max_mV:.2f} mV")
        top.legend(loc="best")
        bottom.plot(t, 1e3 * (f.model_V - f.voltage_V), lw=0.8, color="C3")
        bottom.axhline(0.0, color="0.5", lw=0.5)
        bottom.set_ylabel("model − measured (mV)")
        bottom.set_xlabel("time (h)" if hours else "time (s)")
    return fig

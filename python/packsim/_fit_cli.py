"""``packsim fit`` / ``python -m packsim fit``: test CSVs in, a cell preset YAML out.

    packsim fit hppc.csv cc_1C.csv -o cells/my_cell.yaml --rc-pairs 2 --report fit.png

Exit status 2 for bad input (arguments, data) or a fit that failed; the preset (and the
report) is written only when the fit succeeded.
"""
from __future__ import annotations

import argparse
import os
import sys
import warnings

__all__ = ["main"]


def _numbers(text: str) -> list[float]:
    try:
        return [float(p) for p in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}': expected comma-separated numbers") from None


def _columns(text: str) -> dict[str, str]:
    pairs = {}
    for item in text.split(","):
        ours, sep, theirs = item.partition("=")
        if not sep or not ours.strip() or not theirs.strip():
            raise argparse.ArgumentTypeError(f"'{item}': expected OURS=THEIRS, e.g. voltage_V=Voltage(V)")
        pairs[ours.strip()] = theirs.strip()
    return pairs


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="packsim fit", description="Fit a cell preset (OCV, R0, RC pairs) to test data: "
                                "CSV files with time_s,current_A,voltage_V[,temp_C], positive current discharging.")
    p.add_argument("data", nargs="+", help="test CSV files (constant-current discharges, pulse/HPPC tests with rests)")
    p.add_argument("-o", "--output", required=True, help="the cell preset YAML to write (e.g. cells/my_cell.yaml)")
    p.add_argument("--rc-pairs", type=int, default=2, help="number of RC pairs, 0..4 (default 2)")
    p.add_argument("--soc-grid", help="SOC nodes of the tables: start:step:stop or a,b,c (default: every 0.05, "
                   "and 0.01,0.02,0.035,0.075 near empty)")
    p.add_argument("--form", choices=("table", "poly"), default="table",
                   help="R0 as a table over SOC (default) or a polynomial over discharged Ah")
    p.add_argument("--poly-order", type=int, default=5, help="order of the R0 polynomial with --form poly (default 5)")
    p.add_argument("--rc-over-soc", action="store_true", help="RC resistances as tables over SOC (else constants)")
    p.add_argument("--capacity-Ah", type=float, help="cell capacity (default: measured, the most charge one test removes)")
    p.add_argument("--initial-soc", type=_numbers, default=[1.0],
                   help="SOC at the start of each test: one value or one per file (default 1)")
    p.add_argument("--temp-C", type=_numbers, help="temperature of each test (default: its first temp_C value)")
    p.add_argument("--columns", type=_columns, help="column names in the files, e.g. time_s=Time,voltage_V=U")
    p.add_argument("--invert-current", action="store_true", help="the files log discharge current as negative")
    p.add_argument("--steps-on-samples", action="store_true",
                   help="the files log each current step at the sample it happens at, that sample reading the "
                        "new current (packsim results, cyclers logging each step's start); default: steps fall "
                        "between samples (docs/fit.md)")
    p.add_argument("--max-evaluations", type=int, default=400,
                   help="model evaluations before the fit counts as not converged (default 400)")
    p.add_argument("--temperature-law", choices=("arrhenius", "table"), default="arrhenius",
                   help="tests more than 3 °C apart: one joint fit with Arrhenius laws, every sample at its "
                   "measured temp_C (default), or one fit per temperature written as 2-D tables")
    p.add_argument("--no-ocv-temperature", action="store_true",
                   help="one OCV for every temperature (default: with rests at several temperatures, the joint fit "
                        "fits the OCV's temperature coefficient dOCV/dT over SOC)")
    p.add_argument("--validate", action="append", metavar="CSV",
                   help="a held-out test (repeat for several): not fitted; its error is printed (RMS, max, below "
                   "10 %% SOC) and the tables' smoothness is chosen as the one with the lowest error on them")
    p.add_argument("--validate-initial-soc", type=_numbers, default=[1.0],
                   help="SOC at the start of each held-out test (default 1)")
    p.add_argument("--smoothing", type=float,
                   help="weight of the tables' second-difference penalty (default 0.1, or chosen by --validate)")
    p.add_argument("--report", help="write the fit report (measured vs model, residual) as this PNG")
    p.add_argument("--bpx", metavar="JSON", help="also write the cell as a BPX file (the Battery Parameter eXchange "
                   "format, the equivalent circuit in its User-defined section; needs the bpx package)")
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    return p


def main(argv: list[str]) -> int:
    args = parser().parse_args(argv)
    try:
        import numpy  # noqa: F401
        import scipy.optimize  # noqa: F401
    except ImportError as e:
        print(f"packsim fit: error: needs Python 3 with the packsim package, NumPy and SciPy (pip install numpy scipy): {e}",
              file=sys.stderr)
        return 2
    from ._inputs_kept import refuse_overwriting
    from .fit import FitError, fit
    n = len(args.data)
    try:
        refuse_overwriting({"-o": args.output, "--report": args.report, "--bpx": args.bpx},
                           list(args.data) + list(args.validate or []), FitError)
        for path in filter(None, (args.output, args.report, args.bpx)):  # fail before a long fit, not after it
            folder = os.path.dirname(os.path.abspath(path))
            if not os.path.isdir(folder):
                raise FitError(f"{path}: no such folder {folder}")
        with warnings.catch_warnings():  # printed below, once, as the CLI's own lines
            warnings.simplefilter("ignore")
            f = fit(args.data, capacity_Ah=args.capacity_Ah, rc_pairs=args.rc_pairs, soc_grid=args.soc_grid,
                    form=args.form, poly_order=args.poly_order, rc_over_soc=args.rc_over_soc,
                    initial_soc=args.initial_soc * n if len(args.initial_soc) == 1 else args.initial_soc,
                    temps_C=args.temp_C[0] if args.temp_C and len(args.temp_C) == 1 else args.temp_C,
                    columns=args.columns, invert_current=args.invert_current,
                    max_evaluations=args.max_evaluations, temperature_law=args.temperature_law,
                    validate=args.validate,
                    validate_initial_soc=(args.validate_initial_soc * len(args.validate or [])
                                          if len(args.validate_initial_soc) == 1 else args.validate_initial_soc),
                    smoothing=args.smoothing, ocv_temperature=False if args.no_ocv_temperature else None,
                    steps_on_samples=args.steps_on_samples)
        if args.report:
            try:
                f.plot(args.report)
            except ImportError as e:
                raise FitError(str(e)) from None
        bpx_doc = f.bpx() if args.bpx else None   # refused (a fit per temperature, R0 a polynomial) before any write
        f.save(args.output)
        if bpx_doc is not None:
            f.save_bpx(args.bpx)
    except FitError as e:
        print(f"packsim fit: error: {e}", file=sys.stderr)
        return 2
    for w in f.warnings:
        print(f"packsim fit: warning: {w}", file=sys.stderr)
    if not args.quiet:
        print(f.summary())
        print("wrote " + " and ".join(filter(None, (args.output, args.report, args.bpx))))
    return 0

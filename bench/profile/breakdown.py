#!/usr/bin/env python3
"""Groups a `perf report` flat profile (self time per symbol) into the parts of the
co-simulation step: plant, monitor ICs, firmware, recording and bookkeeping.

    perf record -o run.data build/packsim run SCENARIO --set run.solver=fast -o /tmp/x.h5 -q
    perf report -i run.data --no-children --sort sym --stdio | bench/profile/breakdown.py
"""
from __future__ import annotations

import re
import sys

# First match wins: (part, pattern on the demangled symbol).
PARTS = [
    ("firmware: SOC estimator (EKF)", r"bms::ekf|bms::soc"),
    ("firmware: frame CRC", r"bms::crc"),
    ("firmware: other (drivers, protections, balancing, scheduler)", r"bms::|FirmwareHost|McuFirmware|firmware"),
    ("monitor ICs: noise and ADC conversion", r"AdcChannel|standardNormal|mersenne|__sincos|__ieee754_log|Rng::|__log"),
    ("monitor ICs: chains, comparators, replies", r"Chain|Bq76|Pl455|Bq769|Monitor|Afe|monitor|Thermistor|CanBus"),
    ("plant: cell curves (OCV, R0 tables)", r"interpolateN|Curve::|curve"),
    ("plant: equations and fast integrator", r"Plant|Pack::|ecm::|FastIntegrator|Thermal|__ieee754_exp|__expm1|__exp|Balanc|Fet|Relay|Fuse|Contactor"),
    ("recording and run tracking", r"Recorder|record|RunTracker|Tracker|Stranded|result"),
    ("HDF5 writing", r"H5|hdf5|deflate|zlib|scaleoffset"),
    ("memory and C library", r"malloc|free|memcpy|memmove|memset|operator new|operator delete|_int_"),
]


def main() -> int:
    shares: dict[str, float] = {}
    unknown: list[tuple[float, str]] = []
    for line in sys.stdin:
        m = re.match(r"\s+([0-9.]+)%\s+(?:\[\.\]|\[k\])\s+(.*)$", line)
        if not m:
            continue
        pct, sym = float(m.group(1)), m.group(2).strip()
        part = next((name for name, pat in PARTS if re.search(pat, sym)), None)
        if part is None:
            part = "other"
            unknown.append((pct, sym))
        shares[part] = shares.get(part, 0.0) + pct
    total = sum(shares.values()) or 1.0
    print("| part | share |\n|---|---|")
    for name, _ in PARTS + [("other", "")]:
        if name in shares:
            print(f"| {name} | {100 * shares[name] / total:.0f} % |")
    if "-v" in sys.argv:
        for pct, sym in sorted(unknown, reverse=True)[:15]:
            print(f"  other: {pct:5.2f}% {sym}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

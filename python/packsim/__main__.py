"""``python -m packsim fit ...``: the commands of the packsim package that live in Python
(``packsim fit`` of the command line runs this). Exit status: 0 success, 2 bad input or a
fit that failed (nothing written), 1 anything else."""
from __future__ import annotations

import sys

COMMANDS = ("fit",)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] not in COMMANDS:
        got = f"'{argv[0]}'" if argv else "nothing"
        print(f"usage: python -m packsim {{{','.join(COMMANDS)}}} ...: got {got}", file=sys.stderr)
        return 2
    from ._fit_cli import main as fit_main
    return fit_main(argv[1:])


if __name__ == "__main__":
    sys.exit(main())

"""The ``packsim`` command: ``packsim run motorcycle_110s``, ``python -m packsim list``.

pip installs this as the ``packsim`` console script. It runs the command-line program
shipped inside the package (``packsim/_bin/packsim``, built from the same C++ core as
the extension), telling it to use this interpreter and this package for the commands
that live in Python (plot, export, report, fit). Nothing is found through paths compiled
into the program.
"""
from __future__ import annotations

import importlib
import os
import sys

_PKG = os.path.dirname(os.path.abspath(__file__))

# Subcommands whose work is Python (the program itself runs `python -m packsim.<module>`
# for them): run here, in this interpreter, without the program. Every other
# subcommand goes to the program. A subcommand the program hands back to
# `python -m packsim ...` must be in this table, or the two would call each other.
PYTHON_COMMANDS = {"export": "packsim.export", "report": "packsim.report", "plot": "packsim.plot",
                   "fit": "packsim._fit_cli"}


def program() -> str:
    """Path of the bundled command-line program."""
    return os.path.join(_PKG, "_bin", "packsim")


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else list(argv)
    if args and args[0] in PYTHON_COMMANDS:
        return importlib.import_module(PYTHON_COMMANDS[args[0]]).main(args[1:])
    exe = program()
    if not os.access(exe, os.X_OK):
        sys.stderr.write(f"packsim: error: the command-line program is missing from the package ({exe}); "
                         "reinstall packsim with `pip install .`\n")
        return 1
    env = dict(os.environ)
    env.setdefault("PACKSIM_PYTHON", sys.executable)
    env.setdefault("PACKSIM_PYTHONPATH", os.path.dirname(_PKG))
    scenarios = os.path.join(_PKG, "scenarios")
    if os.path.isdir(scenarios):
        env.setdefault("PACKSIM_SCENARIOS", scenarios)
    args = [exe] + args
    sys.stdout.flush()
    sys.stderr.flush()
    os.execve(exe, args, env)  # replaces this process: exit status and signals are the program's
    return 1  # not reached


if __name__ == "__main__":
    sys.exit(main())

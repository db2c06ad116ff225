"""Where `packsim export` may write: never over the user's own files.

A CSV export is a folder, replaced whole when it is written again. Replacing any folder
`-o` names deleted what was in it -- `-o .` the current folder, the result file
included. Now an existing folder is replaced only when it is an earlier CSV export
(its three files and other .csv files, nothing else), and no output may be the result
file itself.
"""
from __future__ import annotations

import os
import tempfile

from ._inputs_kept import refuse_overwriting

__all__ = ["ExportOutputError", "check_output", "temporary_name", "CSV_EXPORT_FILES"]

# What every CSV export folder holds (export._to_csv); its other files are .csv tables.
CSV_EXPORT_FILES = ("samples.csv", "events.csv", "summary.csv")


class ExportOutputError(ValueError):
    """The output names something an export must not replace (a bad argument: exit 2)."""


def _not_a_csv_export(folder: str) -> tuple[list[str], list[str]]:
    """What says `folder` is no earlier CSV export (empty lists: it is one, or empty):
    its entries that are not .csv files, and the export's own files it lacks."""
    entries = sorted(os.listdir(folder))
    if not entries:
        return [], []
    foreign = [e for e in entries if not (e.endswith(".csv") and os.path.isfile(os.path.join(folder, e)))]
    return foreign, [f for f in CSV_EXPORT_FILES if f not in entries]


def check_output(out: str, fmt: str, source: str | None) -> None:
    """ExportOutputError when writing `out` would replace the result file, a folder that
    is not an earlier CSV export, a file with a folder or a folder with a file."""
    refuse_overwriting({"-o": out}, [source] if source else [], ExportOutputError)
    if not os.path.lexists(out):
        return
    if fmt != "csv":
        if os.path.isdir(out):
            raise ExportOutputError(f"{out} is a folder: a {fmt} export is one file: give a file name")
        return
    if not os.path.isdir(out):
        raise ExportOutputError(f"{out} is a file: a CSV export writes a folder: give a folder name")
    here = os.path.realpath(os.getcwd())
    real = os.path.realpath(out)
    if here == real or here.startswith(real.rstrip(os.sep) + os.sep):
        raise ExportOutputError(f"{out} is the current folder or holds it: give the CSV export a folder of its own")
    foreign, missing = _not_a_csv_export(out)
    if foreign or missing:
        shown = ", ".join(foreign[:3]) + (f" and {len(foreign) - 3} more" if len(foreign) > 3 else "")
        raise ExportOutputError(
            f"{out} exists and is not an earlier CSV export ("
            + (f"it holds {shown}" if foreign else "no " + ", ".join(missing))
            + "): nothing written; a CSV export replaces its folder whole: give a new folder")


def temporary_name(out: str, fmt: str) -> str:
    """A name of its own beside `out` to write to (a folder for csv): concurrent exports
    and a failed one never touch another's files or `out`."""
    parent, base = os.path.split(os.path.abspath(out))
    if fmt == "csv":
        return tempfile.mkdtemp(prefix=f".{base}.tmp.", dir=parent)
    fd, path = tempfile.mkstemp(prefix=f".{base}.tmp.", suffix="." + fmt, dir=parent)
    os.close(fd)
    return path

"""Probe time series as CSV: one row per sample time, first column ``t``.

Numbers are written with ``'%.17g'`` so every float64 reads back bit for bit
(NaN as ``nan``, infinities as ``inf``/``-inf``). A 2D column ``name`` of
shape (n, k) becomes the k columns ``name_0 .. name_{k-1}``.
:class:`ProbeCSVWriter` appends and flushes row by row during a run, so a
crashed run keeps every row written, and can resume after a restart.
"""

import math
import os
import re

import numpy as np

from .vtk import _atomic_write

__all__ = ["write_probes_csv", "read_probes_csv", "ProbeCSVWriter"]

_SUFFIX = re.compile(r"^(.+)_(0|[1-9][0-9]*)$")


def _fmt(value):
    return "%.17g" % value


def _check_names(names, where):
    seen = set()
    for name in names:
        if not isinstance(name, str) or not name:
            raise ValueError(f"{where}: column names must be non-empty strings, got {name!r}")
        if any(c in name for c in ',"\r\n'):
            raise ValueError(f"{where}: column name {name!r} contains a comma, quote or newline")
        if name == "t" or name in seen:
            raise ValueError(f"{where}: duplicate column name {name!r} (\"t\" is the time column)")
        seen.add(name)


def write_probes_csv(path, times, columns):
    """Write ``times`` and the ``columns`` (name -> (n,) or (n, k)) as one CSV file.

    Written atomically (temporary file + rename). Values are stored as
    float64, so integers above 2**53 are not exact. Returns the path written.
    """
    path = os.fspath(path)
    times = np.asarray(times, dtype=np.float64)
    if times.ndim != 1:
        raise ValueError(f"{path}: times must be 1D, got shape {times.shape}")
    n = times.shape[0]
    names, blocks = [], [times[:, None]]
    for name, col in columns.items():
        col = np.asarray(col, dtype=np.float64)
        if col.ndim not in (1, 2) or col.shape[0] != n:
            raise ValueError(f"{path}: column {name!r} must have shape ({n},) or ({n}, k), "
                             f"got {col.shape}")
        if col.ndim == 1:
            names.append(name)
            blocks.append(col[:, None])
        else:
            names.extend(f"{name}_{j}" for j in range(col.shape[1]))
            blocks.append(col)
    _check_names(names, path)
    table = np.concatenate(blocks, axis=1)
    with _atomic_write(path, "w", encoding="utf-8", newline="") as fh:
        fh.write(",".join(["t", *names]) + "\n")
        for row in table.tolist():
            fh.write(",".join(map(_fmt, row)) + "\n")
    return path


def _parse_row(line, ncols, where):
    fields = line.split(",")
    if len(fields) != ncols:
        raise ValueError(f"{where}: expected {ncols} fields, found {len(fields)}")
    try:
        return [float(x) for x in fields]
    except ValueError:
        raise ValueError(f"{where}: non-numeric value in {line!r}") from None


def _read_lines(path):
    """Header names and data lines; a last line cut off mid-write is dropped."""
    with open(path, encoding="utf-8", newline="") as fh:
        text = fh.read()
    lines = text.split("\n")
    # Every complete line ends with "\n", so the last piece is either empty
    # or a partial row left by a crash.
    partial = lines.pop()
    lines = [ln.rstrip("\r") for ln in lines]
    if not lines:
        if partial:
            raise ValueError(f"{path}: no complete header line")
        raise ValueError(f"{path} is empty")
    header = lines[0].split(",")
    if header[0] != "t":
        raise ValueError(f"{path}: first column must be 't', found {header[0]!r}")
    return header, lines[1:], partial


def _merge_vectors(names, data):
    """Group consecutive columns ``base_0 .. base_{k-1}`` (k >= 2) into (n, k)."""
    out = {}
    i = 0
    while i < len(names):
        m = _SUFFIX.match(names[i])
        if m and m.group(2) == "0":
            base, j = m.group(1), i + 1
            while j < len(names) and names[j] == f"{base}_{j - i}":
                j += 1
            if j - i >= 2 and base not in names and base not in out:
                out[base] = np.stack([data[names[c]] for c in range(i, j)], axis=1)
                i = j
                continue
        out[names[i]] = data[names[i]]
        i += 1
    return out


def read_probes_csv(path, *, merge_vectors=True):
    """Read a probe CSV file; returns ``(times, {name: array})``.

    With ``merge_vectors`` (default), consecutive columns ``name_0 ..
    name_{k-1}`` with k >= 2 come back as one (n, k) array ``name``, undoing
    what :func:`write_probes_csv` does to 2D columns. A (n, 1) column comes
    back as the 1D column ``name_0``.
    """
    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(f"probe CSV file not found: {path}")
    header, lines, partial = _read_lines(path)
    rows = [_parse_row(ln, len(header), f"{path}, line {k + 2}")
            for k, ln in enumerate(lines) if ln]
    if partial:
        # Hand-written files may lack the final newline; a row cut off by a
        # crash usually has too few fields and is skipped.
        try:
            rows.append(_parse_row(partial, len(header), path))
        except ValueError:
            pass
    table = np.array(rows, dtype=np.float64).reshape(len(rows), len(header))
    names = header[1:]
    data = {name: table[:, c + 1].copy() for c, name in enumerate(names)}
    if merge_vectors:
        data = _merge_vectors(names, data)
    return table[:, 0].copy(), data


class ProbeCSVWriter:
    """Append probe samples to a CSV file row by row, flushing each row.

    ``ProbeCSVWriter(path, names)`` truncates ``path`` and writes the header
    ``t,<names>``. With ``resume=True`` an existing file with the same
    columns is kept, minus rows with t > ``resume_after`` (and a partial last
    row), and new rows are appended after it. Usable as a context manager.
    """

    def __init__(self, path, names, *, resume=False, resume_after=None):
        self.path = os.fspath(path)
        self.names = list(names)
        _check_names(self.names, self.path)
        self._header = ",".join(["t", *self.names])
        self._fh = None
        if resume and os.path.exists(self.path) and os.path.getsize(self.path) > 0:
            self._truncate_for_resume(resume_after)
            self._fh = open(self.path, "a", encoding="utf-8", newline="")
        else:
            self._fh = open(self.path, "w", encoding="utf-8", newline="")
            self._fh.write(self._header + "\n")
            self._fh.flush()

    def _truncate_for_resume(self, resume_after):
        header, lines, _partial = _read_lines(self.path)
        if header != ["t", *self.names]:
            raise ValueError(f"{self.path}: cannot resume, its columns {header} differ from "
                             f"{['t', *self.names]}")
        kept = []
        for k, ln in enumerate(lines):
            if not ln:
                continue
            row = _parse_row(ln, len(header), f"{self.path}, line {k + 2}")
            if resume_after is None or row[0] <= float(resume_after):
                kept.append(ln)
        with _atomic_write(self.path, "w", encoding="utf-8", newline="") as fh:
            fh.write(self._header + "\n")
            fh.writelines(ln + "\n" for ln in kept)

    def append(self, t, values):
        """Append one row: time ``t`` and one value per name (sequence or mapping)."""
        if self._fh is None:
            raise ValueError(f"{self.path}: writer is closed")
        if isinstance(values, dict):
            missing = [n for n in self.names if n not in values]
            if missing:
                raise ValueError(f"{self.path}: values missing for {missing}")
            values = [values[n] for n in self.names]
        row = np.asarray(values, dtype=np.float64).ravel()
        if row.size != len(self.names):
            raise ValueError(f"{self.path}: got {row.size} values for {len(self.names)} columns")
        t = float(t)
        if math.isnan(t):
            raise ValueError(f"{self.path}: sample time is NaN")
        self._fh.write(",".join([_fmt(t), *map(_fmt, row.tolist())]) + "\n")
        self._fh.flush()

    def close(self):
        if self._fh is not None:
            self._fh.close()
            self._fh = None

    @property
    def closed(self):
        return self._fh is None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

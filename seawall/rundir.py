"""The run directory of ``seawall run``: one run per directory, small files written atomically.

A directory that already holds seawall's files is another run: writing a new
run into it would mix the two (VTU files, ``line_*.csv`` and a checkpoint of
the old run staying beside the new ``summary.json``). It is refused unless
the run continues from a checkpoint in it (``--restart``) or ``--overwrite``
asks to delete seawall's own files first; other files are never touched.
"""

import json
import os
import re
import shutil

from .errors import OutputError, ParameterError
from .io.vtk import _atomic_write

#: the files seawall writes into a run directory (shell patterns)
SEAWALL_FILES = ("summary.json", "probes.csv", "escaped.csv", "checkpoint.h5", "checkpoint.h5.tmp",
                 "fluid.pvd", "fluid_*.vtu", "fluid_*.pvtu", "dem.pvd", "dem_*.vtu", "wall_*.pvd", "wall_*.vtu",
                 "line_*.csv", "unstable_state.vtu", "snapshot.png", "probes.png")

_PATTERNS = [re.compile("^" + re.escape(p).replace(r"\*", r"[^/]*") + "$") for p in SEAWALL_FILES]
# the temporary sibling of an atomic write left by a killed process: .NAME.<12 hex>.tmp
_TEMPORARY = re.compile(r"^\.(?P<name>.+)\.[0-9a-f]{12}\.tmp$")


def is_seawall_file(name):
    """True for the name of a file seawall writes into a run directory (or a temporary one of those)."""
    m = _TEMPORARY.match(name)
    if m:
        name = m.group("name")
    return any(p.match(name) for p in _PATTERNS)


def seawall_files(directory):
    """Names of seawall's files in ``directory`` (sorted; empty if it does not exist)."""
    try:
        names = os.listdir(directory)
    except (FileNotFoundError, NotADirectoryError):
        return []
    return sorted(n for n in names if is_seawall_file(n) and os.path.isfile(os.path.join(directory, n)))


def check_out_path(out):
    """Refuse an ``--out`` that can never be a run directory, before anything is built or created."""
    if out is None:
        return
    if not str(out).strip():
        raise ParameterError("--out must name a directory, got an empty string")
    if os.path.exists(out) and not os.path.isdir(out):
        raise ParameterError(f"--out {out} is a file, not a directory")
    parent = os.path.abspath(out)
    while not os.path.exists(parent):
        parent = os.path.dirname(parent)
    if not os.path.isdir(parent):
        raise ParameterError(f"--out {out} cannot be created: {parent} is a file")


def prepare(out, *, overwrite=False, restart=None):
    """Create or check the run directory ``out``; clear seawall's files with ``overwrite``.

    An existing run directory is accepted as it is only when ``restart`` is a
    checkpoint inside it (the run continues there).
    """
    check_out_path(out)
    existing = seawall_files(out)
    restart_here = restart is not None and _same_directory(os.path.dirname(os.path.abspath(restart)), out)
    if existing and restart_here:
        if overwrite:
            raise ParameterError(f"--overwrite would delete the checkpoint {restart} that --restart continues from")
    elif existing and overwrite:
        for name in existing:
            try:
                os.remove(os.path.join(out, name))
            except OSError as exc:
                raise ParameterError(f"--overwrite: cannot delete {os.path.join(out, name)}: "
                                     f"{exc.strerror or exc}") from None
    elif existing:
        shown = ", ".join(existing[:3]) + (", ..." if len(existing) > 3 else "")
        raise ParameterError(f"--out {out} already holds a seawall run ({shown}); give --overwrite to replace it, "
                             f"--restart {os.path.join(out, 'checkpoint.h5')} to continue it, or another --out")
    try:
        os.makedirs(out, exist_ok=True)
    except OSError as exc:
        raise ParameterError(f"--out {out} cannot be created: {exc.strerror or exc}") from None
    _check_writable(out)


def _same_directory(a, b):
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def _check_writable(out):
    probe = os.path.join(out, f".seawall-write-test-{os.getpid()}")
    try:
        with open(probe, "w"):
            pass
        os.remove(probe)
    except OSError as exc:
        raise ParameterError(f"--out {out} is not writable: {exc.strerror or exc}") from None


def free_space_text(path):
    """'12.3 MB free on DIR' for the nearest existing directory of ``path`` ('' if unknown)."""
    directory = os.path.abspath(path)
    while directory and not os.path.isdir(directory):
        parent = os.path.dirname(directory)
        if parent == directory:
            return ""
        directory = parent
    try:
        free = shutil.disk_usage(directory).free
    except OSError:
        return ""
    return f"{free / 1e6:.1f} MB free on {directory}"


def output_error(exc, path):
    """An :class:`OutputError` saying which file could not be written, why, and the space left."""
    directory = os.path.dirname(os.path.abspath(path)) if not os.path.isdir(path) else path
    if not os.path.isdir(directory):
        return OutputError(f"output directory {directory} was removed during the run; "
                           f"stopped (could not write {os.path.basename(path)})", path=path)
    reason = getattr(exc, "strerror", None) or str(exc)
    space = free_space_text(directory)
    return OutputError(f"cannot write {path}: {reason}" + (f" ({space})" if space else ""), path=path)


def write_json(path, data):
    """Write ``data`` as JSON to ``path`` atomically (temporary file + rename)."""
    with _atomic_write(path, "w", encoding="utf-8") as fh:
        json.dump(data, fh, indent=2)

"""What produced a run: versions, git commit, command line, threads, start time.

Recorded in ``summary.json`` (key ``provenance``) and in every checkpoint, so
a run directory says how to reproduce it.
"""

import datetime
import os
import platform
import subprocess
import sys


def git_commit(directory=None):
    """(commit hash, dirty) of the git checkout holding ``directory`` (default: seawall's source), else (None, None)."""
    directory = directory or os.path.dirname(os.path.abspath(__file__))
    try:
        head = subprocess.run(["git", "-C", directory, "rev-parse", "HEAD"], capture_output=True, text=True,
                              timeout=5)
        if head.returncode != 0:
            return None, None
        status = subprocess.run(["git", "-C", directory, "status", "--porcelain", "--untracked-files=no"],
                                capture_output=True, text=True, timeout=5)
    except (OSError, subprocess.SubprocessError):
        return None, None
    dirty = bool(status.stdout.strip()) if status.returncode == 0 else None
    return head.stdout.strip() or None, dirty


def version_text():
    """``seawall X.Y.Z`` plus the git commit when running from a checkout (``seawall --version``)."""
    from . import __version__

    commit, dirty = git_commit()
    if commit is None:
        return f"seawall {__version__}"
    return f"seawall {__version__} (git {commit[:12]}{', modified' if dirty else ''})"


def provenance(argv=None):
    """The record of what produced a run (JSON-serialisable dict)."""
    import h5py
    import numba
    import numpy

    from . import __version__
    from .jit import THREADED, thread_count
    from .subnormals import supported

    commit, dirty = git_commit()
    return {
        "seawall_version": __version__,
        "git_commit": commit,
        "git_modified": dirty,
        "command_line": list(sys.argv if argv is None else argv),
        "threads": thread_count(),
        "loops": "threaded" if THREADED else "serial",
        # values below 2.2e-308 are flushed to zero during runs (seawall.subnormals)
        "subnormals": "flushed" if supported() else "kept",
        "python": platform.python_version(),
        "numba": numba.__version__,
        "numpy": numpy.__version__,
        "h5py": h5py.__version__,
        "platform": platform.platform(),
        "started": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    }

"""Pictures of a run directory: a particle snapshot and the probe histories.

Used by ``seawall plot RUN_DIR``; reads only the files ``seawall run`` wrote
(fluid.pvd / .vtu series, probes.csv), so it also works on older runs.
"""

import os
import xml.etree.ElementTree as ET

import numpy as np


def _series(run_dir, name="fluid"):
    path = os.path.join(run_dir, f"{name}.pvd")
    if not os.path.exists(path):
        raise FileNotFoundError(f"{path} not found: was the run made with --no-vtk?")
    root = ET.parse(path).getroot()
    return [(float(ds.get("timestep")), os.path.join(run_dir, ds.get("file")))
            for ds in root.iter("DataSet")]


def snapshot(run_dir, out_png, *, time=None, field="pressure", walls=True, title=None):
    """Scatter plot of the fluid particles at the stored time closest to ``time`` (default: last)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .io.vtk import read_vtu

    frames = _series(run_dir)
    if not frames:
        raise ValueError(f"{run_dir}: the fluid series is empty")
    k = len(frames) - 1 if time is None else int(np.argmin([abs(t - time) for t, _ in frames]))
    t, path = frames[k]
    x, data = read_vtu(path)
    if field not in data:
        raise ValueError(f"field must be one of {', '.join(sorted(data))}; got {field!r}")
    values = data[field]
    if values.ndim == 2:
        values = np.linalg.norm(values, axis=1)
    fig, ax = plt.subplots(figsize=(8, 3.6), dpi=110)
    if walls:
        for name in sorted(f[:-4] for f in os.listdir(run_dir) if f.startswith("wall_") and f.endswith(".pvd")):
            wall_frames = _series(run_dir, name)
            if wall_frames:
                wx, _ = read_vtu(wall_frames[0][1])
                ax.scatter(wx[:, 0], wx[:, 1], s=1.0, c="0.55", linewidths=0)
    sc = ax.scatter(x[:, 0], x[:, 1], s=1.2, c=values, cmap="viridis", linewidths=0)
    fig.colorbar(sc, ax=ax, label=field + (" [Pa]" if field == "pressure" else ""))
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title or f"{os.path.basename(os.path.normpath(run_dir))}, t = {t:.3f} s")
    fig.tight_layout()
    fig.savefig(out_png)
    plt.close(fig)
    return out_png


def probe_histories(run_dir, out_png, names=None):
    """Line plot of probe columns of ``probes.csv`` against time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .io.csvout import read_probes_csv

    t, cols = read_probes_csv(os.path.join(run_dir, "probes.csv"))
    names = names or [n for n in cols if n not in ("mass", "kinetic_energy", "front")]
    fig, ax = plt.subplots(figsize=(7, 3.5), dpi=110)
    for n in names:
        ax.plot(t, cols[n], lw=1, label=n)
    ax.set_xlabel("t [s]")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out_png)
    plt.close(fig)
    return out_png

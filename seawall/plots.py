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


#: default colour range: these percentiles of the frame's values (a few particles at the impact or in
#: a splash reach several times the bulk pressure and would otherwise leave the field one colour)
ROBUST_PERCENTILES = (1.0, 99.0)


def colour_range(values, clim=None):
    """(lo, hi) of the colour scale: ``clim`` if given, else the 1st and 99th percentile of the finite values."""
    if clim is not None:
        return float(clim[0]), float(clim[1])
    finite = values[np.isfinite(values)]
    if finite.size == 0:
        return 0.0, 1.0
    lo, hi = np.percentile(finite, ROBUST_PERCENTILES)
    if not hi > lo:
        lo, hi = float(finite.min()), float(finite.max())
        if not hi > lo:
            lo, hi = lo - 0.5, hi + 0.5
    return float(lo), float(hi)


def _view_axes(x):
    """The two axes drawn: (x, y) in 2D; in 3D a side view (x, z) -- gravity along the last axis --
    unless the run has no extent in x (then (y, z))."""
    if not np.any(x[:, 2]):
        return 0, 1
    return (0, 2) if np.ptp(x[:, 0]) > 0 else (1, 2)


def _frame_at(frames, t):
    """The frame of ``frames`` (time, path) nearest to time ``t``."""
    return frames[int(np.argmin([abs(ft - t) for ft, _ in frames]))]


def snapshot(run_dir, out_png, *, time=None, field="pressure", walls=True, title=None, clim=None):
    """Scatter plot of the fluid particles at the stored time closest to ``time`` (default: last).

    Walls are drawn where they were at that time (their frame nearest to it;
    runs made before walls were written at every frame hold one wall frame).
    3D runs are seen from the side (x horizontal, the vertical last axis up).
    ``clim`` = (lo, hi) fixes the colour range; by default it spans the 1st
    to 99th percentile of the field in that frame.
    """
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
    values = values.astype(np.float64)
    lo, hi = colour_range(values, clim)
    a, b = _view_axes(x)
    spacing = _spacing(path, data, x)
    fig, ax = plt.subplots(figsize=(8, 3.6), dpi=110)
    drawn = [x]
    wall_dots = []
    if walls:
        for name in sorted(f[:-4] for f in os.listdir(run_dir) if f.startswith("wall_") and f.endswith(".pvd")):
            wall_frames = _series(run_dir, name)
            if wall_frames:
                wx, _ = read_vtu(_frame_at(wall_frames, t)[1])
                wall_dots.append(ax.scatter(wx[:, a], wx[:, b], c="0.55", linewidths=0))
                drawn.append(wx)
    sc = ax.scatter(x[:, a], x[:, b], c=values, cmap="viridis", vmin=lo, vmax=hi, linewidths=0)
    unit = {"pressure": " [Pa] (gauge)", "density": " [kg/m^3]", "velocity": " [m/s]", "mass": " [kg]"}.get(field, "")
    extend = "both" if clim is None else "neither"
    fig.colorbar(sc, ax=ax, label=field + unit, extend=extend)
    every = np.concatenate(drawn)
    pad = spacing
    ax.set_xlim(every[:, a].min() - pad, every[:, a].max() + pad)
    ax.set_ylim(every[:, b].min() - pad, every[:, b].max() + pad)
    ax.set_aspect("equal")
    names = "xyz"
    ax.set_xlabel(f"{names[a]} [m]")
    ax.set_ylabel(f"{names[b]} [m]")
    ax.set_title(title or f"{_run_label(run_dir)}, t = {t:.3f} s")
    fig.tight_layout()
    # each particle drawn as a dot one particle spacing wide (a fixed marker size left coarse runs
    # as scattered specks with no visible field)
    fig.canvas.draw()
    box = ax.get_window_extent()
    points_per_m = box.width * 72.0 / fig.dpi / (ax.get_xlim()[1] - ax.get_xlim()[0])
    area = max(0.5, (0.95 * spacing * points_per_m) ** 2)
    sc.set_sizes([area])
    for dots in wall_dots:
        dots.set_sizes([area])
    fig.savefig(out_png)
    plt.close(fig)
    return out_png


def _spacing(path, data, x):
    """Particle spacing [m]: the file's dx (FieldData), else (m / rho)^(1/d) of the median particle."""
    from .io.vtk import read_vtu_metadata

    dx = read_vtu_metadata(path).get("dx")
    if isinstance(dx, float) and dx > 0:
        return dx
    dim = 3 if np.any(x[:, 2]) else 2
    if "mass" in data and "density" in data and len(x):
        return float(np.median(data["mass"] / data["density"]) ** (1.0 / dim))
    return 0.01 * float(np.ptp(x[:, 0]) or 1.0)


def _run_label(run_dir):
    """'case, wall model' from summary.json when there is one, else the directory's name."""
    import json

    try:
        with open(os.path.join(run_dir, "summary.json")) as fh:
            s = json.load(fh)
        return f"{s['case']}, {s['boundary']}"
    except (OSError, ValueError, KeyError, TypeError):
        return os.path.basename(os.path.normpath(run_dir))


#: units of probe names written before summary.json recorded them (probe_units)
KNOWN_UNITS = {"front": "m", "kinetic_energy": "J", "mass": "kg", "min_wall_distance_dx": "dx"}


def _probe_units(run_dir, names):
    import json

    units = {}
    try:
        with open(os.path.join(run_dir, "summary.json")) as fh:
            units = json.load(fh).get("probe_units") or {}
    except (OSError, ValueError, AttributeError):
        units = {}
    return {n: units.get(n, KNOWN_UNITS.get(n, "")) for n in names}


def probe_histories(run_dir, out_png, names=None):
    """Probe columns of ``probes.csv`` against time, one panel per unit (Pa, m, N/m, ...), each labelled."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .io.csvout import read_probes_csv

    t, cols = read_probes_csv(os.path.join(run_dir, "probes.csv"))
    names = names or [n for n in cols if n not in ("mass", "kinetic_energy")]
    if not names:
        raise ValueError(f"{run_dir}/probes.csv has no probe columns to draw")
    units = _probe_units(run_dir, names)
    groups = {}
    for n in names:
        groups.setdefault(units[n], []).append(n)
    fig, axes = plt.subplots(len(groups), 1, figsize=(7, 2.4 * len(groups) + 0.6), dpi=110, sharex=True,
                             squeeze=False)
    for ax, (unit, members) in zip(axes[:, 0], groups.items()):
        for n in members:
            ax.plot(t, cols[n], lw=1, label=n)
        ax.set_ylabel(f"[{unit}]" if unit else "(no unit)")
        ax.legend(fontsize=7)
    axes[-1, 0].set_xlabel("t [s]")
    axes[0, 0].set_title(_run_label(run_dir))
    fig.tight_layout()
    fig.savefig(out_png)
    plt.close(fig)
    return out_png

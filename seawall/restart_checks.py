"""Is a checkpoint a valid state of *this* simulation? Checked before a restart loads it.

A restart continues a run; it must not quietly become another one. The
checkpoint's case, wall model and its options, dimension, case parameters
and compiled physics constants must equal those of the simulation it is
loaded into (only output settings and the end time may change), and its
arrays must have the shapes and dtypes this simulation uses (a crafted or
damaged file must not run time backwards or in the wrong dimension).
"""

import json
import math

import numpy as np

from .errors import ParameterError

#: metadata entries that define the run (as opposed to provenance and derived numbers)
SETUP_KEYS = ("case", "case_sha256", "boundary", "boundary_options", "parameters")


def _plain(value):
    """JSON round trip, so values compare as they are stored (tuples as lists, numpy scalars as numbers)."""
    return json.loads(json.dumps(value, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o)))


def _show(value):
    return repr(value) if isinstance(value, str) else json.dumps(value)


def setup_differences(saved_metadata, metadata, saved_physics=None, physics=None):
    """Lines 'what: X in the checkpoint, Y now' for every setting that differs."""
    diffs = []
    saved_metadata = saved_metadata or {}
    for key in SETUP_KEYS:
        if key not in saved_metadata and (key not in metadata or key == "boundary_options"):
            continue   # checkpoints written before wall options were recorded
        old, new = _plain(saved_metadata.get(key)), _plain(metadata.get(key))
        if key == "parameters" and isinstance(old, dict) and isinstance(new, dict):
            for name in sorted(set(old) | set(new)):
                if old.get(name) != new.get(name):
                    diffs.append(f"parameter {name} = {_show(old.get(name))} in the checkpoint, "
                                 f"{_show(new.get(name))} now")
        elif key == "case_sha256" and old != new:
            diffs.append(f"case file changed since the checkpoint (sha256 {str(old)[:12]}... in the checkpoint, "
                         f"{str(new)[:12]}... now)")
        elif old != new:
            diffs.append(f"{key.replace('_', ' ')} {_show(old)} in the checkpoint, {_show(new)} now")
    if saved_physics is not None and physics is not None:
        for name in sorted(set(saved_physics) | set(physics)):
            old, new = _plain(saved_physics.get(name)), _plain(physics.get(name))
            if old != new:
                diffs.append(f"physics constant {name} = {_show(old)} in the checkpoint, {_show(new)} now")
    return diffs


def check_setup(path, attrs, metadata, physics=None):
    """Raise ParameterError naming what differs between the checkpoint's set-up and this one."""
    diffs = setup_differences(attrs.get("metadata"), metadata, attrs.get("physics"), physics)
    if diffs:
        shown = "; ".join(diffs[:4]) + (f"; and {len(diffs) - 4} more" if len(diffs) > 4 else "")
        raise ParameterError(f"checkpoint {path} does not match this simulation: {shown} "
                             f"(a restart may change only output settings and the end time)")


def check_clock(path, attrs, *, need_next_dt=True):
    """Time, step and next time step must be usable: finite, non-negative, dt > 0."""
    t = attrs.get("time")
    if isinstance(t, bool) or not isinstance(t, (int, float)) or not math.isfinite(t) or t < 0:
        raise ParameterError(f"checkpoint {path}: time must be a finite number >= 0, got {t!r}")
    step = attrs.get("step")
    if isinstance(step, bool) or not isinstance(step, int) or step < 0:
        raise ParameterError(f"checkpoint {path}: step must be a whole number >= 0, got {step!r}")
    if need_next_dt:
        dt = attrs.get("next_dt")
        if isinstance(dt, bool) or not isinstance(dt, (int, float)) or not (math.isfinite(dt) and dt > 0):
            raise ParameterError(f"checkpoint {path}: next_dt must be a positive finite time step, got {dt!r}")


def check_arrays(path, group_name, saved, current, *, require_all=True):
    """The checkpoint's arrays of one system against this simulation's: names, dtypes, trailing shapes, count."""
    if not isinstance(saved, dict):
        raise ParameterError(f"checkpoint {path} lacks the arrays of {group_name}")
    counts = set()
    for name, here in current.items():
        if name not in saved:
            if require_all:
                raise ParameterError(f"checkpoint {path} lacks array {name!r} of {group_name}")
            continue
        a = np.asarray(saved[name])
        if a.dtype != here.dtype or a.shape[1:] != here.shape[1:] or a.ndim != here.ndim:
            raise ParameterError(f"checkpoint {path}: array {name!r} of {group_name} is {a.dtype} {a.shape}, "
                                 f"this simulation needs {here.dtype} (n{''.join(f', {k}' for k in here.shape[1:])})")
        counts.add(a.shape[0])
    if len(counts) > 1:
        raise ParameterError(f"checkpoint {path}: the arrays of {group_name} have different lengths {sorted(counts)}")
    if "x" in saved and not np.all(np.isfinite(np.asarray(saved["x"], dtype=np.float64))):
        raise ParameterError(f"checkpoint {path}: positions of {group_name} are not all finite")


def check_probes(path, saved, n_probes):
    times = np.asarray(saved.get("times", np.zeros(0)))
    values = np.asarray(saved.get("values", np.zeros((0, n_probes))))
    if times.ndim != 1 or values.ndim != 2 or values.shape != (times.shape[0], n_probes):
        raise ParameterError(f"checkpoint {path}: probe history has shape {values.shape} for {times.shape} times, "
                             f"this simulation has {n_probes} probes")

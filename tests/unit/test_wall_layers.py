"""On a made-up snapshot: validation/dam-break/wall_layers.py (gap, wall layer, floor, deepest
particle) and plateau_figures.py (the fields figure)."""

import json
import os

import numpy as np
import pytest

from seawall.validation import ROOT, load_script

wall_layers = load_script(os.path.join(ROOT, "validation", "dam-break", "wall_layers.py"))


class _Npz(dict):
    """A loaded npz's interface (``files`` and item access) over a dict."""

    @property
    def files(self):
        return list(self)


def _snapshot(tmp_path, dx=0.006, length=1.608, one_row=False):
    H = wall_layers.H
    rho_g_h = wall_layers.RHO_G_H
    ys = np.arange(0.5 * dx, 0.6 * H, dx)
    # three layers of the downstream wall (first layer at 2 rho g H, the others at 0) and of the floor
    side = [(length + (k + 0.5) * dx, y, 2.0 * rho_g_h if k == 0 else 0.0) for k in range(3) for y in ys]
    xs = np.arange(length - 0.5 * H + 0.5 * dx, length, dx)
    floor = [(x, -(k + 0.5) * dx, (-1.0 if i % 4 == 0 else 1.0) * rho_g_h if k == 0 else 0.0)
             for k in range(3) for i, x in enumerate(xs)]
    if one_row:   # one row on the surfaces at spacing dx / 3 (monaghan-kajtar, liu2012)
        fine = np.arange(0.0, 0.6 * H, dx / 3)
        side = [(length, y, 2.0 * rho_g_h) for y in fine]
        xs = np.arange(length - 0.5 * H + dx / 3, length, dx / 3)
        floor = [(x, 0.0, (-1.0 if i % 4 == 0 else 1.0) * rho_g_h) for i, x in enumerate(xs)]
    w = np.array(side + floor)
    # fluid: a column 1.5 dx off the wall at every height (dx / 2 apart, so that each band y +- dx
    # holds at least two), one particle 0.5 dx inside the floor
    fx = np.array([(length - 1.5 * dx, y) for y in np.arange(0.25 * dx, 0.6 * H, 0.5 * dx)]
                  + [(length - 5 * dx, -0.5 * dx)])
    fv = np.zeros_like(fx)
    fv[-1] = (1.2, 0.0)
    t = 3.5 / np.sqrt(wall_layers.G / H)
    stored = {"dx": np.array(dx), "surface_x": np.array(length)} if one_row else {}
    np.savez(tmp_path / "plateau_snapshots.npz", f0_x=fx, f0_v=fv, f0_p=np.full(len(fx), rho_g_h),
             w0_x=w[:, :2], w0_p=w[:, 2], t0=np.array(t), **stored)
    return tmp_path, len(range(0, len(xs), 4)) / len(xs)


def test_geometry_reads_the_spacing_and_the_wall_surface_of_a_layered_wall():
    w = np.array([(1.611, 0.1), (1.617, 0.1), (1.623, 0.1), (1.611, 0.106)])
    dx, length, first = wall_layers.geometry(_Npz(w0_x=w), 0)
    assert abs(dx - 0.006) < 1e-12
    assert abs(length - 1.608) < 1e-12
    assert abs(first - 0.003) < 1e-12


def test_geometry_takes_dx_and_surface_stored_with_the_snapshots():
    # a one-row wall on the surface at spacing dx / 3: only the stored values give dx
    ys = np.arange(0.0, 0.2, 0.002)
    w = np.column_stack([np.full(ys.size, 1.608), ys])
    dx, length, first = wall_layers.geometry(_Npz(w0_x=w, dx=np.array(0.006), surface_x=np.array(1.608)), 0)
    assert (dx, length, first) == (0.006, 1.608, 0.0)


def test_geometry_of_an_older_one_row_snapshot_reads_dx_from_the_summary(tmp_path):
    ys = np.arange(0.0, 0.2, 0.002)
    w = _Npz(w0_x=np.column_stack([np.full(ys.size, 1.608), ys]))
    with pytest.raises(ValueError, match="summary.json"):
        wall_layers.geometry(w, 0, str(tmp_path))
    (tmp_path / "summary.json").write_text(json.dumps({"dx": 0.006}))
    assert wall_layers.geometry(w, 0, str(tmp_path)) == (0.006, 1.608, 0.0)


@pytest.mark.parametrize("one_row", [False, True])
def test_rows_give_gap_wall_layer_floor_and_deepest(tmp_path, one_row):
    path, negative = _snapshot(tmp_path, one_row=one_row)
    rows = wall_layers.snapshot_rows(str(path))
    assert len(rows) == 1
    r = rows[0]
    assert abs(r["t_star"] - 3.5) < 1e-12
    for gap, wall1 in r["heights"].values():
        assert abs(gap - 1.5) < 1e-9
        assert abs(wall1 - 2.0) < 1e-9
    assert abs(r["floor_negative"] - negative) < 1e-12     # every fourth particle of the floor's first layer
    assert r["floor_median"] == 1.0
    depth, pos, vel = r["deepest"]
    assert abs(depth + 0.5) < 1e-9 and vel[0] == 1.2


def test_a_directory_without_snapshots_is_named(tmp_path, capsys):
    assert wall_layers.main([str(tmp_path)]) == 2
    assert str(tmp_path) in capsys.readouterr().err


def test_plateau_figures_draws_the_fields_of_a_snapshot_and_names_a_missing_one(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    plateau_figures = load_script(os.path.join(ROOT, "validation", "dam-break", "plateau_figures.py"))
    run = tmp_path / "run"
    run.mkdir()
    _snapshot(run, one_row=True)
    out = tmp_path / "fields.png"
    assert plateau_figures.main(["fields", str(out), f"one-row={run}", "--snapshot", "0"]) == 0
    assert out.stat().st_size > 0
    assert plateau_figures.main(["fields", str(out), f"one-row={run}", "--snapshot", "1"]) == 2
    assert "has snapshots 0..0" in capsys.readouterr().err

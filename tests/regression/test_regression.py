"""Every stored series re-runs to the stored result (see ``series.py`` for what is stored and why).

A failure names the series and the quantities that moved. After a deliberate change of the
physics, regenerate exactly the series it should change, e.g.::

    python -m tests.regression.regenerate '*-idbc'

and check that nothing else moved with ``python -m tests.regression.regenerate --check``.
"""

import inspect
import os

import pytest

from seawall.cases import case_by_name

from . import series


@pytest.mark.parametrize("name", list(series.SERIES))
def test_series_reproduces_the_stored_run(name):
    if not os.path.exists(series.path(name)):
        pytest.fail(f"no stored data for series {name!r}: run  python -m tests.regression.regenerate {name}")
    stored = series.load(name)
    new = series.run(name)
    devs = series.deviations(stored, new)
    geometry = [k for k in ("n_fluid", "n_wall", "wall_lo", "wall_hi") if devs[k] > 0.0]
    assert not geometry, (f"series {name!r}: the case built another geometry ({', '.join(geometry)} changed): "
                          f"a case default moved; pin the old value in tests/regression/series.py")
    above = {k: v for k, v in devs.items() if v > series.RTOL}
    assert not above, (f"series {name!r} moved (scaled deviation above {series.RTOL:g}): "
                       + ", ".join(f"{k} {v:.3g}" for k, v in sorted(above.items(), key=lambda kv: -kv[1]))
                       + f"; if deliberate: python -m tests.regression.regenerate {name}")


@pytest.mark.parametrize("name", list(series.SERIES))
def test_every_case_parameter_is_pinned(name):
    # a parameter left to its default would let a change of that default move the baseline unnoticed
    spec = series.SERIES[name]
    case = case_by_name(spec.case)
    # the case's default regularisation and pressure model (--set keys, not parameters) can move a baseline too
    missing = sorted((set(case.parameters) | set(case.regularisation) | set(case.pressure)) - set(spec.params))
    assert not missing, (f"series {name!r} does not pin parameter(s) {', '.join(missing)} of case {spec.case!r}: "
                         f"add them to tests/regression/series.py with the value that reproduces the stored data")
    assert all(value is not None for value in spec.params.values()), "None means 'the default rule': pin a value"


def test_every_registered_wall_model_has_series_in_both_tanks():
    from seawall.boundary.registry import BOUNDARIES

    for model in BOUNDARIES:
        assert f"hydrostatic-{model}" in series.SERIES and f"dam-break-{model}" in series.SERIES, model


def test_stored_data_stay_small():
    total = sum(os.path.getsize(os.path.join(series.DATA, f)) for f in os.listdir(series.DATA))
    assert total < 2_000_000, f"tests/regression/data holds {total} bytes"


def test_regenerate_is_documented():
    from . import regenerate

    assert "python -m tests.regression.regenerate" in inspect.getdoc(regenerate)

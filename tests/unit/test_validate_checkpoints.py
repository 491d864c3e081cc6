"""``seawall validate --checkpoints``: an entry stopped part-way continues from its checkpoint to the
same result, bit for bit, and its stored result says where it resumed."""

import os

import numpy as np
import pytest

from seawall.cases import build
from seawall.cli import main
from seawall.errors import ParameterError
from seawall.validation import Context

T_END = 0.1


def small_tank():
    sim = build("hydrostatic", dx=0.05, length=0.5, depth=0.2, height=0.3, initial="rest", boundary="adami")
    sim.add(every=0.01)
    return sim


def test_a_stopped_entry_run_continues_to_the_uninterrupted_result(tmp_path):
    reference = small_tank()
    ref_result = Context(quick=False, img_dir=str(tmp_path)).run(reference, T_END)

    # the entry stopped part-way: its checkpoint holds the state after whole steps, as a signal leaves it
    stopped = small_tank()
    stopped.run_steps(40)
    stopped_at = stopped.time
    assert 0.0 < stopped_at < T_END
    os.makedirs(tmp_path / "ck")
    stopped.save_checkpoint(str(tmp_path / "ck" / "checkpoint.h5"))

    ctx = Context(quick=False, img_dir=str(tmp_path), checkpoint_dir=str(tmp_path / "ck"))
    resumed = small_tank()
    result = ctx.run(resumed, T_END)
    assert ctx.resumed_at == [stopped_at]
    assert resumed.step == reference.step
    for name in ("x", "v", "rho"):
        assert np.array_equal(resumed.fluid.particles[name], reference.fluid.particles[name]), name
    # the probe samples taken after the stop are the uninterrupted run's
    after = ref_result.times > stopped_at
    np.testing.assert_array_equal(result.times[-after.sum():], ref_result.times[after])
    for name in ref_result.probes:
        np.testing.assert_array_equal(result.probes[name][-after.sum():], ref_result.probes[name][after])
    # the run kept its own checkpoint at the end: given again, the entry is measured from it without a step
    again = small_tank()
    ctx_again = Context(quick=False, img_dir=str(tmp_path), checkpoint_dir=str(tmp_path / "ck"))
    ctx_again.run(again, T_END)
    assert ctx_again.resumed_at == [pytest.approx(T_END)]
    assert again.step == reference.step
    assert np.array_equal(again.fluid.particles["x"], reference.fluid.particles["x"])


def test_a_checkpoint_of_another_build_is_refused(tmp_path):
    other = build("hydrostatic", dx=0.04, length=0.5, depth=0.2, height=0.3, initial="rest", boundary="adami")
    other.run_steps(2)
    os.makedirs(tmp_path / "ck")
    other.save_checkpoint(str(tmp_path / "ck" / "checkpoint.h5"))
    with pytest.raises(ParameterError):
        Context(quick=False, img_dir=str(tmp_path), checkpoint_dir=str(tmp_path / "ck")).run(small_tank(), T_END)


@pytest.mark.parametrize("extra", [["--doc-only"], ["--list"], ["--scheduler", "local"]])
def test_checkpoints_with_an_option_that_runs_nothing_here_is_refused_in_one_line(tmp_path, capsys, extra):
    assert main(["validate", "--checkpoints", str(tmp_path), *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--checkpoints" in err[0]

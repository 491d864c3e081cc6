"""The compile helper (seawall.compile_ahead): each function compiled once across the two
processes, the run's results unchanged, and the rehearsal reaching every loop of a first step."""

import json
import os
import subprocess
import sys
import textwrap

import pytest

from seawall import compile_ahead

# A module of four cached functions in the shape of a run: a set-up function whose result the
# Python code uses, two "particle loops" that only write into arrays, and a read-out. Its name
# starts with "seawall" because the helper shares only seawall's functions.
TOY = textwrap.dedent('''
    import numpy as np
    from numba import njit

    @njit(cache=True)
    def setup(n):
        return np.arange(n, dtype=np.float64)

    @njit(cache=True)
    def loop_a(x, out):
        for i in range(x.size):
            out[i] = 2.0 * x[i]

    @njit(cache=True)
    def loop_b(x, out):
        for i in range(x.size):
            out[i] += x[i] + 1.0

    @njit(cache=True)
    def read_out(out):
        return out.sum()
''')

# Run in a fresh process: start() forks once per process and patches Numba's dispatcher class.
DRIVER = textwrap.dedent('''
    import json, os, sys, time
    import numba
    numba.config.CACHE_DIR = sys.argv[2]
    sys.path.insert(0, sys.argv[1])
    import seawall_toy_compile as toy
    from seawall import compile_ahead

    def pipeline():
        x = toy.setup(1000)
        out = np.zeros_like(x)
        toy.loop_a(x, out)
        toy.loop_b(x, out)
        return toy.read_out(out)

    import numpy as np
    mode = sys.argv[3]
    started = compile_ahead.start([pipeline], {toy.loop_a, toy.loop_b})
    session = compile_ahead._state["session"]
    if mode == "after-helper":      # the helper has done all it will do before the run compiles
        os.waitpid(session.pid, 0)
    elif mode == "helper-killed":   # the helper ends at once; the run must compile what it claimed
        os.kill(session.pid, 9)
    value = pipeline()
    funcs = (toy.setup, toy.loop_a, toy.loop_b, toy.read_out)
    print(json.dumps({"started": started, "value": value,
                      "hits": [sum(f.stats.cache_hits.values()) for f in funcs],
                      "misses": [sum(f.stats.cache_misses.values()) for f in funcs],
                      "compiled_here": session.compiled_here, "loaded": session.loaded_from_other}))
''')


def _drive(tmp_path, mode):
    (tmp_path / "seawall_toy_compile.py").write_text(TOY)
    cache = tmp_path / "cache"
    env = dict(os.environ, SEAWALL_COMPILE_AHEAD="1")
    done = subprocess.run([sys.executable, "-c", DRIVER, str(tmp_path), str(cache), mode], env=env,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_what_the_helper_compiled_is_loaded_from_the_cache_not_compiled_again(tmp_path):
    """With the helper finished first, it has compiled all four functions (the rehearsal runs
    ``setup`` and ``read_out`` and records both loops, which it compiles afterwards); the run
    compiles none of them and loads each from the cache."""
    result = _drive(tmp_path, "after-helper")
    assert result["started"]
    assert result["value"] == pytest.approx(3.0 * 999 * 1000 / 2 + 1000)
    assert result["misses"] == [0, 0, 0, 0]
    assert result["hits"] == [1, 1, 1, 1]
    assert result["compiled_here"] == 0 and result["loaded"] == 4


def test_a_helper_that_dies_leaves_the_run_to_compile_for_itself(tmp_path):
    result = _drive(tmp_path, "helper-killed")
    assert result["started"]
    assert result["value"] == pytest.approx(3.0 * 999 * 1000 / 2 + 1000)
    # every function is there once: compiled here, or loaded if the helper had finished it
    assert [h + m for h, m in zip(result["hits"], result["misses"])] == [1, 1, 1, 1]


PLAN = textwrap.dedent('''
    import json, sys
    import numpy as np
    import numba
    numba.config.CACHE_DIR = sys.argv[2]
    sys.path.insert(0, sys.argv[1])
    import seawall_toy_compile as toy
    from seawall import compile_ahead

    x = np.zeros(3)
    types = (numba.typeof(x), numba.typeof(x))
    plan = [(compile_ahead._key(d, types), d, types) for d in (toy.loop_a, toy.loop_b, toy.read_out)]
    helper = compile_ahead._Session(sys.argv[3], lambda: True)
    helper.publish_plan(plan)
    assert helper.claim(plan[0][0])          # the helper holds loop_a
    run = compile_ahead._Session(sys.argv[3], lambda: True, loops={toy.loop_a, toy.loop_b})
    took = [run.take_from_plan() for _ in range(3)]
    print(json.dumps({"took": took, "compiled_here": run.compiled_here,
                      "overloads": [len(d.overloads) for d in (toy.loop_a, toy.loop_b, toy.read_out)]}))
''')


def test_a_run_waiting_for_the_helper_compiles_the_plans_unclaimed_loops(tmp_path):
    """While the helper holds a loop, the run takes the plan's next unclaimed loop (loop_b), and
    only loops it knows (read_out is not one of the loops given to it); then nothing is left."""
    (tmp_path / "seawall_toy_compile.py").write_text(TOY)
    claims = tmp_path / "claims"
    claims.mkdir()
    done = subprocess.run([sys.executable, "-c", PLAN, str(tmp_path), str(tmp_path / "cache"), str(claims)],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    result = json.loads(done.stdout.strip().splitlines()[-1])
    assert result["took"] == [True, False, False]
    assert result["compiled_here"] == 1
    assert result["overloads"] == [0, 1, 0]


def test_no_particle_loop_returns_a_value():
    """What lets the rehearsal skip a particle loop: the Python code never reads a result of one."""
    import ast
    import importlib
    import inspect
    import pkgutil

    import seawall
    from seawall.jit import PARTICLE_LOOPS

    for module in pkgutil.walk_packages(seawall.__path__, "seawall."):
        if module.name != "seawall.__main__":
            importlib.import_module(module.name)

    assert len(PARTICLE_LOOPS) > 30
    for dispatcher in PARTICLE_LOOPS:
        tree = ast.parse(textwrap.dedent(inspect.getsource(dispatcher.py_func)))
        returns = [node for node in ast.walk(tree) if isinstance(node, ast.Return) and node.value is not None]
        assert not returns, dispatcher.py_func.__qualname__


def test_the_switch_names_its_variable_and_the_suite_runs_without_a_helper():
    assert not compile_ahead.enabled({compile_ahead.ENV_VARIABLE: "0"})
    with pytest.raises(ValueError, match=compile_ahead.ENV_VARIABLE):
        compile_ahead.enabled({compile_ahead.ENV_VARIABLE: "maybe"})
    assert os.environ[compile_ahead.ENV_VARIABLE] == "0"     # tests/conftest.py


REHEARSAL = textwrap.dedent('''
    import json, sys
    import numpy as np
    from numba.core.dispatcher import Dispatcher
    from seawall import compile_ahead
    from seawall.cases import build
    from seawall.jit import PARTICLE_LOOPS

    def key(dispatcher, args):
        return [dispatcher.py_func.__qualname__, str(tuple(dispatcher.typeof_pyval(a) for a in args))]

    # the rehearsal first, in a process where no particle loop has been compiled (as in a helper)
    copy = build("dam-break", dx=0.05, boundary=sys.argv[1])
    x0 = copy.fluid.particles["x"].copy()
    recorded = []

    def hook(dispatcher, args):
        if dispatcher in PARTICLE_LOOPS:
            recorded.append(key(dispatcher, args))
            return compile_ahead._noop
        return compile_ahead._original_compile_for_args(dispatcher, *args)
    compile_ahead._install(hook)
    for stage in copy._rehearsal():
        try:
            stage()
        except Exception:
            pass
    compile_ahead._uninstall()
    x1 = copy.fluid.particles["x"]    # the same points, perhaps reordered by cell
    moved = x1.shape != x0.shape or bool(np.any(x1[np.lexsort(x1.T)] != x0[np.lexsort(x0.T)]))

    # then the real start of a run, every particle loop called from Python noted
    real = build("dam-break", dx=0.05, boundary=sys.argv[1])
    called = []
    original = Dispatcher.__call__
    in_guards = [False]
    check_health = real._check_health

    def guards(*args, **kws):       # the run's guards, which the rehearsal leaves out
        in_guards[0] = True
        try:
            return check_health(*args, **kws)
        finally:
            in_guards[0] = False
    real._check_health = guards

    def spy(self, *args, **kws):
        if self in PARTICLE_LOOPS and not in_guards[0]:
            called.append(key(self, args))
        return original(self, *args, **kws)
    Dispatcher.__call__ = spy
    real._initialise()
    real._one_step(real.next_dt)
    print(json.dumps({"recorded": recorded, "called": called, "moved": moved, "outputs": len(copy.outputs)}))
''')


@pytest.mark.parametrize("boundary", ["adami", "dbc"])
def test_the_rehearsal_records_every_loop_of_the_first_step_with_its_types(boundary):
    """The rehearsal (loops skipped, so rates and sound speeds stay at zero) must still reach
    every particle loop the real start of a run calls, with the same argument types: what it
    misses is compiled by the run alone. The guards are left out of it (the run calls them
    first, before the helper could have compiled anything). Run in a fresh process: a loop
    compiled already would not come to the hook."""
    done = subprocess.run([sys.executable, "-c", REHEARSAL, boundary], capture_output=True, text=True,
                          timeout=900)
    assert done.returncode == 0, done.stderr[-3000:]
    result = json.loads(done.stdout.strip().splitlines()[-1])
    called = {tuple(k) for k in result["called"]}
    assert called and called <= {tuple(k) for k in result["recorded"]}
    assert not result["moved"]          # the skipped loops moved nothing
    assert result["outputs"] == 0


def test_threads_are_set_when_the_first_run_starts_and_recorded_before():
    """A Simulation's ``threads`` must not start Numba's thread pool at its construction (a compile
    helper can only be forked before), yet the run uses and records that count."""
    script = textwrap.dedent('''
        import json
        import numba
        from numba.np.ufunc import parallel
        from seawall.cases import build
        from seawall.jit import thread_count
        from seawall.provenance import provenance

        sim = build("hydrostatic", boundary="dbc", dx=0.05, threads=1)
        before = {"started": parallel._is_initialized, "count": thread_count(),
                  "recorded": provenance([])["threads"]}
        sim.run_steps(1)
        print(json.dumps({"before": before, "after": numba.get_num_threads()}))
    ''')
    env = dict(os.environ, NUMBA_NUM_THREADS="2")
    done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    result = json.loads(done.stdout.strip().splitlines()[-1])
    assert result["before"] == {"started": False, "count": 1, "recorded": 1}
    assert result["after"] == 1

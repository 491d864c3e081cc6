"""The README's Python example runs as printed (with a short end time), in a fresh interpreter."""

import os
import re
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def test_readme_python_example_runs(tmp_path):
    text = open(os.path.join(REPO, "README.md"), encoding="utf-8").read()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, "README.md has no python example"
    code = blocks[0]
    assert "sim.run(1.0)" in code and '"runs/mine"' in code
    # the same code, shorter: a few steps, output into the test's directory, then the named-case line
    code = code.replace("sim.run(1.0)", "sim.run(0.002, progress=False)")
    code = code.replace('"runs/mine"', repr(str(tmp_path / "mine")))
    line = re.search(r"`(sim = sw\.cases\.build\([^`]*\))`", text).group(1)
    code += "\n" + line.replace("dx=0.005", "dx=0.05") + "\nprint(type(sim).__name__, len(result.probes['P1']))\n"
    env = {**os.environ, "PYTHONPATH": REPO + os.pathsep + os.environ.get("PYTHONPATH", ""),
           "NUMBA_NUM_THREADS": os.environ.get("NUMBA_NUM_THREADS", "1")}
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.split()[0] == "Simulation"
    assert (tmp_path / "mine" / "fluid.pvd").exists() and (tmp_path / "mine" / "wall_wall.pvd").exists()

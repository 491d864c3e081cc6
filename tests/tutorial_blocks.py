"""Run the code of a tutorial in docs/tutorials/, block by block, in a folder of its own.

The fenced blocks of a tutorial, in the order they appear:

* ```` ```python file=NAME ```` and ```` ```toml file=NAME ````: written to NAME in the folder;
* ```` ```python run ````: executed there as a script (in this process, the folder on ``sys.path``);
* ```` ```bash ````: every line is one command (``#`` starts a comment): ``seawall ...`` runs
  through ``seawall.cli.main`` in this process, with the test's small settings appended to
  ``run``, ``compare`` and ``bench`` (argparse keeps the last value of an option, so they win
  over the tutorial's ``--dx`` and ``--t-end``); any other command is refused, so a tutorial
  cannot ask a reader for a step the test skips.

Plain ```` ```python ```` blocks (no ``file=`` or ``run``) are left to the tutorial's own test
(the wall-model tutorial assembles its compiled module from them).
"""

import contextlib
import io
import os
import re
import runpy
import shlex
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs" / "tutorials"
FENCE = re.compile(r"^```(\w+)([^\n]*)\n(.*?)^```", flags=re.S | re.M)


def blocks(name):
    """(language, info, text) of every fenced block of docs/tutorials/NAME, in order."""
    return [(lang, info.strip(), text) for lang, info, text in FENCE.findall((DOCS / name).read_text())]


def commands(text):
    """The commands of a bash block: one per line, comments and blank lines dropped."""
    out = []
    for line in text.splitlines():
        words = shlex.split(line, comments=True)
        if words:
            out.append(words)
    return out


def run_tutorial(name, folder, extra=None, replace=None):
    """Run docs/tutorials/NAME in ``folder``; ``extra[subcommand]`` is appended to those seawall commands,
    and each ``old -> new`` of ``replace`` is applied to the ``python run`` blocks (shorter runs); every
    ``old`` must occur in some block.

    Returns the printed output of every step, in order, as (what, text) pairs. A failing step raises
    AssertionError naming it.
    """
    from seawall.cli import main

    extra = extra or {}
    replace = dict(replace or {})
    unused = set(replace)
    folder = Path(folder)
    steps = []
    here = os.getcwd()
    os.chdir(folder)
    sys.path.insert(0, str(folder))
    modules_before = set(sys.modules)
    try:
        for lang, info, text in blocks(name):
            if info.startswith("file="):
                (folder / info[len("file="):]).write_text(text)
            elif lang == "python" and info == "run":
                buffer = io.StringIO()
                path = folder / f"_block_{len(steps)}.py"
                for old, new in replace.items():
                    if old in text:
                        text = text.replace(old, new)
                        unused.discard(old)
                path.write_text(text)
                with contextlib.redirect_stdout(buffer):
                    runpy.run_path(str(path), run_name="__main__")
                steps.append((text, buffer.getvalue()))
            elif lang == "bash":
                for words in commands(text):
                    assert words[0] == "seawall", f"{name}: command the test cannot run: {' '.join(words)}"
                    args = words[1:] + list(extra.get(words[1], ()))
                    buffer = io.StringIO()
                    with contextlib.redirect_stdout(buffer):
                        code = main(args)
                    assert code == 0, f"{name}: {' '.join(words)} exited with {code}: {buffer.getvalue()[-2000:]}"
                    steps.append((" ".join(words), buffer.getvalue()))
        assert not unused, f"{name}: the test's replacements {sorted(unused)} match no python block"
    finally:
        os.chdir(here)
        sys.path.remove(str(folder))
        for module in set(sys.modules) - modules_before:   # the tutorial's own modules go with its folder
            if getattr(sys.modules[module], "__file__", None) and str(folder) in str(sys.modules[module].__file__):
                del sys.modules[module]
    return steps

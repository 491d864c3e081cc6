"""Cases read from files: a Python module (``case.py``) or a declarative TOML file (``case.toml``).

Both become a :class:`~seawall.cases.Case`, so ``seawall run``, ``compare``,
``bench``, ``--set``, ``--boundary`` and ``--restart`` treat them as they
treat the built-in cases. The case records the file's path and its SHA-256
(``case_file``, ``case_sha256`` in the simulation's metadata); a restart
refuses a checkpoint written by a different version of the file.

A Python case file defines

* ``PARAMETERS``: a dict name -> :class:`~seawall.cases.Parameter` (default,
  help, type, unit); it must declare ``dx``;
* ``build(dx, boundary, **params)``: returns a :class:`~seawall.Simulation`
  (or any seawall runner); ``boundary`` is a function returning a fresh wall
  model of the chosen kind (call it once per wall system); ``threads`` is
  passed if ``build`` takes it;
* optionally ``NAME``, ``DESCRIPTION`` (default: the module docstring's first
  line), ``T_END``, ``OUTPUT_EVERY``, ``PROBE_EVERY``, ``DIMENSION`` and
  ``DEFAULT_BOUNDARY``.

The TOML form is described in docs/case-files.md and built by
:mod:`seawall.cases.toml_case`. A malformed file stops with one line naming
the file and the problem (:class:`~seawall.errors.ParameterError`).
"""

import hashlib
import importlib.util
import inspect
import os
import sys

from ..errors import ParameterError
from .base import Case, Parameter

SUFFIXES = (".py", ".toml")


def is_case_file(name):
    """Whether a case name given on the command line means a file (by its suffix or a path separator)."""
    name = str(name)
    return name.endswith(SUFFIXES) or os.sep in name or "/" in name


def file_digest(path):
    with open(path, "rb") as fh:
        return hashlib.sha256(fh.read()).hexdigest()


def load_case_file(path):
    """The :class:`Case` defined by the file at ``path`` (``.py`` or ``.toml``)."""
    path = str(path)
    if not path.endswith(SUFFIXES):
        raise ParameterError(f"case file {path}: a case file ends in .py or .toml")
    if not os.path.isfile(path):
        raise ParameterError(f"case file {path}: no such file")
    try:
        digest = file_digest(path)
    except OSError as exc:
        raise ParameterError(f"case file {path}: cannot be read ({exc.strerror or exc})") from None
    if path.endswith(".toml"):
        from .toml_case import case_from_toml

        case = case_from_toml(path)
    else:
        case = _case_from_module(path)
    case.source = {"path": os.path.abspath(path), "sha256": digest}
    return case


def _fail(path, message):
    return ParameterError(f"case file {path}: {message}")


def _load_module(path):
    stem = os.path.splitext(os.path.basename(path))[0]
    module_name = f"seawall_case_{abs(hash(os.path.abspath(path))):x}_{stem.replace('-', '_')}"
    spec = importlib.util.spec_from_file_location(module_name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module   # dataclasses and pickling look the module up by name
    try:
        spec.loader.exec_module(module)
    except SyntaxError as exc:
        sys.modules.pop(module_name, None)
        raise _fail(path, f"syntax error at line {exc.lineno}: {exc.msg}") from None
    except ParameterError as exc:
        sys.modules.pop(module_name, None)
        raise _fail(path, str(exc)) from None
    except Exception as exc:   # the user's module failed to import: say where, in one line
        sys.modules.pop(module_name, None)
        line = _user_line(exc, path)
        raise _fail(path, f"{type(exc).__name__} while loading{line}: {exc}") from None
    return module


def _user_line(exc, path):
    """' (line N)' of the innermost traceback frame in the case file, '' if none."""
    tb, line = exc.__traceback__, None
    target = os.path.abspath(path)
    while tb is not None:
        if os.path.abspath(tb.tb_frame.f_code.co_filename) == target:
            line = tb.tb_lineno
        tb = tb.tb_next
    return f" (line {line})" if line else ""


def _number(path, module, attr, default, kind=float):
    value = getattr(module, attr, default)
    try:
        value = kind(value)
    except (TypeError, ValueError):
        raise _fail(path, f"{attr} must be a number, got {value!r}") from None
    if not value > 0:
        raise _fail(path, f"{attr} must be > 0, got {value!r}")
    return value


def _case_from_module(path):
    module = _load_module(path)
    build = getattr(module, "build", None)
    if not callable(build):
        raise _fail(path, "defines no function build(dx, boundary, **params)")
    declared = getattr(module, "PARAMETERS", None)
    if not isinstance(declared, dict):
        raise _fail(path, "PARAMETERS must be a dict of name -> seawall.cases.Parameter")
    parameters = {}
    for key, spec in declared.items():
        if not isinstance(key, str) or not key.isidentifier():
            raise _fail(path, f"parameter name {key!r} is not a Python identifier")
        if not isinstance(spec, Parameter):
            raise _fail(path, f"parameter {key} must be a seawall.cases.Parameter(default, help, kind, unit), "
                              f"got {type(spec).__name__}")
        if spec.kind not in (float, int, str, bool):
            raise _fail(path, f"parameter {key}: kind must be float, int, str or bool, got {spec.kind!r}")
        parameters[key] = spec
    if "dx" not in parameters:
        raise _fail(path, "PARAMETERS must declare dx (the particle spacing [m])")
    if "boundary" in parameters or "threads" in parameters:
        raise _fail(path, "boundary and threads are not parameters (they are given by the command line)")
    signature = inspect.signature(build)
    takes_any = any(p.kind is p.VAR_KEYWORD for p in signature.parameters.values())
    accepted = set(signature.parameters)
    if "boundary" not in accepted and not takes_any:
        raise _fail(path, "build() must take boundary (a function returning a fresh wall model)")
    missing = [k for k in parameters if k not in accepted and not takes_any]
    if missing:
        raise _fail(path, f"build() does not take declared parameter {missing[0]}")
    pass_threads = "threads" in accepted

    def builder(params, wall_model, threads):
        from ..runner import Runner

        kwargs = dict(params)
        if pass_threads:
            kwargs["threads"] = threads
        try:
            sim = build(boundary=wall_model, **kwargs)
        except ParameterError as exc:
            raise _fail(path, str(exc)) from None
        except Exception as exc:   # an error in the user's build(): one line with its place in the file
            raise _fail(path, f"{type(exc).__name__} in build(){_user_line(exc, path)}: {exc}") from None
        if not isinstance(sim, Runner):
            raise _fail(path, f"build() returned {type(sim).__name__}, not a seawall.Simulation")
        if threads is not None and not pass_threads:
            from ..jit import use_threads

            use_threads(int(threads))   # applied when the run starts (seawall.compile_ahead)
        return sim

    doc = (module.__doc__ or "").strip().splitlines()
    name = getattr(module, "NAME", None) or os.path.splitext(os.path.basename(path))[0]
    if not isinstance(name, str) or not name or "," in name or "/" in name:
        raise _fail(path, f"NAME must be a non-empty string without ',' or '/', got {name!r}")
    dimension = _number(path, module, "DIMENSION", 2, int)
    if dimension not in (2, 3):
        raise _fail(path, f"DIMENSION must be 2 or 3, got {dimension}")
    default_boundary = getattr(module, "DEFAULT_BOUNDARY", "adami")
    from ..boundary.registry import BOUNDARIES

    if default_boundary not in BOUNDARIES:
        raise _fail(path, f"DEFAULT_BOUNDARY {default_boundary!r} is not a wall model; "
                          f"available: {', '.join(BOUNDARIES)}")
    return Case(name=name, description=str(getattr(module, "DESCRIPTION", None) or (doc[0] if doc else path)),
                builder=builder, parameters=parameters,
                t_end=_number(path, module, "T_END", 1.0), probe_every=_number(path, module, "PROBE_EVERY", 1e-3),
                output_every=_number(path, module, "OUTPUT_EVERY", 0.02), dimension=dimension,
                default_boundary=default_boundary)

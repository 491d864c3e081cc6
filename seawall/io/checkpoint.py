"""HDF5 checkpoints: named groups of numpy arrays plus a flat dict of attributes.

Arrays are stored exactly (dtype, byte order and shape are kept; large
arrays use lossless gzip level 1). Attributes that HDF5 cannot hold natively
(None, lists, dicts) are stored as JSON strings with a ``json:`` prefix and
decoded transparently on load.

The HDF5 image is built in memory and then written with plain file I/O to a
temporary sibling that is renamed over ``path``: the previous checkpoint
survives a crash during writing, and a full disk is an ordinary OSError
(the HDF5 library itself, writing to a full disk, crashed the process
with a segmentation fault when closing the file).
"""

import io
import json
import os

import h5py
import numpy as np

from .vtk import _atomic_write

__all__ = ["save_checkpoint", "load_checkpoint", "FORMAT", "FORMAT_VERSION"]

FORMAT = "seawall-checkpoint"
FORMAT_VERSION = 1
_RESERVED_ATTRS = ("format", "format_version")
_JSON_PREFIX = "json:"
_COMPRESS_ABOVE = 10_000


def _check_name(name, where):
    if not isinstance(name, str) or not name or "/" in name or name in (".", ".."):
        raise ValueError(f"{where}: names must be non-empty strings without '/', got {name!r}")


def _write_group(group, arrays, where):
    for name, value in arrays.items():
        _check_name(name, where)
        if isinstance(value, dict):
            _write_group(group.create_group(name, track_order=True), value, f"{where}/{name}")
            continue
        arr = np.asarray(value)
        if arr.dtype.kind in "OUV" and arr.dtype.names is None:
            raise TypeError(f"{where}/{name}: cannot store arrays of dtype {arr.dtype} "
                            "exactly (use numeric, bool or bytes arrays)")
        kwargs = {}
        if arr.size > _COMPRESS_ABOVE:
            kwargs = {"compression": "gzip", "compression_opts": 1}
        group.create_dataset(name, data=arr, **kwargs)


def _encode_attr(key, value):
    if isinstance(value, str):
        # A string that looks like our JSON marker must itself be escaped.
        return _JSON_PREFIX + json.dumps(value) if value.startswith(_JSON_PREFIX) else value
    if isinstance(value, (bool, np.bool_)):
        return np.bool_(value)
    if isinstance(value, int) and not isinstance(value, bool):
        if -2**63 <= value < 2**63:
            return np.int64(value)
        return _JSON_PREFIX + json.dumps(value)
    if isinstance(value, float):
        return np.float64(value)
    if isinstance(value, (np.generic, np.ndarray)):
        if value.dtype.kind in "OUV":
            raise TypeError(f"attribute {key!r}: dtype {value.dtype} is not supported")
        return value
    if value is None or isinstance(value, (list, tuple, dict)):
        try:
            return _JSON_PREFIX + json.dumps(value, default=_json_default)
        except TypeError as exc:
            raise TypeError(f"attribute {key!r} is not JSON serialisable: {exc}") from None
    raise TypeError(f"attribute {key!r} has unsupported type {type(value).__name__}")


def _json_default(obj):
    # numpy numbers inside lists/dicts are common (e.g. a domain box).
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"{type(obj).__name__} is not JSON serialisable")


def _decode_attr(value):
    if isinstance(value, bytes):
        value = value.decode("utf-8")
    if isinstance(value, str):
        return json.loads(value[len(_JSON_PREFIX):]) if value.startswith(_JSON_PREFIX) else value
    if isinstance(value, np.generic):
        return value.item()
    return value


def save_checkpoint(path, arrays, attrs=None):
    """Write ``arrays`` (group -> name -> array, may nest) and ``attrs`` to HDF5.

    ``attrs`` values may be str, bool, int, float, None, lists/tuples of
    numbers, dicts or numpy scalars/arrays; the keys ``format`` and
    ``format_version`` are reserved. Returns the path written.
    """
    path = os.fspath(path)
    attrs = dict(attrs or {})
    for key in attrs:
        if not isinstance(key, str):
            raise TypeError(f"attribute names must be strings, got {key!r}")
        if key in _RESERVED_ATTRS:
            raise ValueError(f"attribute name {key!r} is reserved for the checkpoint format")
    if not isinstance(arrays, dict):
        raise TypeError(f"arrays must be a dict of groups, got {type(arrays).__name__}")
    encoded = {key: _encode_attr(key, value) for key, value in attrs.items()}

    image = io.BytesIO()
    with h5py.File(image, "w", track_order=True) as f:
        f.attrs["format"] = FORMAT
        f.attrs["format_version"] = np.int64(FORMAT_VERSION)
        for key, value in encoded.items():
            f.attrs[key] = value
        _write_group(f, arrays, path)
    with _atomic_write(path, "wb") as fh:
        fh.write(image.getbuffer())
    return path


def _read_group(group):
    out = {}
    for name, item in group.items():
        if isinstance(item, h5py.Group):
            out[name] = _read_group(item)
        else:
            # [...] (not [()]) keeps 0-d datasets as arrays rather than scalars.
            out[name] = item[...]
    return out


def load_checkpoint(path):
    """Read a checkpoint written by :func:`save_checkpoint`.

    Returns ``(arrays, attrs)`` with the structure, dtypes and values that
    were saved. Raises FileNotFoundError if ``path`` does not exist and
    ValueError if it is not a seawall checkpoint (or a newer format version).
    """
    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(f"checkpoint file not found: {path}")
    if os.path.isdir(path):
        raise ValueError(f"{path} is a directory, not a seawall checkpoint")
    try:
        is_hdf5 = h5py.is_hdf5(path)
    except OSError as exc:
        raise ValueError(f"{path} cannot be read: {exc.strerror or exc}") from None
    if not is_hdf5:
        raise ValueError(f"{path} is not a seawall checkpoint (not an HDF5 file)")
    try:
        return _load(path)
    except OSError as exc:
        # h5py reports damaged and truncated files as OSError
        raise ValueError(f"{path} cannot be read as a checkpoint (truncated or damaged: {exc})") from None


def _load(path):
    with h5py.File(path, "r") as f:
        fmt = _decode_attr(f.attrs.get("format"))
        if fmt != FORMAT:
            raise ValueError(f"{path} is not a seawall checkpoint "
                             f"(format attribute is {fmt!r}, expected {FORMAT!r})")
        version = _decode_attr(f.attrs.get("format_version"))
        if not isinstance(version, int) or isinstance(version, bool) or version < 1:
            raise ValueError(f"{path}: invalid checkpoint format_version {version!r}")
        if version > FORMAT_VERSION:
            raise ValueError(f"{path}: checkpoint format_version {version} is newer than "
                             f"this seawall supports ({FORMAT_VERSION})")
        attrs = {key: _decode_attr(value) for key, value in f.attrs.items()
                 if key not in _RESERVED_ATTRS}
        arrays = _read_group(f)
    return arrays, attrs

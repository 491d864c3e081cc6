"""ParaView output: VTK XML UnstructuredGrid (.vtu) files, parallel (.pvtu) frames and .pvd time series.

Only numpy and the standard library are used. Every particle is written as
its own VTK_VERTEX cell, arrays use the inline ``binary`` encoding (base64 of
a UInt64 byte count followed by the little-endian payload, encoded as one
stream like VTK itself does; with ``compress=True`` the payload is split in
blocks of 32 KiB compressed by zlib, with VTK's block header -- number of
blocks, block size, last block size, compressed sizes -- encoded before it,
``compressor="vtkZLibDataCompressor"``), and every file is written to a
temporary file in the target directory and then renamed over the target, so
readers never see a half-written file.

A frame of a decomposed run is a ``.pvtu`` (VTK's PUnstructuredGrid): the
declarations of the point arrays and points (``PPointData``, ``PPoints``,
type and components as in every piece) and one ``<Piece Source="..."/>`` per
rank, each a ``.vtu`` of its own (:func:`write_pvtu`). :func:`read_vtu` and
:func:`read_vtu_metadata` read a ``.pvtu`` as the one grid its pieces make.

Metadata: numbers go to the grid's ``FieldData`` (ParaView shows them, and
reads ``TimeValue`` as the time); text metadata (model, version, the
pressure convention) is a JSON object in an XML comment ``<!-- seawall
{...} -->`` after the XML declaration, read back by :func:`read_vtu_metadata`.
"""

import base64
import contextlib
import json
import math
import os
import re
import uuid
import zlib
import xml.etree.ElementTree as ET
from xml.sax.saxutils import quoteattr

import numpy as np

__all__ = ["write_vtu", "write_pvtu", "read_vtu", "read_vtu_metadata", "pvtu_pieces", "PVDSeries"]

_VTK_VERTEX = 1

# numpy dtype (little-endian) <-> VTK type name; the writer maps bool to UInt8.
_VTK_TYPES = {
    "Float32": np.dtype("<f4"),
    "Float64": np.dtype("<f8"),
    "Int8": np.dtype("<i1"),
    "Int16": np.dtype("<i2"),
    "Int32": np.dtype("<i4"),
    "Int64": np.dtype("<i8"),
    "UInt8": np.dtype("<u1"),
    "UInt16": np.dtype("<u2"),
    "UInt32": np.dtype("<u4"),
    "UInt64": np.dtype("<u8"),
}
_HEADER_TYPES = {"UInt32": np.dtype("<u4"), "UInt64": np.dtype("<u8")}
_HEADER_TYPE = "UInt64"


# --------------------------------------------------------------------------
# atomic file replacement (shared with the other seawall.io modules)

def _fsync_dir(directory):
    # Makes the rename itself durable; not possible on every platform.
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


@contextlib.contextmanager
def _atomic_write(path, mode="wb", **open_kwargs):
    """Open a temporary sibling of ``path``; on success rename it over ``path``.

    On any exception the temporary file is removed and ``path`` is untouched.
    """
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    tmp = os.path.join(directory, f".{os.path.basename(path)}.{uuid.uuid4().hex[:12]}.tmp")
    # os.open with 0o666 honours the umask, unlike tempfile's private 0o600.
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
    try:
        with os.fdopen(fd, mode, **open_kwargs) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        raise
    _fsync_dir(directory)


# --------------------------------------------------------------------------
# .vtu writing

def _vtk_type_of(dtype):
    """VTK type name and the little-endian numpy dtype to write ``dtype`` as."""
    if dtype == np.bool_:
        return "UInt8", _VTK_TYPES["UInt8"]
    if dtype.kind == "f":
        name = "Float32" if dtype.itemsize == 4 else "Float64"
        return name, _VTK_TYPES[name]
    if dtype.kind in "iu":
        name = ("Int" if dtype.kind == "i" else "UInt") + str(8 * dtype.itemsize)
        if name in _VTK_TYPES:
            return name, _VTK_TYPES[name]
    raise TypeError(f"cannot write arrays of dtype {dtype} to VTK "
                    "(use float, integer or bool arrays)")


#: uncompressed bytes per zlib block (VTK's own default)
_BLOCK = 32768
_ZLIB = "vtkZLibDataCompressor"


def _encode(array, compress=False):
    """Inline ``binary`` payload: base64(UInt64 byte count + raw bytes), or with ``compress``
    base64(block header) + base64(zlib blocks) as VTK writes compressed inline data."""
    raw = np.ascontiguousarray(array).tobytes()
    htype = _HEADER_TYPES[_HEADER_TYPE]
    if not compress:
        header = np.array([len(raw)], dtype=htype).tobytes()
        return base64.b64encode(header + raw).decode("ascii")
    blocks = [zlib.compress(raw[k:k + _BLOCK], 6) for k in range(0, len(raw), _BLOCK)]
    last = len(raw) - _BLOCK * (len(blocks) - 1) if blocks else 0
    header = np.array([len(blocks), _BLOCK, last, *(len(b) for b in blocks)], dtype=htype).tobytes()
    return base64.b64encode(header).decode("ascii") + base64.b64encode(b"".join(blocks)).decode("ascii")


def _data_array(fh, array, ncomp, name=None, indent="        ", compress=False):
    vtk_type, dtype = _vtk_type_of(array.dtype)
    array = np.asarray(array, dtype=dtype)
    name_attr = f" Name={quoteattr(name)}" if name is not None else ""
    fh.write(f'{indent}<DataArray type="{vtk_type}"{name_attr} NumberOfComponents="{ncomp}" '
             f'format="binary">\n{indent}  {_encode(array, compress)}\n{indent}</DataArray>\n')


def _metadata_comment(metadata):
    """The XML comment holding ``metadata`` as JSON ('--' may not appear in a comment: escaped in the JSON)."""
    text = json.dumps(metadata, sort_keys=True, default=str).replace("--", "-\\u002d")
    return f"<!-- seawall {text} -->\n"


def _as_points(positions):
    pos = np.asarray(positions)
    if pos.ndim == 1 and pos.size == 0:
        pos = pos.reshape(0, 3)
    if pos.ndim != 2 or pos.shape[1] not in (2, 3):
        raise ValueError(f"positions must have shape (N, 2) or (N, 3), got {pos.shape}")
    if pos.dtype.kind not in "fiu":
        raise TypeError(f"positions must be numeric, got dtype {pos.dtype}")
    out = np.zeros((pos.shape[0], 3), dtype="<f8")
    out[:, :pos.shape[1]] = pos
    return out


def _as_point_array(name, value, n):
    if not isinstance(name, str) or not name:
        raise ValueError(f"point data names must be non-empty strings, got {name!r}")
    arr = np.asarray(value)
    if arr.ndim == 0 or arr.ndim > 2 or arr.shape[0] != n:
        raise ValueError(f"point data {name!r} must have shape ({n},) or ({n}, d), "
                         f"got {arr.shape}")
    _vtk_type_of(arr.dtype)  # reject unsupported dtypes before writing anything
    if arr.ndim == 2 and arr.shape[1] == 2:
        # ParaView treats only 3-component arrays as vectors (glyphs, arrows).
        arr = np.concatenate([arr, np.zeros((n, 1), dtype=arr.dtype)], axis=1)
    ncomp = 1 if arr.ndim == 1 else arr.shape[1]
    if ncomp < 1:
        raise ValueError(f"point data {name!r} has no components: shape {arr.shape}")
    return arr, ncomp


def _prepare(positions, point_data, float32):
    """Points (N, 3) and [(name, array, components)] as :func:`write_vtu` writes them."""
    points = _as_points(positions)
    n = points.shape[0]
    arrays = [(name, *_as_point_array(name, value, n))
              for name, value in (point_data or {}).items()]
    if float32:
        points = points.astype("<f4")
        arrays = [(name, arr.astype("<f4") if arr.dtype.kind == "f" else arr, ncomp) for name, arr, ncomp in arrays]
    return points, arrays


def write_vtu(path, positions, point_data=None, *, field_data=None, metadata=None, compress=False,
              float32=False):
    """Write particles as a VTK XML UnstructuredGrid of vertex cells.

    ``positions`` is (N, 2) or (N, 3) (2D is padded with z = 0). ``point_data``
    maps names to (N,) scalars or (N, d) vectors (d = 2 is padded to 3).
    Float32 arrays stay Float32, other floats become Float64 (Float32 with
    ``float32=True``, points included), integers keep their width, bool
    becomes UInt8. ``field_data`` maps names to numbers or 1D arrays of
    numbers (the grid's FieldData, e.g. ``TimeValue``); ``metadata`` is a
    JSON-able dict stored in an XML comment (see :func:`read_vtu_metadata`).
    ``compress=True``: zlib-compressed arrays. Returns the path written.
    """
    points, arrays = _prepare(positions, point_data, float32)
    n = points.shape[0]
    fields = []
    for name, value in (field_data or {}).items():
        arr = np.atleast_1d(np.asarray(value, dtype=np.float64))
        if arr.ndim != 1 or not name:
            raise ValueError(f"field data {name!r} must be a number or a 1D array, got shape {arr.shape}")
        fields.append((name, arr))

    path = os.fspath(path)
    with _atomic_write(path, "w", encoding="ascii", newline="\n") as fh:
        _open_vtk_file(fh, "UnstructuredGrid", metadata, compress)
        fh.write('  <UnstructuredGrid>\n')
        if fields:
            fh.write('    <FieldData>\n')
            for name, arr in fields:
                values = " ".join(repr(float(v)) for v in arr)
                fh.write(f'      <DataArray type="Float64" Name={quoteattr(name)} NumberOfTuples="{arr.size}" '
                         f'format="ascii">{values}</DataArray>\n')
            fh.write('    </FieldData>\n')
        fh.write(f'    <Piece NumberOfPoints="{n}" NumberOfCells="{n}">\n'
                 '      <PointData>\n')
        for name, arr, ncomp in arrays:
            _data_array(fh, arr, ncomp, name, compress=compress)
        fh.write('      </PointData>\n'
                 '      <Points>\n')
        _data_array(fh, points, 3, "Points", compress=compress)
        fh.write('      </Points>\n'
                 '      <Cells>\n')
        ids = np.arange(n, dtype="<i8")
        _data_array(fh, ids, 1, "connectivity", compress=compress)
        _data_array(fh, ids + 1, 1, "offsets", compress=compress)
        _data_array(fh, np.full(n, _VTK_VERTEX, dtype="<u1"), 1, "types", compress=compress)
        fh.write('      </Cells>\n'
                 '    </Piece>\n'
                 '  </UnstructuredGrid>\n'
                 '</VTKFile>\n')
    return path


def _open_vtk_file(fh, kind, metadata, compress):
    """The XML declaration, the metadata comment and the <VTKFile> element of a file of type ``kind``."""
    fh.write('<?xml version="1.0"?>\n')
    if metadata:
        fh.write(_metadata_comment(metadata))
    fh.write(f'<VTKFile type="{kind}" version="1.0" byte_order="LittleEndian" '
             f'header_type="{_HEADER_TYPE}"' + (f' compressor="{_ZLIB}"' if compress else '') + '>\n')


def write_pvtu(path, sources, positions, point_data=None, *, metadata=None, compress=False, float32=False):
    """Write a parallel frame: a PUnstructuredGrid (.pvtu) naming the pieces ``sources`` (.vtu files
    relative to the .pvtu's directory, written by :func:`write_vtu`).

    ``positions`` and ``point_data`` are one piece's arrays (any number of rows, none included): the
    declarations (name, type, components) are those :func:`write_vtu` gives them with the same
    ``float32``, so they match every piece written with the same names and dtypes. The pieces carry
    the FieldData; ``metadata`` is stored in the same XML comment as in a .vtu. Returns the path.
    """
    points, arrays = _prepare(positions, point_data, float32)
    if not sources:
        raise ValueError("a .pvtu needs at least one piece")
    path = os.fspath(path)
    with _atomic_write(path, "w", encoding="ascii", newline="\n") as fh:
        _open_vtk_file(fh, "PUnstructuredGrid", metadata, compress)
        fh.write('  <PUnstructuredGrid GhostLevel="0">\n'
                 '    <PPointData>\n')
        for name, arr, ncomp in arrays:
            fh.write(f'      <PDataArray type="{_vtk_type_of(arr.dtype)[0]}" Name={quoteattr(name)} '
                     f'NumberOfComponents="{ncomp}"/>\n')
        fh.write('    </PPointData>\n'
                 '    <PPoints>\n'
                 f'      <PDataArray type="{_vtk_type_of(points.dtype)[0]}" Name="Points" NumberOfComponents="3"/>\n'
                 '    </PPoints>\n')
        for source in sources:
            fh.write(f'    <Piece Source={quoteattr(os.fspath(source))}/>\n')
        fh.write('  </PUnstructuredGrid>\n'
                 '</VTKFile>\n')
    return path


# --------------------------------------------------------------------------
# .vtu reading

def _decode(text, dtype, header_dtype, where):
    text = "".join(text.split())
    hsize = header_dtype.itemsize
    hchars = 4 * math.ceil(hsize / 3)
    if len(text) < hchars:
        raise ValueError(f"{where}: binary data array is truncated")
    try:
        if len(text) > hchars and text[hchars - 1] == "=":
            # Padding inside the text: header and payload were encoded separately.
            nbytes = int(np.frombuffer(base64.b64decode(text[:hchars]), header_dtype)[0])
            payload = base64.b64decode(text[hchars:])
        else:
            blob = base64.b64decode(text)
            nbytes = int(np.frombuffer(blob[:hsize], header_dtype)[0])
            payload = blob[hsize:]
    except (ValueError, IndexError) as exc:
        raise ValueError(f"{where}: invalid base64 data ({exc})") from None
    if len(payload) < nbytes or nbytes % dtype.itemsize:
        raise ValueError(f"{where}: data array holds {len(payload)} bytes, header says {nbytes}")
    return np.frombuffer(payload[:nbytes], dtype=dtype).copy()


def _b64(text, where):
    try:
        return base64.b64decode(text)
    except ValueError as exc:
        raise ValueError(f"{where}: invalid base64 data ({exc})") from None


def _decode_zlib(text, dtype, header_dtype, where):
    """Inline compressed data: base64(header [nblocks, block size, last size, sizes...]) + base64(blocks)."""
    text = "".join(text.split())
    hsize = header_dtype.itemsize
    first = 4 * math.ceil(3 * hsize / 3)
    if len(text) < first:
        raise ValueError(f"{where}: compressed data array is truncated")
    nblocks = int(np.frombuffer(_b64(text[:first], where)[:hsize], header_dtype)[0])
    hchars = 4 * math.ceil((3 + nblocks) * hsize / 3)
    header = np.frombuffer(_b64(text[:hchars], where)[:(3 + nblocks) * hsize], header_dtype)
    if header.size != 3 + nblocks:
        raise ValueError(f"{where}: compressed data header is truncated")
    blob = _b64(text[hchars:], where)
    out, pos = [], 0
    try:
        for size in header[3:]:
            out.append(zlib.decompress(blob[pos:pos + int(size)]))
            pos += int(size)
    except zlib.error as exc:
        raise ValueError(f"{where}: damaged compressed data ({exc})") from None
    raw = b"".join(out)
    if len(raw) % dtype.itemsize:
        raise ValueError(f"{where}: compressed data holds {len(raw)} bytes, not whole {dtype} values")
    return np.frombuffer(raw, dtype=dtype).copy()


def _read_data_array(elem, header_dtype, where, compressed=False):
    vtk_type = elem.get("type")
    if vtk_type not in _VTK_TYPES:
        raise ValueError(f"{where}: unsupported DataArray type {vtk_type!r}")
    dtype = _VTK_TYPES[vtk_type]
    fmt = elem.get("format", "ascii")
    if fmt == "binary" and compressed:
        flat = _decode_zlib(elem.text or "", dtype, header_dtype, where)
    elif fmt == "binary":
        flat = _decode(elem.text or "", dtype, header_dtype, where)
    elif fmt == "ascii":
        flat = np.array((elem.text or "").split(), dtype=dtype)
    else:
        raise ValueError(f"{where}: DataArray format {fmt!r} is not supported")
    ncomp = int(elem.get("NumberOfComponents", "1"))
    if ncomp < 1 or flat.size % ncomp:
        raise ValueError(f"{where}: {flat.size} values do not split into {ncomp} components")
    return flat.astype(dtype.newbyteorder("="), copy=False), ncomp


def _parse(path):
    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(f"VTU file not found: {path}")
    try:
        return ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise ValueError(f"{path} is not a valid VTK XML file: {exc}") from None


def pvtu_pieces(path):
    """The pieces' paths of a .pvtu (in the order it lists them) and its declared point arrays,
    {name: (VTK type, components)}."""
    path = os.fspath(path)
    return _pvtu_pieces(_parse(path), path)


def _pvtu_pieces(root, path):
    if root.tag != "VTKFile" or root.get("type") != "PUnstructuredGrid":
        raise ValueError(f"{path} is not a VTK XML PUnstructuredGrid file")
    grid = root.find("./PUnstructuredGrid")
    sources = [p.get("Source") for p in grid.findall("./Piece")] if grid is not None else []
    if not sources or any(not s for s in sources):
        raise ValueError(f"{path}: no pieces (<Piece Source=.../>)")
    directory = os.path.dirname(path)
    return [os.path.join(directory, s) for s in sources], {
        e.get("Name"): (e.get("type"), int(e.get("NumberOfComponents", "1")))
        for e in grid.findall("./PPointData/PDataArray")}


def _read_pvtu(root, path):
    pieces, declared = _pvtu_pieces(root, path)
    parts = [read_vtu(p) for p in pieces]
    for piece, (_, data) in zip(pieces, parts):      # a piece of another frame or run would not match
        names = set(data)
        if names != set(declared):
            raise ValueError(f"{path}: piece {os.path.basename(piece)} holds arrays {sorted(names)}, "
                             f"the .pvtu declares {sorted(declared)}")
    positions = np.concatenate([x for x, _ in parts])
    return positions, {name: np.concatenate([d[name] for _, d in parts]) for name in declared}


def read_vtu(path):
    """Read a .vtu written by :func:`write_vtu`, or a .pvtu written by :func:`write_pvtu` (its pieces
    joined in the order it lists them).

    Returns ``(positions, point_data)``: positions (N, 3) float64 and a dict
    name -> (N,) for scalars or (N, ncomp) for vectors (2D vectors come back
    with the padded zero z column). Bool arrays come back as uint8.
    """
    path = os.fspath(path)
    root = _parse(path)
    if root.tag == "VTKFile" and root.get("type") == "PUnstructuredGrid":
        return _read_pvtu(root, path)
    if root.tag != "VTKFile" or root.get("type") != "UnstructuredGrid":
        raise ValueError(f"{path} is not a VTK XML UnstructuredGrid file")
    compressor = root.get("compressor")
    if compressor and compressor != _ZLIB:
        raise ValueError(f"{path}: compressor {compressor!r} is not supported (only {_ZLIB})")
    compressed = bool(compressor)
    if root.get("byte_order", "LittleEndian") != "LittleEndian":
        raise ValueError(f"{path}: only LittleEndian VTU files are supported")
    header_name = root.get("header_type", "UInt32")
    if header_name not in _HEADER_TYPES:
        raise ValueError(f"{path}: unsupported header_type {header_name!r}")
    header_dtype = _HEADER_TYPES[header_name]
    pieces = root.findall("./UnstructuredGrid/Piece")
    if len(pieces) != 1:
        raise ValueError(f"{path}: expected exactly one Piece, found {len(pieces)}")
    piece = pieces[0]
    n = int(piece.get("NumberOfPoints", "0"))

    pts_elem = piece.find("./Points/DataArray")
    if pts_elem is None:
        raise ValueError(f"{path}: no Points array")
    flat, ncomp = _read_data_array(pts_elem, header_dtype, f"{path}: Points", compressed)
    if ncomp != 3 or flat.size != 3 * n:
        raise ValueError(f"{path}: Points array does not hold {n} 3D points")
    positions = flat.reshape(n, 3).astype(np.float64, copy=False)

    data = {}
    for elem in piece.findall("./PointData/DataArray"):
        name = elem.get("Name")
        flat, ncomp = _read_data_array(elem, header_dtype, f"{path}: point data {name!r}", compressed)
        if flat.size != n * ncomp:
            raise ValueError(f"{path}: point data {name!r} has {flat.size} values, "
                             f"expected {n * ncomp}")
        data[name] = flat if ncomp == 1 else flat.reshape(n, ncomp)
    return positions, data


def read_vtu_metadata(path):
    """The metadata of a .vtu written by :func:`write_vtu`: the FieldData numbers (name -> float, or a list
    for several values) and the entries of the ``<!-- seawall {...} -->`` comment; {} if it has neither.
    Of a .pvtu: its comment and the FieldData of its first piece (every piece carries the same)."""
    path = os.fspath(path)
    with open(path, "r", encoding="ascii", errors="replace") as fh:
        head = fh.read(4096)
    out = {}
    found = re.search(r"<!-- seawall (\{.*?\}) -->", head)
    if found:
        try:
            out.update(json.loads(found.group(1)))
        except ValueError:
            raise ValueError(f"{path}: the seawall metadata comment is not valid JSON") from None
    root = _parse(path)
    if root.get("type") == "PUnstructuredGrid":
        fields = read_vtu_metadata(_pvtu_pieces(root, path)[0][0])
        fields.pop("piece", None)          # the first piece's number, not the frame's
        return {**fields, **out}
    for elem in root.findall("./UnstructuredGrid/FieldData/DataArray"):
        values = [float(v) for v in (elem.text or "").split()]
        out[elem.get("Name")] = values[0] if len(values) == 1 else values
    return out


# --------------------------------------------------------------------------
# .pvd collections

class PVDSeries:
    """A time series of .vtu files listed in a ParaView .pvd collection.

    ``write`` creates ``{directory}/{name}_{k:05d}.vtu`` and rewrites
    ``{directory}/{name}.pvd`` atomically, so the collection is valid after
    every step, even if the run dies later. With ``resume=True`` an existing
    collection is read back, entries with time > ``resume_after`` are dropped
    and numbering continues after the last kept entry (the .vtu files of
    dropped entries are overwritten as the run catches up). Without
    ``resume`` any previous collection of that name is replaced by an empty one.
    ``add`` lists a frame the caller wrote (a decomposed run's ``{name}_{k:05d}.pvtu``).
    """

    def __init__(self, directory, name, *, resume=False, resume_after=None):
        if not isinstance(name, str) or not name or os.sep in name or "/" in name:
            raise ValueError(f"series name must be a non-empty file name, got {name!r}")
        self.directory = os.fspath(directory)
        self.name = name
        os.makedirs(self.directory, exist_ok=True)
        self.pvd_path = os.path.join(self.directory, f"{name}.pvd")
        self._entries = []
        self._next_index = 0
        if resume and os.path.exists(self.pvd_path):
            entries = self._parse_pvd(self.pvd_path)
            if resume_after is not None:
                entries = [(t, f) for t, f in entries if t <= float(resume_after)]
            self._entries = entries
            self._next_index = self._index_after(entries)
        self._write_pvd()

    @property
    def files(self):
        """List of (time, filename relative to the .pvd directory)."""
        return list(self._entries)

    def write(self, time, positions, point_data=None, **options):
        """Write one snapshot at ``time``; returns the .vtu path (``options``: those of :func:`write_vtu`)."""
        time = float(time)
        if not math.isfinite(time):
            raise ValueError(f"snapshot time must be finite, got {time!r}")
        filename = f"{self.name}_{self._next_index:05d}.vtu"
        path = os.path.join(self.directory, filename)
        write_vtu(path, positions, point_data, **options)
        self._entries.append((time, filename))
        self._next_index += 1
        self._write_pvd()
        return path

    @property
    def next_index(self):
        """The number the next frame's file takes (``{name}_{k:05d}``)."""
        return self._next_index

    def add(self, time, filename):
        """List a frame written by the caller (a .pvtu and its pieces) at ``time``; it takes the next number."""
        time = float(time)
        if not math.isfinite(time):
            raise ValueError(f"snapshot time must be finite, got {time!r}")
        self._entries.append((time, os.fspath(filename)))
        self._next_index += 1
        self._write_pvd()

    def _index_after(self, entries):
        pattern = re.compile(re.escape(self.name) + r"_(\d+)\.p?vtu$")
        indices = [int(m.group(1)) for _, f in entries if (m := pattern.match(f))]
        return max(indices) + 1 if indices else len(entries)

    def _write_pvd(self):
        lines = ['<?xml version="1.0"?>',
                 '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
                 '  <Collection>']
        for t, f in self._entries:
            # repr() round-trips the float exactly.
            lines.append(f'    <DataSet timestep="{t!r}" group="" part="0" file={quoteattr(f)}/>')
        lines += ['  </Collection>', '</VTKFile>', '']
        with _atomic_write(self.pvd_path, "w", encoding="utf-8", newline="\n") as fh:
            fh.write("\n".join(lines))

    @staticmethod
    def _parse_pvd(path):
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError as exc:
            raise ValueError(f"{path} is not a valid .pvd file: {exc}") from None
        if root.tag != "VTKFile" or root.get("type") != "Collection":
            raise ValueError(f"{path} is not a VTK Collection (.pvd) file")
        entries = []
        for ds in root.iter("DataSet"):
            try:
                entries.append((float(ds.get("timestep", "0")), ds.get("file")))
            except ValueError:
                raise ValueError(f"{path}: bad timestep {ds.get('timestep')!r}") from None
            if entries[-1][1] is None:
                raise ValueError(f"{path}: DataSet without a file attribute")
        return entries

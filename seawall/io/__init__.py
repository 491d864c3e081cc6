"""File input/output: ParaView VTU/PVTU/PVD series, HDF5 checkpoints, probe CSV files."""

from .checkpoint import load_checkpoint, save_checkpoint
from .csvout import ProbeCSVWriter, read_probes_csv, write_probes_csv
from .vtk import PVDSeries, read_vtu, read_vtu_metadata, write_pvtu, write_vtu

__all__ = [
    "write_vtu",
    "write_pvtu",
    "read_vtu",
    "read_vtu_metadata",
    "PVDSeries",
    "save_checkpoint",
    "load_checkpoint",
    "write_probes_csv",
    "read_probes_csv",
    "ProbeCSVWriter",
]

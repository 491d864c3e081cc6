"""Output callbacks: VTU/PVD snapshots for ParaView and HDF5 checkpoints."""

import os

import numpy as np

from .errors import require_positive
from .schedule import first_due_after, next_due


#: the pressure convention of every VTU field named "pressure" (fluid and walls), written into each file
PRESSURE_CONVENTION = "gauge: p - p_background [Pa] (p_background in FieldData; pressure_absolute on walls)"


class VTK:
    """Write the fluid and wall particles every ``every`` seconds as VTU/PVD series.

    Files: ``DIR/fluid.pvd`` + ``DIR/fluid_00000.vtu``...; each wall as
    ``DIR/wall_<name>.pvd`` with a file at every fluid frame (moving or not,
    so the wall pressure during an impact can be followed in ParaView).
    Point data: fluid velocity, pressure, density, mass, id; walls id,
    velocity, pressure and density (where the model keeps them), normals and
    mirror points (2 x surface point - position, where the model has them),
    ``force``: the fluid's force on each wall particle [N, N/m in 2D], for models
    that push by one pair force per wall particle (``pairwise_momentum``;
    :mod:`seawall.boundary.particle_forces`), summing to ``wall_force``.

    Pressure convention: ``pressure`` is gauge pressure, p - p_background
    [Pa], in the fluid and wall files alike (the background pressure is 0
    for the Tait and linear EOS without one). Wall files also keep the
    absolute pressure the model holds as ``pressure_absolute`` (until 0.1.0
    the wall ``pressure`` field was that absolute value). Every file carries
    FieldData ``TimeValue`` [s], ``h`` [m], ``dx`` [m], ``p_background`` [Pa]
    and, for walls, ``wall_force`` (the fluid's force on that wall system
    [N, N/m in 2D]), and a metadata comment with the case, wall model,
    seawall version and pressure convention (:func:`seawall.io.read_vtu_metadata`).

    ``compress`` (default True): zlib-compressed arrays; ``float32``: write
    floating-point arrays and positions in single precision (about half the
    size again; the particle ids stay exact).

    A decomposed run (``mpiexec``) writes each fluid frame as ``fluid_k.pvtu`` with one piece
    ``fluid_k_p<rank>.vtu`` per rank, listed in the same ``fluid.pvd``; ``gather=True`` writes the
    serial ``fluid_k.vtu`` instead (:class:`seawall.parallel.distributed.DecomposedVTK`).
    """

    def __init__(self, directory, *, every=0.02, walls=True, compress=True, float32=False, gather=False):
        self.directory = str(directory)
        # decomposed runs only: gather the fluid on rank 0 into serial .vtu frames instead of per-rank pieces
        self.gather = bool(gather)
        self.every = require_positive("every", every)
        self.walls = bool(walls)
        self.compress = bool(compress)
        self.float32 = bool(float32)
        self._fluid = None
        self._wall_series = {}
        self.next_time = 0.0

    def open(self, sim, resume_after=None):
        from .io.vtk import PVDSeries

        os.makedirs(self.directory, exist_ok=True)
        resume = resume_after is not None
        self._fluid = PVDSeries(self.directory, "fluid", resume=resume, resume_after=resume_after)
        if self.walls:
            forces = getattr(sim, "wall_forces", None)
            for wall in sim.walls:
                self._wall_series[wall.name] = PVDSeries(self.directory, f"wall_{wall.name}",
                                                         resume=resume, resume_after=resume_after)
                if forces is not None:   # the fluid's force on each wall is then computed with the rates
                    forces.setdefault(wall.name, np.zeros(sim.dim))
        if resume:
            self.next_time = first_due_after(resume_after, self.every)

    def due(self, t):
        return t >= self.next_time - 1e-12

    def _metadata(self, sim, what):
        from . import __version__

        md = sim.metadata
        gravity = getattr(sim, "gravity", None)
        return {"seawall_version": __version__, "case": md.get("case"), "boundary": md.get("boundary"),
                "wall_model": what, "time": sim.time, "step": sim.step, "h": sim.h,
                "kernel": type(getattr(sim, "kernel", None)).__name__, "dimension": sim.dim,
                "dx": sim.fluid.spacing, "pressure_convention": PRESSURE_CONVENTION,
                # the volume m / rho0 of `seawall discharge` needs it
                "rho0": float(sim.physics.rho0),
                # the sensors of `seawall sample` extrapolate the pressure to the wall with it
                "gravity": None if gravity is None else [float(g) for g in gravity]}

    def _options(self, sim, extra=None):
        p_bg = float(sim.physics.p_background)
        fields = {"TimeValue": sim.time, "h": sim.h, "dx": sim.fluid.spacing, "p_background": p_bg, **(extra or {})}
        return {"field_data": fields, "compress": self.compress, "float32": self.float32}

    @staticmethod
    def fluid_point_data(sim, fp):
        """The point data of a fluid frame of the particles ``fp``."""
        return {"velocity": fp["v"], "pressure": fp["p"] - float(sim.physics.p_background),
                "density": fp["rho"], "mass": fp["m"], "id": fp["id"],
                **({"zone": fp["zone"]} if "zone" in fp else {})}

    def write(self, sim):
        fp = sim.fluid.particles
        self._fluid.write(sim.time, fp["x"], self.fluid_point_data(sim, fp),
                          metadata=self._metadata(sim, "fluid"), **self._options(sim))
        self.write_walls(sim)
        self.next_time = next_due(self.next_time, self.every, sim.time)

    def write_walls(self, sim):
        """One frame of every wall series."""
        p_bg = float(sim.physics.p_background)
        forces = getattr(sim, "wall_forces", {})
        for wall in sim.walls:
            series = self._wall_series.get(wall.name)
            if series is None:
                continue
            pa = wall.particles
            data = {"id": pa["id"], "velocity": pa["v"]}
            if "p" in pa:
                data["pressure"] = pa["p"] - p_bg
                data["pressure_absolute"] = pa["p"]
            if "rho" in pa:
                data["density"] = pa["rho"]
            if "normal" in pa:
                data["normal"] = pa["normal"]
            if "surface" in pa:
                # where each wall particle's state is read by mirror-point (ghost) models
                data["mirror_point"] = 2.0 * pa["surface"] - pa["x"]
            force = getattr(sim, "wall_particle_forces", {}).get(wall.name)
            if force is not None:
                # the fluid's force on each wall particle [N, N/m in 2D] (seawall.boundary.particle_forces)
                data["force"] = force
            model = getattr(wall, "model", None)
            extra = {"wall_force": forces[wall.name]} if wall.name in forces else {}
            series.write(sim.time, pa["x"], data, metadata=self._metadata(sim, f"{getattr(model, 'name', '')} ({type(model).__name__})"),
                         **self._options(sim, extra))

    def last_time(self):
        """Time of the last snapshot written [s], None before the first."""
        files = self._fluid.files if self._fluid is not None else []
        return files[-1][0] if files else None

    def write_state(self, sim, filename):
        """One-off snapshot of the fluid (used to keep the state of a run that blew up)."""
        from .io.vtk import write_vtu

        fp = sim.fluid.particles
        write_vtu(os.path.join(self.directory, filename), fp["x"], {
            "velocity": fp["v"], "pressure": fp["p"] - float(sim.physics.p_background), "density": fp["rho"],
            "id": fp["id"]}, metadata=self._metadata(sim, "fluid"), **self._options(sim))


class Checkpoint:
    """Write an HDF5 checkpoint every ``every`` seconds to ``DIR/checkpoint.h5``.

    The file is replaced atomically, so the last good checkpoint survives a
    crash or a blow-up; :meth:`seawall.Simulation.restart` continues from it.
    """

    def __init__(self, directory, *, every=0.1, filename="checkpoint.h5"):
        self.directory = str(directory)
        self.every = require_positive("every", every)
        self.path = os.path.join(self.directory, filename)
        self.next_time = self.every
        self.last_written = None

    def open(self, sim, resume_after=None):
        os.makedirs(self.directory, exist_ok=True)
        if resume_after is not None:
            self.next_time = first_due_after(resume_after, self.every)

    def due(self, t):
        return t >= self.next_time - 1e-12

    def write(self, sim):
        sim.save_checkpoint(self.path)
        self.last_written = self.path
        self.next_time = next_due(self.next_time, self.every, sim.time)

"""Output callbacks: VTU/PVD snapshots for ParaView and HDF5 checkpoints."""

import os


from .errors import require_positive
from .schedule import first_due_after, next_due


class VTK:
    """Write the fluid (and wall) particles every ``every`` seconds as a VTU/PVD series.

    Files: ``DIR/fluid.pvd`` + ``DIR/fluid_00000.vtu``...; each wall as
    ``DIR/wall_<name>.pvd`` (written once if the wall does not move).
    Point data: velocity, pressure, density, mass, id; walls also pressure,
    density, normals and mirror points (2 x surface point - position), so the
    geometry of ghost-particle walls can be inspected in ParaView.
    """

    def __init__(self, directory, *, every=0.02, walls=True):
        self.directory = str(directory)
        self.every = require_positive("every", every)
        self.walls = bool(walls)
        self._fluid = None
        self._wall_series = {}
        self.next_time = 0.0

    def open(self, sim, resume_after=None):
        from .io.vtk import PVDSeries

        os.makedirs(self.directory, exist_ok=True)
        resume = resume_after is not None
        self._fluid = PVDSeries(self.directory, "fluid", resume=resume, resume_after=resume_after)
        if self.walls:
            for wall in sim.walls:
                self._wall_series[wall.name] = PVDSeries(self.directory, f"wall_{wall.name}",
                                                         resume=resume, resume_after=resume_after)
        if resume:
            self.next_time = first_due_after(resume_after, self.every)

    def due(self, t):
        return t >= self.next_time - 1e-12

    def write(self, sim):
        fp = sim.fluid.particles
        self._fluid.write(sim.time, fp["x"], {
            "velocity": fp["v"], "pressure": fp["p"] - sim.physics.p_background,
            "density": fp["rho"], "mass": fp["m"], "id": fp["id"],
            **({"zone": fp["zone"]} if "zone" in fp else {})})
        for wall in sim.walls:
            series = self._wall_series.get(wall.name)
            if series is None or (series.files and not sim.wall_moves(wall)):
                continue
            pa = wall.particles
            data = {"id": pa["id"], "velocity": pa["v"]}
            for name in ("p", "rho"):
                if name in pa:
                    data["pressure" if name == "p" else "density"] = pa[name]
            if "normal" in pa:
                data["normal"] = pa["normal"]
            if "surface" in pa:
                # where each wall particle's state is read by mirror-point (ghost) models
                data["mirror_point"] = 2.0 * pa["surface"] - pa["x"]
            series.write(sim.time, pa["x"], data)
        self.next_time = next_due(self.next_time, self.every, sim.time)

    def last_time(self):
        """Time of the last snapshot written [s], None before the first."""
        files = self._fluid.files if self._fluid is not None else []
        return files[-1][0] if files else None

    def write_state(self, sim, filename):
        """One-off snapshot of the fluid (used to keep the state of a run that blew up)."""
        from .io.vtk import write_vtu

        fp = sim.fluid.particles
        write_vtu(os.path.join(self.directory, filename), fp["x"], {
            "velocity": fp["v"], "pressure": fp["p"], "density": fp["rho"], "id": fp["id"]})


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

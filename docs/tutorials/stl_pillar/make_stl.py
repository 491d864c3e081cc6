"""Write the STL files of the 3D pillar case: an open tank, a square pillar and a water column.

Plain numpy through seawall.meshes (no trimesh needed to write them):

    python make_stl.py            # writes tank.stl, pillar.stl, column.stl here

Normals point into the fluid: the tank's inwards (fluid = "inside"), the
pillar's outwards (fluid = "outside"). The pillar has no bottom face: it
stands on the floor, and a face covered by another wall is refused. The column is the region the water
fills at t = 0 (either orientation).
"""

import os

from seawall.meshes import box_mesh, write_stl

HERE = os.path.dirname(os.path.abspath(__file__))

TANK = ([0.0, 0.0, 0.0], [0.8, 0.4, 0.6])        # interior [m], closed (the run-up would jump an open top)
PILLAR = ([0.5, 0.15, 0.0], [0.6, 0.25, 0.5])     # standing on the floor: open at its foot
COLUMN = ([0.0, 0.0, 0.0], [0.3, 0.4, 0.3])       # the water at t = 0


def main(folder=HERE):
    paths = [write_stl(os.path.join(folder, "tank.stl"), box_mesh(*TANK, inward=True), "tank"),
             write_stl(os.path.join(folder, "pillar.stl"), box_mesh(*PILLAR, open_bottom=True), "pillar"),
             write_stl(os.path.join(folder, "column.stl"), box_mesh(*COLUMN), "column")]
    for path in paths:
        print(path)
    return paths


if __name__ == "__main__":
    main()

"""Figure of the pillar case's results: the x force on the pillar and the surge front, per wall model.

    seawall run pillar.toml --boundary adami --out runs/adami
    seawall run pillar.toml --boundary dbc --out runs/dbc
    python plot_force.py runs/adami runs/dbc --out ../../img/stl_pillar_force.png
"""

import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", help="run directories of seawall run pillar.toml")
    parser.add_argument("--out", default="stl_pillar_force.png")
    args = parser.parse_args(argv)
    fig, (ax_f, ax_x) = plt.subplots(2, 1, figsize=(6.4, 5.2), sharex=True)
    for run in args.runs:
        data = np.genfromtxt(os.path.join(run, "probes.csv"), delimiter=",", names=True)
        label = os.path.basename(os.path.normpath(run))
        ax_f.plot(data["t"], data["pillar_force_x"], lw=0.9, label=label)
        ax_x.plot(data["t"], data["front"], lw=0.9, label=label)
    ax_f.set_ylabel("force on the pillar, x [N]")
    ax_x.set_ylabel("surge front x [m]")
    ax_x.set_xlabel("t [s]")
    ax_x.axhline(0.5, color="0.6", lw=0.6, ls="--")
    ax_x.text(0.01, 0.52, "pillar face", color="0.4", fontsize=8)
    for ax in (ax_f, ax_x):
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    ax_f.set_title("STL pillar case, dx = 0.025 m (2304 fluid particles)", fontsize=10)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(args.out)


if __name__ == "__main__":
    main()

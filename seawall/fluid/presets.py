"""Named fluid schemes: the configured pieces of a FluidSystem and its kernel.

``marrone2011`` -- the delta-SPH scheme of Marrone et al. (2011) as seed 001
(Huang et al. 2019) writes it in sec. 2.1, eq. 5-7:

* linear equation of state p = c0^2 (rho - rho0)                (eq. 3, 5);
* density diffusion delta h c0 sum psi_ij . grad W V_j with the
  renormalised density gradient rho^L (eq. 5-6), delta = 0.1;
* artificial viscosity alpha h c0 rho0 sum pi_ij . grad W V_j, alpha = 0.02,
  the minimum that stabilises the scheme according to Marrone et al.
  (the core's Monaghan form with alpha = 0.02 and beta = 0: the same term);
* Gaussian kernel cut at delta = 3h and renormalised to unit integral (eq. 7),
  h = 1.3 dx in seed 001 sec. 4.1.
"""

from dataclasses import dataclass

from ..eos import Linear
from ..kernels import Gaussian
from .models import ArtificialViscosity, DeltaSPH
from .system import FluidSystem


@dataclass
class FluidPreset:
    """Equation of state, viscosity, diffusion and kernel of a named scheme."""

    name: str
    eos: object
    viscosity: object
    density_diffusion: object
    kernel: object
    h_factor: float

    def fluid(self, shape, **kwargs):
        """A FluidSystem on ``shape`` with this scheme (extra FluidSystem arguments pass through)."""
        return FluidSystem(shape, eos=self.eos, viscosity=self.viscosity,
                           density_diffusion=self.density_diffusion, **kwargs)


def marrone2011(c0, *, alpha=0.02, delta=0.1, h_factor=1.3):
    """delta-SPH of Marrone et al. (2011) as in seed 001 sec. 2.1 (linear EOS, Gaussian cut at 3h).

    Parameters
    ----------
    c0 : float
        Speed of sound [m/s] (seed 001: 10 sqrt(g H) ... 20 sqrt(g H)).
    alpha : float
        Artificial viscosity coefficient, 0.02.
    delta : float
        delta-SPH diffusion coefficient, 0.1.
    h_factor : float
        h / dx, 1.3.
    """
    return FluidPreset(name="marrone2011", eos=Linear(c0=c0), viscosity=ArtificialViscosity(alpha=alpha),
                       density_diffusion=DeltaSPH(delta=delta) if delta > 0 else None, kernel=Gaussian(),
                       h_factor=h_factor)


PRESETS = {"marrone2011": marrone2011}

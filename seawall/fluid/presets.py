"""Named fluid schemes: the configured pieces of a FluidSystem and its kernel.

``marrone2011`` -- the delta-SPH scheme of Marrone et al. (2011) as [Huang2019]
(Huang et al. 2019) writes it in sec. 2.1, eq. 5-7:

* linear equation of state p = c0^2 (rho - rho0)                (eq. 3, 5);
* density diffusion delta h c0 sum psi_ij . grad W V_j with the
  renormalised density gradient rho^L (eq. 5-6), delta = 0.1;
* artificial viscosity alpha h c0 rho0 sum pi_ij . grad W V_j, alpha = 0.02,
  the minimum that stabilises the scheme according to Marrone et al.
  (the core's Monaghan form with alpha = 0.02, beta = 0 and ``all_pairs=True``:
  eq. 5 sums over every neighbour, with no switch on approaching pairs, so
  the term is a shear viscosity nu = alpha h c0 / 8 in 2D, docs/formulas.md);
* Gaussian kernel cut at delta = 3h and renormalised to unit integral (eq. 7),
  h = 1.3 dx in [Huang2019] sec. 4.1.

``liu2015`` -- the fluid of Liu et al. (2015), [Liu2015] sec. 2:

* Tait equation of state, gamma = 7, P0 = c_s^2 rho0 / gamma      (eq. 4);
* cubic spline kernel                                           (eq. 7);
* laminar viscosity (Morris et al. 1997) with mu = 1e-3 Pa s     (eq. 9, sec. 4.1)
  plus Monaghan artificial viscosity, alpha = 0.02 (the smallest value the
  seed found stable), epsilon = 0.01 in r^2 + epsilon h^2       (eq. 11);
* delta-SPH, delta = 0.1, with the Bonet-Lok corrected gradient  (eq. 12-15);
* leap-frog with the rates at the predicted full-step state     (eq. 16-17;
  :class:`~seawall.integrators.PredictedLeapFrog`)
  with dt = min(0.4 dt_cv, 0.25 dt_f)                             (eq. 18-20).
"""

from dataclasses import dataclass

from ..eos import Linear, Tait
from ..integrators import PredictedLeapFrog
from ..kernels import CubicSpline, Gaussian
from .models import ArtificialViscosity, DeltaSPH, LaminarViscosity
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
    #: the scheme's time integrator, if it prescribes one
    integrator: object = None

    def fluid(self, shape, **kwargs):
        """A FluidSystem on ``shape`` with this scheme (extra FluidSystem arguments pass through)."""
        return FluidSystem(shape, eos=self.eos, viscosity=self.viscosity,
                           density_diffusion=self.density_diffusion, **kwargs)


def marrone2011(c0, *, alpha=0.02, delta=0.1, h_factor=1.3):
    """delta-SPH of Marrone et al. (2011) as in [Huang2019] sec. 2.1 (linear EOS, Gaussian cut at 3h).

    Parameters
    ----------
    c0 : float
        Speed of sound [m/s] ([Huang2019]: 10 sqrt(g H) ... 20 sqrt(g H)).
    alpha : float
        Artificial viscosity coefficient, 0.02.
    delta : float
        delta-SPH diffusion coefficient, 0.1.
    h_factor : float
        h / dx, 1.3.
    """
    return FluidPreset(name="marrone2011", eos=Linear(c0=c0), viscosity=ArtificialViscosity(alpha=alpha, all_pairs=True),
                       density_diffusion=DeltaSPH(delta=delta) if delta > 0 else None, kernel=Gaussian(),
                       h_factor=h_factor)


def liu2015(c0, *, alpha=0.02, delta=0.1, nu=1e-6, h_factor=1.2, lagged_gradient=True,
            background_pressure=0.0, dt=None):
    """The fluid of Liu et al. (2015), [Liu2015] sec. 2 (Tait, cubic spline, laminar + artificial viscosity,
    delta-SPH, leap-frog with the dt rule of eq. 18-20).

    Parameters
    ----------
    c0 : float
        Speed of sound c_s [m/s] ([Liu2015]: about 10 x the largest flow speed).
    alpha : float
        Artificial viscosity coefficient (eq. 11), 0.02; 0 switches it off.
    delta : float
        delta-SPH coefficient (eq. 12), 0.1; 0 switches it off.
    nu : float
        Kinematic viscosity [m^2/s] of the laminar term (eq. 9), 1e-6 (water); 0 switches it off.
    h_factor : float
        h / dx: 1.5 in [Liu2015] sec. 4.1, 1.2 in sec. 4.2 and 4.3.
    lagged_gradient : bool
        delta-SPH density gradient of the previous evaluation (one neighbour pass,
        see :class:`~seawall.fluid.DeltaSPH`); False computes it as written.
    background_pressure : float
        Constant added to the Tait pressure [Pa], 0 in [Liu2015].
    dt : float, optional
        Fixed time step [s] ([Liu2015] runs its cases with one); default the rule of eq. 18-20.
    """
    viscosity = []
    if alpha > 0:
        viscosity.append(ArtificialViscosity(alpha=alpha))
    if nu > 0:
        viscosity.append(LaminarViscosity(nu=nu))
    return FluidPreset(name="liu2015", eos=Tait(c0=c0, gamma=7.0, background_pressure=background_pressure),
                       viscosity=viscosity or None,
                       density_diffusion=DeltaSPH(delta=delta, lagged_gradient=lagged_gradient) if delta > 0 else None,
                       kernel=CubicSpline(), h_factor=h_factor,
                       integrator=PredictedLeapFrog(dt=dt) if dt else PredictedLeapFrog(rule="liu2015"))


PRESETS = {"marrone2011": marrone2011, "liu2015": liu2015}

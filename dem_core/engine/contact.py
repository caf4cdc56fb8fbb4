"""The contact laws' parameters and their defaults.

Two laws, chosen by ``ContactParameters.law``: ``"corner"`` (default), vertex-to-face springs as UDEC
uses, and ``"overlap_area"``, the thesis' law (L. Papaloizou, 2009).  Their equations are written in
docs/method.md (1.3 to 1.5) and in :mod:`dem_core.engine._contact_law`, the functions the compiled
kernel calls; this module holds what a user sets: ``K_n`` (N/m^2 per metre of depth, the one
scene-wide stiffness), the damping ratios or explicit dashpots, and the tangential stiffness ratio.

The corner law's normal dashpots are critical by default (``zeta = 1``): an almost plastic corner
impact, which is what Housner's rocking theory assumes, so that the energy a rocking block loses
follows from the geometry with no fitted table.  The overlap-area law's rocking couple is calibrated
against Housner's decay per slenderness (:data:`HOUSNER_DAMPING`): its impacts lose the right energy
only at the stiffness it was calibrated at.

:func:`damping_ratio_for_restitution` and :func:`normal_damping` map a target coefficient of
restitution or damping ratio onto a dashpot; :func:`stiffer` scales ``K_n``.
"""

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ._contact_law import CORNER, OVERLAP_AREA, dashpot

#: the contact laws by name, each at the position of its code in the compiled kernels
LAWS = ("corner", "overlap_area")
assert LAWS.index("corner") == CORNER and LAWS.index("overlap_area") == OVERLAP_AREA

#: N/m^2 per metre of depth, per law.  The corner law's is stiff enough that rocking under records no longer
#: depends on it (the evidence is in docs/method.md 1.3); the overlap-area law keeps the
#: stiffness its damping table was calibrated at.
DEFAULT_STIFFNESS = {"corner": 2.0e11, "overlap_area": 2.0e10}
DEFAULT_NORMAL_DAMPING_RATIO = 0.3  # restitution 0.45 for a block dropped flat
DEFAULT_TANGENTIAL_DAMPING_RATIO = 0.2

#: (slenderness alpha in rad, rocking damping ratio) that reproduces
#: Housner's peak decay over the first five impacts of free rocking from
#: 0.2 alpha, with the other contact parameters at their defaults and a time
#: step converged for the impacts (0.1 of the stability limit); the worst
#: peak error there is under 0.4% up to alpha = 0.25, 0.8% at 0.3, 1.9% at
#: 0.4.  Output of ``python -m comparisons calibrate-damping``.
HOUSNER_DAMPING = (
    (0.06, 0.189), (0.08, 0.340), (0.10, 0.472), (0.125, 0.601), (0.15, 0.697), (0.175, 0.769),
    (0.2, 0.822), (0.25, 0.896), (0.3, 0.952), (0.35, 1.004), (0.4, 1.058),
)


def housner_damping_ratio(alpha: float) -> float:
    """Contact damping ratio whose rocking impacts lose Housner's energy for slenderness ``alpha`` (rad).

    Linear interpolation in :data:`HOUSNER_DAMPING`, clamped at its ends.
    """
    table = np.array(HOUSNER_DAMPING)
    return float(np.interp(alpha, table[:, 0], table[:, 1]))


#: default damping ratios per law: (normal, tangential)
DEFAULT_DAMPING = {"corner": (1.0, 1.0), "overlap_area": (DEFAULT_NORMAL_DAMPING_RATIO, DEFAULT_TANGENTIAL_DAMPING_RATIO)}


@dataclass(frozen=True)
class ContactParameters:
    """Contact parameters of a scene.

    law : ``"corner"`` (default) or ``"overlap_area"`` (the thesis' law); see the module docstring.
    kn : N/m^2 per m depth, the normal stiffness (per metre of contact length and of depth); None: the
        law's default (:data:`DEFAULT_STIFFNESS`: 2e11 for the corner law, 2e10 for the overlap-area law).
    damping_ratio : zeta of the normal dashpots (None: 1.0 for the corner law, critical; 0.3 for the
        overlap-area law).  Ignored if ``cn`` or ``restitution`` is given.
    restitution : instead of ``damping_ratio``, the coefficient of restitution of a flat impact the
        normal dashpots should give (:func:`damping_ratio_for_restitution`).
    rocking_damping_ratio : overlap-area law only, zeta_r of the couple that resists relative
        rotation (ignored if ``cr`` is given); None: :func:`housner_damping_ratio` of the scene's
        rocking slenderness.
    tangential_stiffness_ratio : K_t over the normal spring (ignored if ``kt`` is given).
    tangential_damping_ratio : zeta_t of the tangential dashpot (None: 0.2; ignored if ``ct`` is given).
    cn, cr, kt, ct : explicit N s/m, N s/m, N/m, N s/m applied to every interface (per contact
        point for the corner law), or None for the per-interface defaults.
    """

    law: str = "corner"
    kn: float | None = None
    damping_ratio: float | None = None
    restitution: float | None = None
    rocking_damping_ratio: float | None = None
    tangential_stiffness_ratio: float = 0.5
    tangential_damping_ratio: float | None = None
    cn: float | None = None
    cr: float | None = None
    kt: float | None = None
    ct: float | None = None

    def __post_init__(self):
        if self.law not in LAWS:
            raise ValueError(f"contact law must be one of {', '.join(LAWS)}, got {self.law!r}")
        if self.kn is None:
            object.__setattr__(self, "kn", DEFAULT_STIFFNESS[self.law])
        for name in ("kn", "tangential_stiffness_ratio"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"contact parameter {name} must be positive, got {v}")
        for name in ("damping_ratio", "rocking_damping_ratio", "tangential_damping_ratio", "cn", "cr", "kt", "ct"):
            v = getattr(self, name)
            if v is not None and not (np.isfinite(v) and v >= 0):
                raise ValueError(f"contact parameter {name} must be >= 0 or None, got {v}")
        if self.restitution is not None:
            if self.damping_ratio is not None:
                raise ValueError("give either damping_ratio or restitution, not both")
            damping_ratio_for_restitution(self.restitution)  # raises for a value out of range
        if self.law == "corner" and self.rocking_damping_ratio is not None:
            raise ValueError("rocking_damping_ratio belongs to the overlap-area law; the corner law has no "
                             "rocking couple")

    @property
    def normal_damping_ratio(self) -> float:
        """zeta of the normal dashpots in force (from ``damping_ratio``, ``restitution`` or the law's default)."""
        if self.damping_ratio is not None:
            return float(self.damping_ratio)
        if self.restitution is not None:
            return damping_ratio_for_restitution(self.restitution)
        return DEFAULT_DAMPING[self.law][0]

    @property
    def tangential_damping(self) -> float:
        """zeta_t in force."""
        if self.tangential_damping_ratio is not None:
            return float(self.tangential_damping_ratio)
        return DEFAULT_DAMPING[self.law][1]


def restitution_for_damping_ratio(damping_ratio: float) -> float:
    """Coefficient of restitution of a flat impact on a linear spring-dashpot that cannot pull.

    The contact force ``k x + c x'`` is clamped at zero, so the bodies part
    when that force vanishes, before the spring is back at rest (Schwager and
    Poschel 2007, Phys. Rev. E 75, 051304).  With ``beta = zeta omega_0`` and
    ``omega = omega_0 sqrt(1 - zeta^2)`` the force vanishes at
    ``omega t* = pi - atan2(2 beta omega, omega_0^2 - 2 beta^2)`` and
    ``e = exp(-beta t*) |cos(omega t*) - (beta / omega) sin(omega t*)|``.
    Valid for 0 <= zeta < 1.
    """
    zeta = float(damping_ratio)
    if not 0.0 <= zeta < 1.0:
        raise ValueError(f"damping ratio must be in [0, 1), got {zeta}")
    omega = math.sqrt(1.0 - zeta * zeta)  # in units of omega_0
    t_star = (math.pi - math.atan2(2.0 * zeta * omega, 1.0 - 2.0 * zeta * zeta)) / omega
    return math.exp(-zeta * t_star) * abs(math.cos(omega * t_star) - zeta / omega * math.sin(omega * t_star))


def damping_ratio_for_restitution(restitution: float) -> float:
    """Damping ratio whose flat impact rebounds with ``restitution`` (inverse of
    :func:`restitution_for_damping_ratio`); ``e`` from 0.136 (zeta -> 1) to 1."""
    low = restitution_for_damping_ratio(0.999)
    if not low <= restitution <= 1.0:
        raise ValueError(f"restitution must be in [{low:.3f}, 1], got {restitution}")
    if restitution == 1.0:
        return 0.0
    return float(brentq(lambda z: restitution_for_damping_ratio(z) - restitution, 0.0, 0.999, xtol=1e-14))


def normal_damping(stiffness: float, mass: float, *, restitution: float | None = None,
                   damping_ratio: float | None = None) -> float:
    """Dashpot constant ``C_n = 2 zeta sqrt(k m)`` (N s/m) for a target restitution or damping ratio.

    stiffness : N/m, the interface's linear normal stiffness ``K_n d L``.
    mass : kg, the effective (reduced) mass of the pair.
    Give exactly one of ``restitution`` (0 < e <= 1) and ``damping_ratio`` (>= 0).
    """
    if (restitution is None) == (damping_ratio is None):
        raise ValueError("give exactly one of restitution and damping_ratio")
    zeta = damping_ratio_for_restitution(restitution) if restitution is not None else float(damping_ratio)
    if zeta < 0:
        raise ValueError(f"damping_ratio must be >= 0, got {zeta}")
    return dashpot(math.nan, zeta, stiffness, mass)


def stiffer(contact: ContactParameters, factor: float) -> ContactParameters:
    """``contact`` with ``K_n`` multiplied by ``factor`` (> 0) and every other setting kept."""
    if not (np.isfinite(factor) and factor > 0):
        raise ValueError(f"the stiffness factor must be positive, got {factor}")
    return dataclasses.replace(contact, kn=contact.kn * factor)


def rocking_damping_ratio(scene) -> float:
    """The damping ratio of the overlap-area law's rotational dashpot couple for ``scene`` (0 for the corner law)."""
    p = scene.contact
    if p.law != "overlap_area":
        return 0.0
    if p.rocking_damping_ratio is None:
        return housner_damping_ratio(scene.rocking_slenderness)
    return p.rocking_damping_ratio

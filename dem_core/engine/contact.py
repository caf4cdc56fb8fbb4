"""The contact laws' parameters and their defaults.

Two laws, chosen by ``ContactParameters.law``: ``"corner"`` (default), vertex-to-face springs as UDEC
uses, and ``"overlap_area"``, the thesis' law (L. Papaloizou, 2009).  Their equations are written in
docs/method.md (1.3 to 1.5) and in :mod:`dem_core.engine._contact_law`, the functions the compiled
kernel calls; this module holds what a user sets: ``K_n`` (N/m^2 per metre of depth, the one
scene-wide stiffness), the damping ratios or explicit dashpots, and the tangential stiffness ratio.

Impacts on the corner law's points follow ``ContactParameters.restitution``, Newton's coefficient ``e`` of a
point impact, plastic (``e = 0``) by default as Housner's rocking theory assumes, so that the energy a rocking
block loses follows from the geometry with no fitted table.  Moreau-Jean imposes it at the points as Newton's
law (:mod:`dem_core.engine._moreau`).  The explicit core gives it with each point's dashpot: the damping ratio
whose spring-dashpot, released at zero force, rebounds with ``e`` (:func:`damping_ratio_for_restitution`,
against the point's own spring and effective mass).  ``e = 0`` would take an infinite dashpot, and the stable
step shrinks as the dashpot grows (about ``1 / (2 zeta)`` of the undamped one), so the explicit core gives at
least :data:`EXPLICIT_LEAST_RESTITUTION` (what it gives for ``e = 0``; between the two it refuses a run).  The
overlap-area law keeps the thesis' dashpot unless a restitution is given, and its rocking couple is calibrated
against Housner's decay per slenderness (:data:`HOUSNER_DAMPING`): its impacts lose the right energy only at the
stiffness it was calibrated at.

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
#: the least restitution the explicit core's dashpots give a point impact, what it gives where a plastic impact
#: (e = 0) is asked, and below which it refuses one: its stable step is still more than half of critical damping's
#: (docs/method.md 1.3, with what a smaller one moves)
EXPLICIT_LEAST_RESTITUTION = 0.05

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


#: default damping ratios per law: (normal, tangential); the corner law's normal dashpots follow the restitution
DEFAULT_DAMPING = {"corner": (None, 1.0),
                   "overlap_area": (DEFAULT_NORMAL_DAMPING_RATIO, DEFAULT_TANGENTIAL_DAMPING_RATIO)}


@dataclass(frozen=True)
class ContactParameters:
    """Contact parameters of a scene.

    law : ``"corner"`` (default) or ``"overlap_area"`` (the thesis' law); see the module docstring.
    kn : N/m^2 per m depth, the normal stiffness (per metre of contact length and of depth); None: the
        law's default (:data:`DEFAULT_STIFFNESS`: 2e11 for the corner law, 2e10 for the overlap-area law).
    damping_ratio : zeta of the explicit core's normal dashpots instead of a restitution (None: the corner
        law's from the restitution, the overlap-area law's 0.3).  Ignored if ``cn`` is given.
    restitution : Newton's coefficient ``e`` of a point impact, from 0 to 1 (None: 0, plastic, for the corner
        law; the overlap-area law's dashpot otherwise): exact in Moreau-Jean, by the points' dashpots in the
        explicit core, at least :data:`EXPLICIT_LEAST_RESTITUTION` (:meth:`explicit_restitution`).
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
            if not 0.0 <= self.restitution <= 1.0:
                raise ValueError(f"contact parameter restitution must be from 0 to 1, got {self.restitution}")
        if self.law == "corner" and self.rocking_damping_ratio is not None:
            raise ValueError("rocking_damping_ratio belongs to the overlap-area law; the corner law has no "
                             "rocking couple")

    @property
    def impact_restitution(self) -> float:
        """Newton's coefficient the scene asks of a point impact (0, plastic, unless given)."""
        return 0.0 if self.restitution is None else float(self.restitution)

    @property
    def explicit_restitution(self) -> float | None:
        """The restitution the explicit core's dashpots give a point impact: ``restitution`` (0 for the corner law
        unless given) raised to :data:`EXPLICIT_LEAST_RESTITUTION`; None where a damping ratio, or the
        overlap-area law's default, sets the dashpots instead."""
        if self.damping_ratio is not None or (self.restitution is None and self.law != "corner"):
            return None
        return max(self.impact_restitution, EXPLICIT_LEAST_RESTITUTION)

    @property
    def normal_damping_ratio(self) -> float:
        """zeta of the explicit core's normal dashpots (from ``damping_ratio``, the restitution or the law's
        default)."""
        if self.damping_ratio is not None:
            return float(self.damping_ratio)
        if self.explicit_restitution is not None:
            return damping_ratio_for_restitution(self.explicit_restitution)
        return DEFAULT_DAMPING[self.law][0]

    @property
    def tangential_damping(self) -> float:
        """zeta_t in force."""
        if self.tangential_damping_ratio is not None:
            return float(self.tangential_damping_ratio)
        return DEFAULT_DAMPING[self.law][1]


def restitution_for_damping_ratio(damping_ratio: float) -> float:
    """Coefficient of restitution of a point impact on a linear spring-dashpot that cannot pull.

    The contact force ``k x + c x'`` is clamped at zero, so the bodies part
    when that force vanishes, before the spring is back at rest (Schwager and
    Poschel 2007, Phys. Rev. E 75, 051304).  In units of ``omega_0 = sqrt(k/m)``, with ``x(0) = 0`` and
    ``x'(0) = 1``:

    * ``zeta < 1``: with ``omega = sqrt(1 - zeta^2)`` the force vanishes at
      ``omega t* = pi - atan2(2 zeta omega, 1 - 2 zeta^2)`` and
      ``e = exp(-zeta t*) |cos(omega t*) - (zeta / omega) sin(omega t*)|``;
    * ``zeta = 1``: ``t* = 2`` and ``e = exp(-2)``;
    * ``zeta > 1``: the roots ``r = -zeta +- s``, ``s = sqrt(zeta^2 - 1)``, satisfy ``1 + 2 zeta r = -r^2``, so
      the force ``x + 2 zeta x'`` vanishes at ``t* = ln(r_2 / r_1) / s`` and
      ``e = (r_2 exp(r_2 t*) - r_1 exp(r_1 t*)) / (2 s)``, about ``1 / (4 zeta^2)`` for a large ``zeta``.

    ``damping_ratio`` >= 0; ``e`` falls from 1 (no dashpot) towards 0 as the dashpot grows.
    """
    zeta = float(damping_ratio)
    if not (math.isfinite(zeta) and zeta >= 0.0):
        raise ValueError(f"damping ratio must be finite and >= 0, got {zeta}")
    if zeta < 1.0:
        omega = math.sqrt(1.0 - zeta * zeta)
        t_star = (math.pi - math.atan2(2.0 * zeta * omega, 1.0 - 2.0 * zeta * zeta)) / omega
        return math.exp(-zeta * t_star) * abs(math.cos(omega * t_star) - zeta / omega * math.sin(omega * t_star))
    if zeta == 1.0:
        return math.exp(-2.0)
    s = math.sqrt(zeta * zeta - 1.0)
    r_1, r_2 = -zeta + s, -zeta - s
    t_star = math.log(r_2 / r_1) / s
    return (r_2 * math.exp(r_2 * t_star) - r_1 * math.exp(r_1 * t_star)) / (2.0 * s)


def damping_ratio_for_restitution(restitution: float) -> float:
    """Damping ratio whose point impact rebounds with ``restitution`` (inverse of
    :func:`restitution_for_damping_ratio`), ``0 < e <= 1``: ``e = 0`` would take an infinite dashpot."""
    e = float(restitution)
    if not 0.0 < e <= 1.0:
        raise ValueError(f"a dashpot's restitution must be in (0, 1], got {restitution}")
    if e == 1.0:
        return 0.0
    high = 1.0
    while restitution_for_damping_ratio(high) > e:
        high *= 2.0
    return float(brentq(lambda z: restitution_for_damping_ratio(z) - e, 0.0, high, xtol=1e-14, rtol=1e-14))


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

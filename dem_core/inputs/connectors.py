"""Connectors across joints: the wooden poles set between ancient drums and the metal bars of restorations.

A :class:`Connector` is a bar or pin across the joint between two blocks that touch at the start, at a
``position`` along the joint (m from its middle), of a :class:`ConnectorKind`: what it is made of and how it
acts, in shear (dowel action) and in tension (docs/method.md 1.12, the law of :mod:`dem_core.engine._connector_law`):

* shear: free within ``clearance`` each way (the hole wider than the pin), then elastic (``shear_stiffness``) up
  to ``yield_force``, hardening linearly to ``ultimate_force`` at ``ultimate_slip`` past the clearance, flat after;
  it ruptures when the plastic slip it has taken, over every excursion, reaches what a monotonic push takes up to
  ``rupture_slip``;
* tension: ``axial_stiffness`` while the joint opens (0: a loose pin, which holds nothing together), rupture at
  ``axial_strength``; compression is the stone's.

:func:`titanium_bar` and :data:`OAK_POLOS` are presets with their sources; a :class:`Placement` puts connectors
of a kind at a scene's joints by name (``"all"``, ``"capital"`` or a list of pairs), which every builder takes
(``connectors=[Placement(...)]``).  Scenes carry them in
:attr:`~dem_core.Scene.connectors`; both of the native core's integrators act on them; the adapters' engines
refuse a scene that has any.
"""

import itertools
import math
from dataclasses import dataclass

from ..engine.stacks import find_stacks
from .errors import SceneError
from .number_types import is_real

#: where a kind of connector goes at every joint of each column, or at the joint under each column's top block
PLACES = ("all", "capital")


def _quantity(kind: str, name: str, value, *, allow_zero: bool = False, allow_inf: bool = False) -> float:
    if not is_real(value) or math.isnan(value):
        raise SceneError(f"connector '{kind}': {name} must be a number, got {value!r}")
    value = float(value)
    if value < 0 or (value == 0 and not allow_zero) or (math.isinf(value) and not allow_inf):
        bound = ">= 0" if allow_zero else "positive"
        raise SceneError(f"connector '{kind}': {name} must be {bound}{'' if allow_inf else ' and finite'}, got {value}")
    return value


@dataclass(frozen=True)
class ConnectorKind:
    """What a connector is made of and how it acts (module docstring).

    name : how results name it.  shear_stiffness : N/m.  yield_force, ultimate_force : N in shear (no yield
    given: elastic).  ultimate_slip : m past the clearance where the force reaches ``ultimate_force`` (needed when
    it is above ``yield_force``).  rupture_slip : m past the clearance where a monotonic push breaks it (inf:
    never).  axial_stiffness : N/m in tension.  axial_strength : N (inf: never pulls out).  clearance : m each way.
    source : where the values come from.
    """

    name: str
    shear_stiffness: float | None = None
    yield_force: float | None = None
    ultimate_force: float | None = None
    ultimate_slip: float | None = None
    rupture_slip: float = math.inf
    axial_stiffness: float = 0.0
    axial_strength: float | None = None
    clearance: float = 0.0
    source: str = ""

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise SceneError(f"a connector kind needs a name, got {self.name!r}")
        name = self.name
        if self.shear_stiffness is None:
            given = [key for key in ("yield_force", "ultimate_force", "ultimate_slip")
                     if getattr(self, key) is not None]
            raise SceneError(f"connector '{name}': " + (f"{', '.join(given)} given without a shear_stiffness"
                                                        if given else "give its shear_stiffness (N/m)"))
        k = _quantity(name, "shear_stiffness", self.shear_stiffness)
        yield_force = math.inf if self.yield_force is None else _quantity(name, "yield_force", self.yield_force)
        ultimate = yield_force if self.ultimate_force is None else _quantity(name, "ultimate_force",
                                                                             self.ultimate_force, allow_inf=True)
        if ultimate < yield_force:
            raise SceneError(f"connector '{name}': ultimate_force {ultimate:g} N is below its yield_force "
                             f"{yield_force:g} N")
        if ultimate > yield_force:
            if self.ultimate_slip is None:
                raise SceneError(f"connector '{name}': ultimate_force above yield_force needs the ultimate_slip (m) "
                                 f"at which it is reached")
            slip = _quantity(name, "ultimate_slip", self.ultimate_slip)
            if not slip * k > ultimate:
                raise SceneError(f"connector '{name}': ultimate_slip {slip:g} m is within the elastic range "
                                 f"(yield at {yield_force / k:.3g} m): at least {ultimate / k:.3g} m")
        rupture = _quantity(name, "rupture_slip", self.rupture_slip, allow_inf=True)
        if self.ultimate_slip is not None and rupture < self.ultimate_slip:
            raise SceneError(f"connector '{name}': rupture_slip {rupture:g} m comes before its ultimate_slip "
                             f"{self.ultimate_slip:g} m")
        axial = _quantity(name, "axial_stiffness", self.axial_stiffness, allow_zero=True)
        if self.axial_strength is not None:
            _quantity(name, "axial_strength", self.axial_strength, allow_inf=True)
            if axial == 0:
                raise SceneError(f"connector '{name}': axial_strength given without an axial_stiffness (a loose pin "
                                 f"holds nothing in tension)")
        _quantity(name, "clearance", self.clearance, allow_zero=True)

    @property
    def hardening(self) -> float:
        """N/m: the kinematic hardening ``H`` whose envelope after yield rises at
        ``(F_u - F_y) / (slip_u - F_y / k)`` (0: perfectly plastic)."""
        k, yield_force, ultimate = self.shear_stiffness, self.yield_force, self.ultimate_force
        if yield_force is None or ultimate is None or ultimate == yield_force:
            return 0.0
        tangent = (ultimate - yield_force) / (self.ultimate_slip - yield_force / k)
        return k * tangent / (k - tangent)

    @property
    def slip_capacity(self) -> float:
        """m: the plastic slip a monotonic push takes up to ``rupture_slip``, which cyclic slips use up too."""
        ultimate = self.ultimate_force if self.ultimate_force is not None else self.yield_force
        if ultimate is None or math.isinf(self.rupture_slip):
            return math.inf
        return self.rupture_slip - ultimate / self.shear_stiffness


@dataclass(frozen=True)
class Connector:
    """A connector of ``kind`` across the joint between the blocks named ``between`` (lower or first, upper or
    second; the base is ``base``), ``position`` m along the joint from its middle (along +x where the joint is
    level)."""

    between: tuple
    kind: ConnectorKind
    position: float = 0.0

    def __post_init__(self):
        between = tuple(self.between)
        if len(between) != 2 or not all(isinstance(n, str) for n in between) or between[0] == between[1]:
            raise SceneError(f"a connector joins two blocks named by their names, got between = {self.between!r}")
        object.__setattr__(self, "between", between)
        if not isinstance(self.kind, ConnectorKind):
            raise SceneError(f"connector between {between}: kind must be a ConnectorKind, got {self.kind!r}")
        if not is_real(self.position) or not math.isfinite(self.position):
            raise SceneError(f"connector between {between}: position must be a number of m, got {self.position!r}")
        object.__setattr__(self, "position", float(self.position))

    @property
    def name(self) -> str:
        """How results name it: ``"<first>/<second>"`` and where it is, if not in the middle."""
        at = f"@{self.position:+g}" if self.position else ""
        return f"{self.between[0]}/{self.between[1]}{at}"


#: an oak polos of 40 mm in softwood empolia, as the builders of Greek temples set one at the middle of each
#: joint: a loose pin that holds nothing in tension.  Papadopoulos and Vintzileou (2013, "The new 'poles and
#: empolia' for the columns of the ancient Greek temple of Apollo Epikourios", Built Heritage 2013) describe the
#: system (one pole per joint, hard-wood poles in soft-wood empolia, supplementary to friction); Penrose (1888,
#: "An Investigation of the Principles of Athenian Architecture", p. 25) measured the Parthenon's (a 49 mm pin
#: "accurately fitting" a 113 mm empolion).  No test of such a pin is published: the values are estimates, the
#: stiffness by Eurocode 5's slip modulus of a dowel (rho_m^1.5 d / 23, rho_m = 400 kg/m^3), the strength by
#: Johansen's rigid-pin mode (0.414 f_h t d, embedment f_h 12 MPa over t = 60 mm), yield at half of it, and a
#: clearance of the oak's radial shrinkage on drying
OAK_POLOS = ConnectorKind(
    "oak polos", shear_stiffness=1.4e7, yield_force=8e3, ultimate_force=1.5e4, ultimate_slip=8e-3, rupture_slip=2e-2,
    clearance=1e-3, source="Papadopoulos and Vintzileou 2013; Penrose 1888; strength and stiffness estimated "
                           "(Eurocode 5 slip modulus, Johansen's pin mode)")


def titanium_bar(diameter: float = 0.016) -> ConnectorKind:
    """A titanium bar of ``diameter`` (m) grouted across the joint with white cement, as the Acropolis
    restorations set them (the Acropolis Restoration Service, www.ysma.gr, "Methodology"; commercially pure
    titanium, ASTM grade 2: yield 275 MPa at least, 340 typical).  Dowel strength by Vintzileou and Tassios (1986,
    "Mathematical models for dowel action under monotonic and cyclic conditions", Magazine of Concrete Research
    38(134)), ``F_u = 1.3 d^2 sqrt(f_c f_y)`` with the grout's f_c = 40 MPa, reached at a slip of 0.1 d; the
    shear stiffness of two semi-infinite beams on an elastic foundation, ``k = E_f / (4 lambda)`` with
    ``lambda = (E_f / (4 E I))^(1/4)``, E_f = 25 GPa, E = 105 GPa; yield at half the dowel strength, rupture at a
    slip of 0.4 d; tension by a bond length of 10 d each side, ``E A / (20 d)``, pulling out at 30 kN scaled with
    the bar's circumference.  Slips and the bond are estimates: no test of titanium dowels in marble is published.
    """
    d = _quantity("titanium bar", "diameter", diameter)
    f_c, f_y, e_bar, e_found = 40e6, 340e6, 105e9, 25e9
    ultimate = 1.3 * d**2 * math.sqrt(f_c * f_y)
    inertia = math.pi * d**4 / 64.0
    lam = (e_found / (4.0 * e_bar * inertia)) ** 0.25
    area = math.pi * d**2 / 4.0
    return ConnectorKind(
        f"titanium bar {d * 1e3:g} mm", shear_stiffness=e_found / (4.0 * lam), yield_force=0.5 * ultimate,
        ultimate_force=ultimate, ultimate_slip=0.1 * d, rupture_slip=0.4 * d, axial_stiffness=e_bar * area / (20.0 * d),
        axial_strength=30e3 * d / 0.016, source="YSMA (Acropolis Restoration Service); ASTM B348 grade 2; Vintzileou "
                                               "and Tassios 1986; slips and bond estimated")


#: the presets by the names scene files use
PRESETS = {"oak_polos": lambda: OAK_POLOS, "titanium_bar": titanium_bar}


@dataclass(frozen=True)
class Placement:
    """Connectors of ``kind`` at the joints ``at`` names, ``position`` m along each joint from its middle:
    ``"all"``, every joint between two blocks of a column (drum on drum, capital on drum: not a column's foot on
    the base); ``"capital"``, the joint under each column's top block; or a list of ``(first, second)`` block
    names."""

    kind: ConnectorKind
    at: object = "all"
    position: float = 0.0

    def connectors(self, scene) -> tuple:
        """The :class:`Connector` of this placement in ``scene``."""
        if isinstance(self.at, str):
            if self.at not in PLACES:
                raise SceneError(f"connectors at {self.at!r}: give one of {PLACES} or a list of (block, block) pairs")
            joints = []
            for stack in find_stacks(scene):
                names = [scene.blocks[b].name for b in stack.blocks]
                pairs = list(itertools.pairwise(names))
                joints += pairs if self.at == "all" else pairs[-1:]
            if not joints:
                raise SceneError(f"connectors at {self.at!r}: the scene has no column of two blocks or more")
        else:
            joints = [tuple(pair) for pair in self.at]
        return tuple(Connector(pair, self.kind, self.position) for pair in joints)


def place(scene, kind: ConnectorKind, at="all", position: float = 0.0) -> tuple:
    """The connectors of ``Placement(kind, at, position)`` in ``scene``."""
    return Placement(kind, at, position).connectors(scene)

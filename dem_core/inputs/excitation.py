"""Ground motion: analytic pulses, harmonic motion and recorded accelerograms.

A :class:`GroundMotion` holds a horizontal and a vertical :class:`Component`;
each component gives the ground acceleration (m/s^2), velocity (m/s) and
displacement (m) as vectorised functions of time (s).  Velocity and
displacement are exact integrals of the acceleration (closed forms for the
analytic motions; exact integration of the piecewise-linear record), with the
ground at rest at ``t = 0`` except for harmonic motion, whose velocity starts
at ``A omega`` (the blocks then start at rest relative to the ground).
"""

import functools
import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from . import records
from .number_types import is_integer, is_real
from .text_files import shown


class ExcitationError(ValueError):
    """A ground motion's arguments that do not go together; ``keys`` names them (as a scene file's
    ``[excitation]`` keys), so that a caller that set one of them can say so."""

    def __init__(self, message: str, keys=()):
        super().__init__(message)
        self.keys = tuple(keys)


class Component:
    """One direction of ground motion.  Subclasses implement the three functions."""

    #: natural end of the motion (s); a simulation without a duration runs this long.
    end_time: float = np.inf
    #: the shortest time over which the motion changes (s): a harmonic's period, a pulse's duration; inf for
    #: motions that set none (a record's samples are integrated exactly, whatever the step)
    time_scale: float = np.inf

    def acceleration(self, t):
        raise NotImplementedError

    def velocity(self, t):
        raise NotImplementedError

    def displacement(self, t):
        raise NotImplementedError

    @property
    def peak_acceleration(self) -> float:
        """Largest |acceleration|, m/s^2."""
        raise NotImplementedError


class Still(Component):
    """No motion."""

    end_time = 0.0

    def acceleration(self, t):
        return np.zeros_like(np.asarray(t, dtype=float))

    velocity = displacement = acceleration
    peak_acceleration = 0.0


@dataclass(frozen=True)
class Harmonic(Component):
    """``u = A sin(2 pi f t)``.  amplitude A (m), frequency f (Hz)."""

    amplitude: float
    frequency: float

    def __post_init__(self):
        _finite(self.amplitude, "harmonic amplitude (m)")
        _positive(self.frequency, "harmonic frequency", "Hz")

    @property
    def _omega(self):
        return 2.0 * np.pi * self.frequency

    @property
    def time_scale(self):
        return 1.0 / self.frequency

    def displacement(self, t):
        return self.amplitude * np.sin(self._omega * np.asarray(t, dtype=float))

    def velocity(self, t):
        return self.amplitude * self._omega * np.cos(self._omega * np.asarray(t, dtype=float))

    def acceleration(self, t):
        return -self.amplitude * self._omega**2 * np.sin(self._omega * np.asarray(t, dtype=float))

    @property
    def peak_acceleration(self):
        return abs(self.amplitude) * self._omega**2


@dataclass(frozen=True)
class Pulse(Component):
    """Acceleration pulse of amplitude ``a_p`` (m/s^2) lasting ``T_p`` (s) from t = 0.

    shape: ``"rectangular"`` (a_p), ``"sine"`` (a_p sin(2 pi t/T_p), one full
    cycle) or ``"cosine"`` (a_p cos(2 pi t/T_p), one full cycle).
    """

    amplitude: float
    duration: float
    shape: str = "rectangular"

    def __post_init__(self):
        if self.shape not in ("rectangular", "sine", "cosine"):
            raise ValueError(f"unknown pulse shape {self.shape!r}")
        _finite(self.amplitude, f"{self.shape} pulse amplitude (m/s^2)")
        _positive(self.duration, f"{self.shape} pulse duration", "s")

    @property
    def end_time(self):
        return self.duration

    @property
    def time_scale(self):
        return self.duration

    def _parts(self, t):
        t = np.asarray(t, dtype=float)
        tau = np.clip(t, 0.0, self.duration)
        return t, tau, 2.0 * np.pi / self.duration

    def acceleration(self, t):
        t, tau, w = self._parts(t)
        inside = (t >= 0) & (t < self.duration)
        if self.shape == "rectangular":
            a = np.full_like(tau, self.amplitude)
        elif self.shape == "sine":
            a = self.amplitude * np.sin(w * tau)
        else:
            a = self.amplitude * np.cos(w * tau)
        return np.where(inside, a, 0.0)

    def velocity(self, t):
        t, tau, w = self._parts(t)
        ap = self.amplitude
        if self.shape == "rectangular":
            return ap * tau
        if self.shape == "sine":
            return ap / w * (1.0 - np.cos(w * tau))
        return ap / w * np.sin(w * tau)

    def displacement(self, t):
        t, tau, w = self._parts(t)
        ap, tp = self.amplitude, self.duration
        after = np.maximum(t - tp, 0.0)
        if self.shape == "rectangular":
            return ap * tau**2 / 2.0 + ap * tp * after
        if self.shape == "sine":
            return ap / w * (tau - np.sin(w * tau) / w)  # the velocity is back to zero at T_p
        return ap / w**2 * (1.0 - np.cos(w * tau))

    @property
    def peak_acceleration(self):
        return abs(self.amplitude)


@dataclass(frozen=True)
class Ramp(Component):
    """``a = rate * t`` (m/s^2 per s), held at ``peak`` (m/s^2) once reached, if given."""

    rate: float
    peak: float | None = None

    def __post_init__(self):
        if _finite(self.rate, "ramp rate (m/s^2 per s)") == 0:
            raise ValueError("ramp rate must not be zero, got 0 m/s^2 per s")
        if self.peak is not None:
            _positive(self.peak, "ramp peak", "m/s^2", "; the ramp's direction is the sign of its rate")

    def _t_hold(self):
        return np.inf if self.peak is None else abs(self.peak / self.rate)

    def acceleration(self, t):
        t = np.maximum(np.asarray(t, dtype=float), 0.0)
        return self.rate * np.minimum(t, self._t_hold())

    def velocity(self, t):
        t = np.maximum(np.asarray(t, dtype=float), 0.0)
        th = self._t_hold()
        tau = np.minimum(t, th)
        return self.rate * (tau**2 / 2.0 + th * np.maximum(t - th, 0.0)) if np.isfinite(th) else self.rate * t**2 / 2.0

    def displacement(self, t):
        t = np.maximum(np.asarray(t, dtype=float), 0.0)
        th = self._t_hold()
        if not np.isfinite(th):
            return self.rate * t**3 / 6.0
        tau = np.minimum(t, th)
        after = np.maximum(t - th, 0.0)
        return self.rate * (tau**3 / 6.0 + th**2 / 2.0 * after + th * after**2 / 2.0)

    @property
    def peak_acceleration(self):
        return np.inf if self.peak is None else abs(self.peak)


@dataclass(frozen=True, eq=False)
class Sampled(Component):
    """A record: accelerations ``samples`` (m/s^2) every ``dt`` s from ``t = 0``.

    Linear between samples, zero after the last one (the ground then coasts at
    its final velocity).  Velocity and displacement are the exact integrals of
    that piecewise-linear acceleration.  ``factor`` says what the record was
    multiplied by to make ``samples`` (:func:`record`'s ``scale`` or ``pga``):
    what a batch's row shows, never used to compute.
    """

    samples: np.ndarray
    dt: float
    name: str = "record"
    factor: float = 1.0
    _v: np.ndarray = field(init=False, repr=False)
    _u: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        a = np.array(self.samples, dtype=float)
        if a.ndim != 1 or len(a) < 2:
            raise ValueError(f"{self.name}: a record needs a 1-D array of at least 2 accelerations")
        _check_finite(a, self.name)
        object.__setattr__(self, "dt", records.check_dt(self.dt, self.name))
        a.flags.writeable = False
        object.__setattr__(self, "samples", a)
        v, u = _integrate_piecewise_linear(a, self.dt)
        object.__setattr__(self, "_v", v)
        object.__setattr__(self, "_u", u)

    @property
    def end_time(self):
        return (len(self.samples) - 1) * self.dt

    def _locate(self, t):
        t = np.asarray(t, dtype=float)
        n = len(self.samples)
        k = np.clip(np.floor(t / self.dt).astype(np.int64), 0, n - 2)
        tau = np.clip(t - k * self.dt, 0.0, None)
        a0 = self.samples[k]
        slope = (self.samples[k + 1] - a0) / self.dt
        inside = (t >= 0) & (t <= self.end_time)
        return t, k, tau, a0, slope, inside

    def acceleration(self, t):
        _, _, tau, a0, slope, inside = self._locate(t)
        return np.where(inside, a0 + slope * tau, 0.0)

    def velocity(self, t):
        t, k, tau, a0, slope, inside = self._locate(t)
        v_in = self._v[k] + a0 * tau + slope * tau**2 / 2.0
        return np.where(t < 0, 0.0, np.where(inside, v_in, self._v[-1]))

    def displacement(self, t):
        t, k, tau, a0, slope, inside = self._locate(t)
        u_in = self._u[k] + self._v[k] * tau + a0 * tau**2 / 2.0 + slope * tau**3 / 6.0
        u_after = self._u[-1] + self._v[-1] * (t - self.end_time)
        return np.where(t < 0, 0.0, np.where(inside, u_in, u_after))

    @property
    def peak_acceleration(self):
        return float(np.max(np.abs(self.samples)))


def _integrate_piecewise_linear(a, dt):
    v = np.zeros_like(a)
    u = np.zeros_like(a)
    v[1:] = np.cumsum(dt * (a[:-1] + a[1:]) / 2.0)
    u[1:] = np.cumsum(dt * v[:-1] + dt**2 * (2.0 * a[:-1] + a[1:]) / 6.0)
    return v, u


#: a record whose peak after :func:`baseline_correct` is below this fraction of its peak before is a constant or a
#: straight line that the correction has taken away (what is left is rounding): :func:`record` refuses to scale it
BASELINE_REMAINDER = 1e-9


def baseline_correct(a, dt):
    """Subtract the linear baseline ``c0 + c1 t`` that brings the ground back to rest where it started.

    ``c0``, ``c1`` are chosen so that the exact integrals of the corrected
    (piecewise-linear) record give zero velocity and zero displacement at its
    end: a record's small offsets otherwise integrate into a velocity that
    never returns to zero and a displacement that runs away.  Returns the
    corrected accelerations (m/s^2); the change is a small fraction of the
    peak for any usable record.
    """
    a = np.asarray(a, dtype=float)
    t_end = (len(a) - 1) * dt
    v, u = _integrate_piecewise_linear(a, dt)
    # c0 + c1 t with s = t / t_end: c0 + s (c1 t_end); in those unknowns the system does not depend on t_end
    system = np.array([[1.0, 1.0 / 2.0], [1.0 / 2.0, 1.0 / 6.0]])
    c0, c1_t_end = np.linalg.solve(system, [v[-1] / t_end, u[-1] / t_end**2])
    return a - (c0 + c1_t_end * np.arange(len(a)) / (len(a) - 1))


@dataclass(frozen=True, eq=False)
class GroundMotion:
    """Horizontal and vertical ground motion (docs/method.md section 2)."""

    horizontal: Component = field(default_factory=Still)
    vertical: Component = field(default_factory=Still)
    name: str = "ground motion"

    @property
    def end_time(self) -> float:
        return max(self.horizontal.end_time, self.vertical.end_time)

    @property
    def time_scale(self) -> float:
        """The shorter of the components' :attr:`Component.time_scale`, s."""
        return min(self.horizontal.time_scale, self.vertical.time_scale)

    def acceleration(self, t):
        """``(a_x, a_y)`` at times ``t``, m/s^2."""
        return self.horizontal.acceleration(t), self.vertical.acceleration(t)

    def velocity(self, t):
        return self.horizontal.velocity(t), self.vertical.velocity(t)

    def displacement(self, t):
        return self.horizontal.displacement(t), self.vertical.displacement(t)


#: the strong motion of a record: the time between these fractions of its Arias intensity, the integral of the
#: squared acceleration (the significant duration of Trifunac and Brady 1975, "A study on the duration of strong
#: earthquake ground motion", BSSA 65(3))
STRONG_MOTION = (0.05, 0.95)


def unscaled(component: Component) -> Component:
    """The component a chain of :class:`Scaled` and :class:`Extended` wraps (a record's samples), or ``component``
    itself."""
    return _unwrapped(component)[0]


def _unwrapped(component: Component) -> tuple[Component, float]:
    """``(inner, factor)``: the component a chain of :class:`Scaled` and :class:`Extended` wraps, and the product of
    the chain's :class:`Scaled` factors (1 for no chain)."""
    factor = 1.0
    while isinstance(component, (Scaled, Extended)):
        factor *= component.factor if isinstance(component, Scaled) else 1.0
        component = component.component
    return component, factor


def strong_motion(component: Component) -> tuple[float, float] | None:
    """``(start, end)`` s of a recorded component's strong motion (:data:`STRONG_MOTION` of its Arias intensity,
    the same for any scale of it), or None for a motion that is not a record or has no shaking."""
    component = unscaled(component)
    if not isinstance(component, Sampled) or len(component.samples) < 2:
        return None
    squared = component.samples ** 2
    arias = np.concatenate(([0.0], np.cumsum(0.5 * (squared[1:] + squared[:-1]))))
    if arias[-1] <= 0.0:
        return None
    t = component.dt * np.arange(len(squared))
    start, end = np.interp(STRONG_MOTION, arias / arias[-1], t)
    return float(start), float(end)


#: s: the ground velocity is sampled this finely (or finer, for a motion that changes faster) to find its peak
VELOCITY_SAMPLING = 1e-3


def scale_factor(component: Component) -> float:
    """The product of the factors of the :class:`Scaled` in the chain (with :class:`Extended`) that wraps
    ``component`` and of the record's own (:attr:`Sampled.factor`); 1 for a component not scaled."""
    inner, factor = _unwrapped(component)
    return factor * (inner.factor if isinstance(inner, Sampled) else 1.0)


@functools.lru_cache(maxsize=128)
def _record_measure(measure, record, *args) -> float:
    """``measure(record, *args)``, kept for the other motions that scale ``record``."""
    return measure(record, *args)


def _speed_measure(measure, component: Component, *args) -> float:
    """``measure(component, *args)`` of a measure of speed, which scales with |factor|: a scaled record's is the
    |factor| times its record's, found once for all the factors of a batch; a still component's is 0; any other
    component's is computed."""
    inner, factor = _unwrapped(component)
    if isinstance(inner, Still):
        return 0.0
    if isinstance(inner, Sampled):
        return abs(factor) * _record_measure(measure, inner, *args)
    return measure(component, *args)


def _peak_speed(component: Component) -> float:
    end = component.end_time
    if not math.isfinite(end):
        raise ValueError("PGV needs a motion with an end (a record, a pulse)")
    step = min(VELOCITY_SAMPLING, component.time_scale / 50.0)
    t = np.linspace(0.0, end, math.ceil(end / step) + 1)
    return float(np.max(np.abs(component.velocity(t))))


def peak_velocity(motion: GroundMotion) -> float:
    """PGV (m/s): the peak |velocity| of ``motion``'s horizontal component, sampled every
    :data:`VELOCITY_SAMPLING` s or 1/50 of its shortest time; ``ValueError`` naming a motion without an end (a
    harmonic, a ramp).  A scaled record's is its record's times |factor|."""
    inner, factor = _unwrapped(motion.horizontal)
    try:
        return abs(factor) * _speed_measure(_peak_speed, inner)
    except ValueError as error:
        raise ValueError(f"{motion.name}: {error}") from None


def _velocity_range(component: Component, duration: float, samples: int) -> float:
    return float(np.ptp(component.velocity(np.linspace(0.0, duration, samples))))


def velocity_range(motion: GroundMotion, duration: float) -> float:
    """m/s: the sum over ``motion``'s two components of max - min of the ground's velocity over ``[0, duration]``
    (s), sampled every :data:`VELOCITY_SAMPLING` s (at least 2 samples and at most 1e6).  A scaled record's is the
    |factor| times its record's, found once for all the factors of a batch."""
    samples = math.ceil(min(max(duration / VELOCITY_SAMPLING, 2), 1e6)) + 1
    return float(sum(_speed_measure(_velocity_range, component, float(duration), samples)
                     for component in (motion.horizontal, motion.vertical)))


def describe(motion: GroundMotion) -> dict:
    """What a member's motion is, as a batch's row gives it: ``motion`` (its name), ``record`` (the name of what it
    scales, :func:`record_name`), ``scale`` (the factor, :func:`scale_factor`; a sequence's
    :attr:`MotionSequence.factor`), ``pga_m_s2`` and ``pgv_m_s`` (its
    horizontal component's, NaN for the PGV of a motion without an end)."""
    try:
        pgv = peak_velocity(motion)
    except ValueError:
        pgv = math.nan
    scale = motion.factor if isinstance(motion, MotionSequence) else scale_factor(motion.horizontal)
    return {"motion": motion.name, "record": record_name(motion), "scale": scale,
            "pga_m_s2": float(motion.horizontal.peak_acceleration), "pgv_m_s": pgv}


def record_name(motion: GroundMotion) -> str:
    """The name of the record ``motion`` scales: its name without the scale factors (" x1.5") :func:`scaled` adds;
    a sequence's is :attr:`MotionSequence.record`, the name :func:`sequence` gave it."""
    if isinstance(motion, MotionSequence):
        return motion.record
    return re.sub(r"( x[-+.0-9eE]+)+$", "", motion.name)


def cuts_strong_motion(motion: GroundMotion, duration: float | None) -> str:
    """Why ``duration`` s of ``motion`` leave out part of its strong motion, naming its record; '' where they do
    not (no duration: the motion runs whole)."""
    if duration is None:
        return ""
    found = strong_motion(motion.horizontal)
    if found is None or duration >= found[1]:
        return ""
    start, end = found
    return (f"{duration:g} s of {record_name(motion)} stop before the end of its strong motion ({start:.1f} to "
            f"{end:.1f} s hold {STRONG_MOTION[0]:.0%} to {STRONG_MOTION[1]:.0%} of its Arias intensity): run at "
            f"least {math.ceil(end):g} s, or the whole record")


def strong_motion_cuts(runs) -> list:
    """The distinct :func:`cuts_strong_motion` of ``runs``, pairs ``(motion, duration)``, in their order."""
    return [said for said in dict.fromkeys(cuts_strong_motion(motion, duration) for motion, duration in runs) if said]


#: a ground acceleration above this many g (9.80665 m/s^2) is beyond what a stone block can meet and more likely a
#: mistake of units or scale: a run under such a motion is refused (:func:`refuse_extreme`), whether it comes
#: from a scene file, from simulate or as a member of a batch
EXTREME_PGA_G = 50.0


def peak_acceleration(motion: GroundMotion, duration: float | None = None) -> float:
    """The largest |acceleration| (m/s^2) of either component of ``motion``; a component that rises without a peak
    (a ramp) is taken at ``duration`` (s), where given, and is infinite otherwise."""
    peaks = []
    for component in (motion.horizontal, motion.vertical):
        peak = component.peak_acceleration
        if peak == math.inf and duration is not None:
            peak = float(np.max(np.abs(component.acceleration(np.array([0.0, duration])))))
        peaks.append(peak)
    return max(peaks)


def refuse_extreme(motion: GroundMotion, duration: float | None = None) -> None:
    """:class:`ExcitationError` if ``motion`` peaks above :data:`EXTREME_PGA_G` within ``duration`` (s; a motion
    rising without a peak and no duration is not judged), naming the motion and its peak."""
    try:
        peak = peak_acceleration(motion, duration)
    except NotImplementedError:
        return
    if EXTREME_PGA_G * records.G_STANDARD < peak < math.inf:
        raise ExcitationError(f"the ground motion '{motion.name}' would peak at {peak:.3g} m/s^2 "
                              f"({peak / records.G_STANDARD:.3g} g), beyond the {EXTREME_PGA_G:g} g a stone block "
                              f"can meet; check its size and units")


@dataclass(frozen=True)
class Scaled(Component):
    """``factor`` times the motion of ``component``."""

    component: Component
    factor: float

    @property
    def end_time(self):
        return self.component.end_time

    @property
    def time_scale(self):
        return self.component.time_scale

    def acceleration(self, t):
        return self.factor * self.component.acceleration(t)

    def velocity(self, t):
        return self.factor * self.component.velocity(t)

    def displacement(self, t):
        return self.factor * self.component.displacement(t)

    @property
    def peak_acceleration(self):
        return self.factor * self.component.peak_acceleration


@dataclass(frozen=True)
class Extended(Component):
    """``component`` run ``extra`` s past its natural end: the same motion, its end later.  After a record's last
    sample the ground keeps its final velocity, zero for a baseline-corrected record: the ground at rest."""

    component: Component
    extra: float

    @property
    def end_time(self):
        return self.component.end_time + self.extra

    @property
    def time_scale(self):
        return self.component.time_scale

    def acceleration(self, t):
        return self.component.acceleration(t)

    def velocity(self, t):
        return self.component.velocity(t)

    def displacement(self, t):
        return self.component.displacement(t)

    @property
    def peak_acceleration(self):
        return self.component.peak_acceleration


def extended(motion: GroundMotion, extra: float) -> GroundMotion:
    """``motion`` with both components run ``extra`` s (finite, at least 0) past its natural end, under its own
    name: a record followed by the ground at rest, for what a run leaves once the shaking is over (a
    :class:`MotionSequence`'s last rest lengthened)."""
    if not is_real(extra) or not (math.isfinite(extra) and extra >= 0):
        raise ValueError(f"{motion.name}: the time past the motion's end must be a finite number of seconds, at least "
                         f"0, got {extra!r}")
    if extra == 0:
        return motion
    if isinstance(motion, MotionSequence):
        last = motion.events[-1]
        return _joined(motion.events[:-1] + (replace(last, rest=last.rest + float(extra)),), motion.name, motion.record,
                       motion.factor)
    return GroundMotion(Extended(motion.horizontal, float(extra)), Extended(motion.vertical, float(extra)),
                        name=motion.name)


def scaled(motion: GroundMotion, factor: float) -> GroundMotion:
    """``motion`` with both components multiplied by ``factor`` (finite, positive), named ``"<name> x<factor>"``:
    a record loaded once and run at many amplitudes (a :class:`MotionSequence` event by event)."""
    factor = _positive_factor(factor, "factor", motion.name)
    name = f"{motion.name} x{factor:.4g}"
    if isinstance(motion, MotionSequence):
        return _joined(tuple(replace(event, motion=scaled(event.motion, factor)) for event in motion.events), name,
                       motion.record, motion.factor * factor)
    return GroundMotion(Scaled(motion.horizontal, factor), Scaled(motion.vertical, factor), name=name)


@dataclass(frozen=True, eq=False)
class Joined(Component):
    """Components one after another: ``parts[e]`` from ``starts[e]`` s, its own time 0 there, until the next one
    starts, the last on past ``end`` (s).  Each part takes the ground on from the velocity and displacement the
    parts before it left, so that the ground's velocity and displacement run on where a part starts at rest."""

    parts: tuple
    starts: tuple
    end: float
    _carried_velocity: tuple = field(init=False, repr=False)
    _carried_displacement: tuple = field(init=False, repr=False)

    def __post_init__(self):
        velocity, displacement = [0.0], [0.0]
        for part, start, following in zip(self.parts, self.starts, self.starts[1:]):
            span = following - start
            displacement.append(displacement[-1] + velocity[-1] * span + float(part.displacement(span)))
            velocity.append(velocity[-1] + float(part.velocity(span)))
        object.__setattr__(self, "_carried_velocity", tuple(velocity))
        object.__setattr__(self, "_carried_displacement", tuple(displacement))

    @property
    def end_time(self):
        return self.end

    @property
    def time_scale(self):
        return min(part.time_scale for part in self.parts)

    def _pieced(self, t, piece):
        """``piece(e, local times)`` of the part each of the times ``t`` (s) falls in (the first before 0)."""
        t = np.asarray(t, dtype=float)
        flat = np.atleast_1d(t)
        part = np.maximum(np.searchsorted(self.starts, flat, side="right") - 1, 0)
        out = np.zeros(flat.shape)
        for e, start in enumerate(self.starts):
            here = part == e
            if np.any(here):
                out[here] = piece(e, flat[here] - start)
        return out.reshape(t.shape)

    def acceleration(self, t):
        return self._pieced(t, lambda e, tau: self.parts[e].acceleration(tau))

    def velocity(self, t):
        return self._pieced(t, lambda e, tau: self._carried_velocity[e] + self.parts[e].velocity(tau))

    def displacement(self, t):
        return self._pieced(t, lambda e, tau: self._carried_displacement[e] + self._carried_velocity[e] * tau
                            + self.parts[e].displacement(tau))

    @property
    def peak_acceleration(self):
        return max(part.peak_acceleration for part in self.parts)


@dataclass(frozen=True)
class Event:
    """One event of a :class:`MotionSequence`: ``motion`` from ``start`` s of the sequence, then ``rest`` s of the
    ground at rest before the next event starts."""

    motion: GroundMotion
    start: float
    rest: float

    @property
    def alone(self) -> GroundMotion:
        """The event's motion followed by its rest, as a run of it alone takes it (:func:`extended`)."""
        return extended(self.motion, self.rest)


@dataclass(frozen=True, eq=False)
class MotionSequence(GroundMotion):
    """Ground motions one after another, each followed by the ground at rest (:func:`sequence`): ``events``
    (:class:`Event`, ...), whose motions the components join (:class:`Joined`).  ``record`` is the name of the
    sequence as :func:`sequence` made it and ``factor`` what :func:`scaled` has multiplied it by since (each event's
    own factor stays in its motion's name)."""

    events: tuple = ()
    record: str = ""
    factor: float = 1.0

    def event_steps(self, dt: float) -> np.ndarray:
        """(n_events + 1,) int64: the step of ``dt`` (s) at which each event starts in a run, the first at 0 and each
        next one at the first whole step at or past the end of the rest before it, then the step the last rest
        ends at."""
        steps = [0]
        for event in self.events:
            steps.append(steps[-1] + math.ceil((event.motion.end_time + event.rest) / dt - 1e-9))
        return np.array(steps, dtype=np.int64)

    def on_steps(self, dt: float) -> "MotionSequence":
        """This sequence with each event starting at its step of :meth:`event_steps` (its rest before lengthened by
        less than a step), as a run of step ``dt`` (s) takes it."""
        starts = self.event_steps(dt) * dt
        events = tuple(replace(event, start=float(start), rest=float(following - start - event.motion.end_time))
                       for event, start, following in zip(self.events[:-1], starts, starts[1:]))
        return _joined(events + (replace(self.events[-1], start=float(starts[-2])),), self.name, self.record,
                       self.factor)


def _joined(events: tuple, name: str, record: str | None = None, factor: float = 1.0) -> MotionSequence:
    """The :class:`MotionSequence` of ``events``, which hold their starts, named ``name``: the sequence ``record``
    (``name`` when None) multiplied by ``factor``."""
    starts = tuple(event.start for event in events)
    end = events[-1].start + events[-1].motion.end_time + events[-1].rest
    return MotionSequence(Joined(tuple(event.motion.horizontal for event in events), starts, end),
                          Joined(tuple(event.motion.vertical for event in events), starts, end), name=name,
                          events=events, record=name if record is None else record, factor=factor)


def sequence(motions, rest=0.0, resample=False) -> MotionSequence:
    """Ground motions one after another, each followed by ``rest`` s of the ground at rest: an earthquake and its
    aftershocks, or two earthquakes years apart, on one structure.

    motions : ground motions that end (records, pulses: a finite ``end_time``), at least one, none a sequence.
    rest : s, at least 0: one number for every motion or one per motion.
    resample : records of different sampling intervals are refused (:class:`ExcitationError` naming the record and
        both intervals) unless ``resample`` is true (one value, or one per motion) for each record not on the
        finest interval: such a record is then put on the finest interval by linear interpolation, which leaves a
        piecewise-linear record unchanged where its samples fall on the finer grid.

    Event ``e`` starts at the end of the rest before it; a run starts it at the first whole step from there
    (:meth:`MotionSequence.event_steps`) and gives it the ground's input a run of it alone would get
    (docs/method.md section 2).  The name joins the motions' names with " + "."""
    motions = list(motions) if isinstance(motions, (list, tuple)) else motions
    if not isinstance(motions, list):
        raise TypeError(f"sequence: motions must be a list of ground motions, got {type(motions).__name__}")
    if not motions:
        raise ExcitationError("sequence: no motions: give at least one ground motion", keys=("source",))
    for k, motion in enumerate(motions):
        if not isinstance(motion, GroundMotion):
            raise TypeError(f"sequence: motion {k + 1} must be a ground motion (record(...), sine_pulse(...), ...), "
                            f"got {type(motion).__name__} {shown(motion)}")
        if isinstance(motion, MotionSequence):
            raise ExcitationError(f"sequence: motion {k + 1} '{motion.name}' is a sequence itself: give its motions "
                                  f"one by one", keys=("source",))
        if not math.isfinite(motion.end_time):
            raise ExcitationError(f"sequence: motion {k + 1} '{motion.name}' has no natural end (a harmonic, a ramp): "
                                  f"only motions that end (records, pulses) can follow one another", keys=("source",))
    rests = _per_motion(rest, motions, "rest")
    for motion, value in zip(motions, rests):
        if not is_real(value) or not (math.isfinite(value) and value >= 0):
            raise ExcitationError(f"sequence: the rest after '{motion.name}' must be a finite number of seconds, at "
                                  f"least 0, got {value!r}", keys=("rest",))
    resamples = _per_motion(resample, motions, "resample")
    if not all(isinstance(value, bool) for value in resamples):
        raise ExcitationError(f"sequence: resample must be true or false, for every motion or for each, got "
                              f"{resample!r}", keys=("resample",))
    motions = _on_finest_interval(motions, resamples)
    events, start = [], 0.0
    for motion, value in zip(motions, rests):
        events.append(Event(motion, start, float(value)))
        start += motion.end_time + float(value)
    return _joined(tuple(events), " + ".join(motion.name for motion in motions))


def _per_motion(value, motions: list, what: str) -> list:
    """``value`` for each of ``motions``: one value for all, or a list or tuple of one per motion
    (:class:`ExcitationError` naming ``what`` and both lengths otherwise)."""
    if not isinstance(value, (list, tuple)):
        return [value] * len(motions)
    if len(value) != len(motions):
        raise ExcitationError(f"sequence: {len(value)} value(s) of {what} for {len(motions)} motions: give one value "
                              f"for every motion or one per motion", keys=(what,))
    return list(value)


def sampling_interval(motion: GroundMotion) -> float | None:
    """The sampling interval (s) of the record ``motion`` scales or extends, or None for a motion that is not a
    record."""
    for component in (motion.horizontal, motion.vertical):
        inner = unscaled(component)
        if isinstance(inner, Sampled):
            return inner.dt
    return None


def _on_finest_interval(motions: list, resample: list) -> list:
    """``motions`` with each record not on the finest sampling interval among them resampled onto it where
    ``resample`` says so for it, and refused naming it and both intervals where not."""
    intervals = [sampling_interval(motion) for motion in motions]
    sampled = [k for k, interval in enumerate(intervals) if interval is not None]
    if not sampled:
        return motions
    finest = min(sampled, key=lambda k: intervals[k])
    step = intervals[finest]
    motions = list(motions)
    for k in sampled:
        if abs(intervals[k] - step) <= records.TIME_STEP_TOLERANCE * step:
            continue
        if not resample[k]:
            raise ExcitationError(f"sequence: '{motions[k].name}' is sampled every {intervals[k]:g} s and "
                                  f"'{motions[finest].name}' every {step:g} s: give resample=True to put the records "
                                  f"on the finest interval, {step:g} s, by linear interpolation", keys=("resample",))
        motions[k] = GroundMotion(_resampled(motions[k].horizontal, step), _resampled(motions[k].vertical, step),
                                  name=motions[k].name)
    return motions


def _resampled(component: Component, dt: float) -> Component:
    """``component`` with the record it scales or extends sampled every ``dt`` s, linear between its samples (the
    last held to the end of the new grid's last step)."""
    if isinstance(component, (Scaled, Extended)):
        return replace(component, component=_resampled(component.component, dt))
    if not isinstance(component, Sampled):
        return component
    count = math.ceil(component.end_time / dt - 1e-6) + 1
    own = np.arange(len(component.samples)) * component.dt
    return Sampled(np.interp(np.arange(count) * dt, own, component.samples), dt, name=component.name,
                   factor=component.factor)


def still() -> GroundMotion:
    """No ground motion."""
    return GroundMotion(name="none")


def harmonic(amplitude: float | None = None, frequency: float = 1.0, *, pga: float | None = None,
             vertical_amplitude: float = 0.0) -> GroundMotion:
    """Harmonic ground displacement ``u_g = A sin(2 pi f t)``.

    amplitude : A in m; or give ``pga`` (m/s^2) and A = pga / (2 pi f)^2.
    frequency : f in Hz.
    vertical_amplitude : m, a vertical component in phase with the horizontal.
    """
    _positive(frequency, "harmonic frequency", "Hz")
    if amplitude is not None and pga is not None:
        raise ExcitationError(f"harmonic: give exactly one of amplitude (m) and pga (m/s^2), got both: "
                              f"amplitude = {amplitude!r} and pga = {pga!r}", keys=("amplitude", "pga"))
    if amplitude is None and pga is None:
        raise ExcitationError("harmonic: give exactly one of amplitude (m) and pga (m/s^2), got neither",
                              keys=("amplitude", "pga"))
    if amplitude is None:
        if _finite(pga, "harmonic pga (m/s^2)") < 0:
            raise ValueError(f"harmonic pga must not be negative, got {pga!r} m/s^2 (the amplitude's sign sets "
                             f"the phase)")
        amplitude = pga / (2.0 * np.pi * frequency) ** 2
    _finite(amplitude, "harmonic amplitude (m)")
    _finite(vertical_amplitude, "harmonic vertical_amplitude (m)")
    vertical = Harmonic(vertical_amplitude, frequency) if vertical_amplitude else Still()
    return GroundMotion(Harmonic(amplitude, frequency), vertical, name=f"harmonic {amplitude:g} m at {frequency:g} Hz")


def rectangular_pulse(amplitude: float, duration: float) -> GroundMotion:
    """Constant acceleration ``amplitude`` (m/s^2) for ``duration`` (s) from t = 0."""
    return GroundMotion(Pulse(amplitude, duration, "rectangular"), name=f"rectangular pulse {amplitude:g} m/s^2")


def sine_pulse(amplitude: float, duration: float) -> GroundMotion:
    """One-sine acceleration pulse ``a_p sin(2 pi t / T_p)``, 0 <= t < T_p."""
    return GroundMotion(Pulse(amplitude, duration, "sine"), name=f"one-sine pulse {amplitude:g} m/s^2")


def cosine_pulse(amplitude: float, duration: float) -> GroundMotion:
    """One-cosine acceleration pulse ``a_p cos(2 pi t / T_p)``, 0 <= t < T_p."""
    return GroundMotion(Pulse(amplitude, duration, "cosine"), name=f"one-cosine pulse {amplitude:g} m/s^2")


def ramp(rate: float, peak: float | None = None) -> GroundMotion:
    """Monotonic acceleration ``a_g = rate * t`` (m/s^2 per s), optionally held at ``peak``."""
    return GroundMotion(Ramp(rate, peak), name=f"ramp {rate:g} m/s^3")


def record(source, dt: float | None = None, scale: float = 1.0, pga: float | None = None,
           vertical=None, *, units: str = "m/s^2", component: int | None = None,
           baseline: bool = True, resample: bool = False) -> GroundMotion:
    """A recorded accelerogram as ground motion.

    source : path of a PEER AT2 file or a column text file, the name of a
        bundled record (see :data:`dem_core.inputs.records.BUNDLED`), or an array of
        accelerations in m/s^2 (then ``dt`` is required).
    dt : s, sampling interval; read from the file when it has a time column or header (a ``dt`` given
        must then agree with it, or the error names both) or from the bundled record's entry.
    scale : finite positive factor applied to both components; ignored when ``pga`` is given.
    pga : m/s^2, finite and positive: scale the horizontal component, as run (after ``baseline``), to this
        peak (the vertical by the same factor).
    vertical : None, a 1-based component index of the same file, another
        source (path or array, same dt), or a bundled record's own vertical with ``True``.
    units : of a text file (``"m/s^2"``, ``"g"``, ``"cm/s^2"``); AT2 files state theirs.
    component : 1-based component of a multi-column file (default: the first,
        or the bundled record's documented one).
    baseline : subtract the linear baseline that brings the ground back to rest at the end
        (see :func:`baseline_correct`).
    resample : a text file whose time column is uneven is refused naming its largest gap, unless
        ``resample`` is true: it is then interpolated linearly onto a uniform step, ``dt`` if given, else
        the time column's median step (see :func:`dem_core.inputs.records.read_text_record`).

    A sample that stands alone far above the others (:func:`dem_core.inputs.records.find_spike`) is
    refused naming the record, the sample's line (or index) and time, and its value.
    """
    where = _source_name(source)
    scale = _positive_factor(scale, "scale", where)
    if pga is not None:
        pga = _positive_factor(pga, "pga (m/s^2)", where)
    if dt is not None:
        dt = records.check_dt(dt, where)
    if not isinstance(resample, bool):
        raise records.RecordError(f"{where}: resample must be true or false, got {resample!r}")
    horizontal, dt, name, bundled = _load(source, dt, units, component, resample)
    if vertical is True:
        if bundled is None or bundled.vertical_component is None:
            raise ValueError(f"{name}: has no bundled vertical component")
        vertical = bundled.vertical_component
    if vertical is None or vertical is False:
        vert = None
    elif is_integer(vertical):
        vert, vdt, _, _ = _load(source, dt, units, int(vertical), resample)
    else:
        vert, vdt, _, _ = _load(vertical, dt, units, None, resample)
    if vert is not None:
        if abs(vdt - dt) > 1e-9 * dt:
            raise ValueError(f"{name}: vertical component is sampled every {vdt} s, horizontal every {dt} s")
        n = max(len(horizontal), len(vert))
        horizontal = np.pad(horizontal, (0, n - len(horizontal)))
        vert = np.pad(vert, (0, n - len(vert)))
    for samples, which in ((horizontal, where), (vert, f"{where} (vertical)")):
        if samples is not None and len(samples) < 2:
            raise records.RecordError(f"{which}: a record needs at least 2 samples, found {len(samples)}")
    raw_peak = float(np.max(np.abs(horizontal)))
    if baseline:
        horizontal = baseline_correct(horizontal, dt)
        vert = None if vert is None else baseline_correct(vert, dt)
    peak = float(np.max(np.abs(horizontal)))
    if pga is not None:
        if raw_peak == 0:
            raise records.RecordError(f"{where}: cannot scale to pga={pga}: the record is zero throughout")
        if peak <= BASELINE_REMAINDER * raw_peak:
            raise records.RecordError(f"{where}: cannot scale to pga={pga}: the baseline correction leaves nothing "
                                      f"of the record (a constant or a straight line): turn the correction off "
                                      f"(baseline false), or give a record that shakes")
        scale = pga / peak
    h = Sampled(horizontal * scale, dt, name=name, factor=scale)
    v = Sampled(vert * scale, dt, name=name + " (vertical)", factor=scale) if vert is not None else Still()
    return GroundMotion(h, v, name=f"{name} x{scale:.4g}")


def _load(source, dt, units, component, resample=False):
    """Accelerations from any record source: ``(a m/s^2, dt, name, bundled entry or None)``."""
    if isinstance(source, (str, Path)) and str(source) in records.BUNDLED and not Path(source).exists():
        entry = records.BUNDLED[str(source)]
        path = records.bundled_path(str(source))
        a, step = _read_file(path, entry.dt, entry.units, component or entry.component, False)
        if dt is not None and abs(dt - step) > records.TIME_STEP_TOLERANCE * step:
            raise records.RecordError(f"{source}: dt={dt:g} was given but the bundled record is sampled every "
                                      f"{step:g} s: leave dt out (or read its file, records.bundled_path"
                                      f"({str(source)!r}), at another step)")
        return a, step, str(source), entry
    if isinstance(source, (str, Path)):
        path = Path(source)
        a, step = _read_file(path, dt, units, component or 1, resample)
        return a, step, path.stem, None
    name = "array record"
    try:
        a = np.asarray(source, dtype=float)
    except (TypeError, ValueError):
        raise records.RecordError(f"{name}: the source must be a record name, a path or an array of "
                                  f"accelerations (m/s^2), got {type(source).__name__}") from None
    if a.ndim != 1:
        raise records.RecordError(f"{name}: accelerations must be a 1-D array, got shape {a.shape}")
    _check_finite(a, name)
    if dt is None:
        raise records.RecordError(f"{name}: an array record needs dt (s)")
    records.refuse_spike(a, np.arange(len(a)) * dt, "m/s^2", lambda k: f"{name}: sample {k}")
    return a, dt, name, None


def _finite(value, what: str) -> float:
    """``value`` as a float if it is a finite number; else ValueError naming ``what``."""
    if not is_real(value) or not math.isfinite(value):
        raise ValueError(f"{what} must be a finite number, got {value!r}")
    return float(value)


def _positive(value, what: str, unit: str, note: str = "") -> float:
    """``value`` as a float if it is a finite positive number; else ValueError naming ``what`` and the value
    in ``unit``."""
    if _finite(value, f"{what} ({unit})") <= 0:
        raise ValueError(f"{what} must be positive, got {value!r} {unit}{note}")
    return float(value)


def _source_name(source) -> str:
    """How errors name a record source before it is read."""
    return str(source) if isinstance(source, (str, Path)) else "array record"


def _positive_factor(value, what: str, where: str) -> float:
    if not is_real(value) or not (math.isfinite(value) and value > 0):
        raise records.RecordError(f"{where}: {what} must be a finite positive number, got {value!r}")
    return float(value)


def _check_finite(a, name: str) -> None:
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        others = f" ({bad.size - 1} more samples are not finite either)" if bad.size > 1 else ""
        raise records.RecordError(f"{name}: sample {bad[0]} is not finite ({a[bad[0]]}){others}")


def _read_file(path, dt, units, component, resample):
    if path.suffix.lower() == ".at2":
        a, step = records.read_at2(path)
        if component not in (None, 1):
            raise records.RecordError(f"{path}: an AT2 file holds one component, asked for component {component}")
        if dt is not None and abs(dt - step) > records.TIME_STEP_TOLERANCE * step:
            raise records.RecordError(f"{path}: dt={dt:g} was given but the file's header says DT={step:g} s: "
                                      f"leave dt out to use the header's")
        return a, step
    a, step, t0 = records.read_text_record(path, dt=dt, units=units, component=component, resample=resample)
    lead = round(t0 / step)
    if lead > len(a):
        raise records.RecordError(f"{path}: the time column starts at {t0:g} s, later than the record lasts "
                                  f"({(len(a) - 1) * step:g} s): is the first column time?")
    if lead > 0 and abs(lead * step - t0) < records.TIME_STEP_TOLERANCE * step:
        a = np.concatenate([np.zeros(lead), a])  # first sample at t0 > 0: the ground is still before it
    return a, step

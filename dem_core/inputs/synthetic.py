"""Synthetic ground motions where records are scarce: stochastic motions of an earthquake scenario and near-fault
velocity pulses, seeded so that a suite is made again identically.

A stochastic motion (:func:`stochastic_motion`) follows Boore (2003, "Simulation of ground motion using the
stochastic method", Pure Appl. Geophys. 160): Gaussian white noise under a Saragoni-Hart envelope, its Fourier
spectrum normalised to unit mean square amplitude and multiplied by a target Fourier amplitude spectrum.  The
target is the effective amplitude spectrum of Bayless and Abrahamson (2019, BSSA 109(5)), with a residual drawn per
motion with that model's standard deviation and the inter-frequency correlation of Bayless and Abrahamson (2018,
BSSA 108(6)); the envelope lasts so that the motion's 5-95% significant duration is the one of Afshari and Stewart
(2016, Earthquake Spectra 32(4)), drawn per motion with that model's standard deviation.  The models are pygmm's.

A near-fault pulse (:func:`velocity_pulse`) is the Mavroeidis and Papageorgiou (2003, BSSA 93(3)) pulse:

    v(t) = A/2 (1 + cos(2 pi f_p (t - t_0) / gamma)) cos(2 pi f_p (t - t_0) + nu),  |t - t_0| <= gamma / (2 f_p)

with its period ``T_p = 1/f_p`` from their regression ``log10 T_p = -2.9 + 0.5 M_w`` (:func:`pulse_period`).
A near-fault motion (:func:`near_fault_motion`) adds such a pulse to a stochastic motion of the same scenario, a
superposition that keeps both whole (Mavroeidis and Papageorgiou instead take the pulse's band out of the
stochastic motion first).
"""

import math
from dataclasses import dataclass

import numpy as np

from .excitation import GroundMotion, Sampled, Still, baseline_correct
from .number_types import is_integer, is_real
from .records import G_STANDARD

#: the Saragoni-Hart envelope's shape (Boore 2003, eq. 9-10): the envelope peaks at EPSILON of its length and
#: has fallen to ETA of its peak at its end
EPSILON, ETA = 0.2, 0.05
#: s, the sampling interval of a synthetic motion unless given
DT = 0.01
#: s of a stochastic motion kept after its envelope's end: the long periods its spectrum gives spread past the
#: envelope, and a column rocks on after the shaking
TAIL = 5.0
#: mechanisms the ground-motion models take: strike-slip, normal, reverse
MECHANISMS = ("SS", "NS", "RS")
#: the range of a near-fault pulse's oscillatory character gamma and phase nu (rad) a near-fault motion draws from,
#: uniformly: the ranges of the pulses Mavroeidis and Papageorgiou (2003) fitted to records (their Table 1)
PULSE_GAMMA = (1.5, 2.5)
PULSE_PHASE = (0.0, 2.0 * math.pi)


@dataclass(frozen=True)
class Scenario:
    """An earthquake as the ground-motion models take it.

    magnitude : moment magnitude M_w.
    distance_km : km, taken as both the rupture and the Joyner-Boore distance (a rupture reaching the surface
        above the site's side of the fault).
    vs30 : m/s, the site's time-averaged shear-wave velocity over its top 30 m (760 is rock, 400 stiff soil).
    mechanism : "SS" strike-slip, "NS" normal, "RS" reverse.
    """

    magnitude: float
    distance_km: float
    vs30: float = 760.0
    mechanism: str = "NS"

    def __post_init__(self):
        for what, value, low, high in (("magnitude", self.magnitude, 3.0, 8.0),
                                       ("distance_km", self.distance_km, 0.0, 300.0),
                                       ("vs30", self.vs30, 180.0, 1500.0)):
            if not is_real(value) or not low <= value <= high:
                raise ValueError(f"scenario {what} must be a number from {low:g} to {high:g} (the range of the "
                                 f"ground-motion models), got {value!r}")
        if self.mechanism not in MECHANISMS:
            raise ValueError(f"scenario mechanism must be one of {', '.join(MECHANISMS)}, got {self.mechanism!r}")

    @property
    def label(self) -> str:
        return f"M{self.magnitude:g} {self.mechanism} R {self.distance_km:g} km Vs30 {self.vs30:g} m/s"

    def pygmm(self):
        """The scenario as pygmm's :class:`pygmm.Scenario`."""
        import pygmm
        return pygmm.Scenario(mag=self.magnitude, dist_rup=self.distance_km, dist_jb=self.distance_km,
                              dist_x=0.0, v_s30=self.vs30, mechanism=self.mechanism, depth_tor=0.0, dip=90.0,
                              region="global")


def envelope(t, length: float) -> np.ndarray:
    """Saragoni-Hart envelope of ``length`` s at times ``t`` (s): ``a (t/L)^b exp(-c t/L)``, 1 at ``EPSILON L``,
    :data:`ETA` at ``L`` and 0 after (Boore 2003, eq. 9-10)."""
    b = -EPSILON * math.log(ETA) / (1.0 + EPSILON * (math.log(EPSILON) - 1.0))
    c = b / EPSILON
    a = (math.e / EPSILON) ** b
    x = np.asarray(t, dtype=float) / length
    inside = (x >= 0.0) & (x <= 1.0)
    x = np.where(inside, x, 0.0)
    return np.where(inside, a * x ** b * np.exp(-c * x), 0.0)


def significant_share(low: float = 0.05, high: float = 0.95) -> float:
    """The time between ``low`` and ``high`` of the Arias intensity of motion under :func:`envelope` (white noise:
    the envelope squared), as a share of the envelope's length."""
    x = np.linspace(0.0, 1.0, 200_001)
    cumulative = np.cumsum(envelope(x, 1.0) ** 2)
    start, end = np.interp((low, high), cumulative / cumulative[-1], x)
    return float(end - start)


def motion_rng(seed: int, index: int = 0) -> np.random.Generator:
    """The random stream of motion ``index`` of a suite seeded ``seed``: each motion's own, whatever the suite's
    size."""
    return np.random.default_rng([int(seed), int(index)])


def stochastic_accelerations(scenario: Scenario, rng: np.random.Generator, dt: float = DT,
                             variability: bool = True) -> np.ndarray:
    """Accelerations (m/s^2, every ``dt`` s from 0, shape (n,)) of one stochastic motion of ``scenario``.

    The envelope lasts ``D5-95 / significant_share()``, D5-95 of Afshari and Stewart (2016), and the motion
    :data:`TAIL` s more; the target Fourier amplitude is Bayless and Abrahamson's (2019) effective amplitude
    spectrum, interpolated in log-log between its frequencies (0.1 to 100 Hz) and falling as f^2 below 0.1 Hz (the
    omega-squared source).  ``variability``: the duration and the spectrum each take a residual drawn with their
    model's standard deviation (the spectrum's correlated across frequency, Bayless and Abrahamson 2018; above the
    highest frequency whose standard deviation the model gives, the last one given); otherwise both are the medians
    and only the phases are random.
    """
    import pygmm
    where = scenario.pygmm()
    durations = pygmm.AfshariStewart2016(where)
    d595 = float(durations.duration["D_5t95"])
    spectrum = pygmm.BaylessAbrahamson2019(where)
    ln_eas = np.log(spectrum.eas)
    if variability:
        d595 *= math.exp(float(durations.std_err["D_5t95"]) * rng.standard_normal())
        std = np.array(spectrum.ln_std, dtype=float)
        given = np.flatnonzero(np.isfinite(std))
        std[given[-1]:] = std[given[-1]]
        covariance = pygmm.BaylessAbrahamson2018.cov(spectrum.freqs, std=std)
        lower = np.linalg.cholesky(covariance + 1e-10 * np.eye(len(std)))
        ln_eas = ln_eas + lower @ rng.standard_normal(len(std))
    length = d595 / significant_share()
    n = math.ceil(length / dt) + 1
    kept = n + round(TAIL / dt)
    n_fft = 1 << math.ceil(math.log2(2 * kept))
    noise = rng.standard_normal(n) * envelope(np.arange(n) * dt, length)
    phases = np.fft.rfft(noise, n_fft)
    phases /= np.sqrt(np.mean(np.abs(phases) ** 2))
    f = np.fft.rfftfreq(n_fft, dt)
    f_low = spectrum.freqs[0]
    amplitude = np.exp(np.interp(np.log(np.maximum(f, f_low)), np.log(spectrum.freqs), ln_eas))
    amplitude = np.where(f < f_low, amplitude * (f / f_low) ** 2, amplitude)  # g s
    return np.fft.irfft(amplitude * G_STANDARD / dt * phases, n_fft)[:kept]


def pulse_period(magnitude: float) -> float:
    """s, the median near-fault pulse period of Mavroeidis and Papageorgiou (2003): ``log10 T_p = -2.9 + 0.5 M_w``."""
    return 10.0 ** (-2.9 + 0.5 * magnitude)


def pulse_velocity(t, amplitude: float, period: float, gamma: float = 2.0, phase: float = 0.0,
                   peak_time: float | None = None) -> np.ndarray:
    """Ground velocity (m/s) of the Mavroeidis-Papageorgiou pulse at times ``t`` (s), the equation in the module's
    docstring: ``amplitude`` A (m/s), ``period`` T_p (s), ``gamma`` > 1, ``phase`` nu (rad), ``peak_time`` t_0
    (s; default half the pulse's length, ``gamma T_p / 2``, so that it starts at t = 0)."""
    t0, half = _pulse_times(period, gamma, peak_time)
    tau = np.asarray(t, dtype=float) - t0
    w = 2.0 * math.pi / period
    inside = np.abs(tau) <= half
    return np.where(inside, amplitude / 2.0 * (1.0 + np.cos(w * tau / gamma)) * np.cos(w * tau + phase), 0.0)


def pulse_acceleration(t, amplitude: float, period: float, gamma: float = 2.0, phase: float = 0.0,
                       peak_time: float | None = None) -> np.ndarray:
    """Ground acceleration (m/s^2), the time derivative of :func:`pulse_velocity`."""
    t0, half = _pulse_times(period, gamma, peak_time)
    tau = np.asarray(t, dtype=float) - t0
    w = 2.0 * math.pi / period
    inside = np.abs(tau) <= half
    a = -amplitude / 2.0 * (w / gamma * np.sin(w * tau / gamma) * np.cos(w * tau + phase)
                            + w * (1.0 + np.cos(w * tau / gamma)) * np.sin(w * tau + phase))
    return np.where(inside, a, 0.0)


def _pulse_times(period: float, gamma: float, peak_time: float | None) -> tuple[float, float]:
    """``(t_0, half length)`` s of a pulse, after checking its parameters."""
    if not (is_real(period) and math.isfinite(period) and period > 0):
        raise ValueError(f"pulse period must be a positive number of seconds, got {period!r}")
    if not (is_real(gamma) and math.isfinite(gamma) and gamma > 1):
        raise ValueError(f"pulse gamma must be a number above 1 (Mavroeidis and Papageorgiou 2003), got {gamma!r}")
    half = gamma * period / 2.0
    return (half if peak_time is None else float(peak_time)), half


def velocity_pulse(amplitude: float, period: float, gamma: float = 2.0, phase: float = 0.0, *, dt: float = 0.001,
                   peak_time: float | None = None) -> GroundMotion:
    """A Mavroeidis-Papageorgiou pulse as ground motion: :func:`pulse_acceleration` sampled every ``dt`` s from 0
    to its end (the ground velocity is then that of :func:`pulse_velocity` within O(dt^2))."""
    t0, half = _pulse_times(period, gamma, peak_time)
    t = np.arange(0.0, t0 + half + dt, dt)
    a = pulse_acceleration(t, amplitude, period, gamma, phase, t0)
    return GroundMotion(Sampled(a, dt, name="pulse"), Still(),
                        name=f"pulse {amplitude:g} m/s T_p {period:g} s gamma {gamma:g} nu {phase:.3g}")


def stochastic_motion(scenario: Scenario, seed: int = 0, index: int = 0, dt: float = DT,
                      variability: bool = True) -> GroundMotion:
    """Motion ``index`` of the stochastic suite of ``scenario`` seeded ``seed`` (:func:`stochastic_accelerations`),
    baseline-corrected as a record is (:func:`dem_core.inputs.excitation.baseline_correct`)."""
    a = baseline_correct(stochastic_accelerations(scenario, motion_rng(seed, index), dt, variability), dt)
    name = f"stochastic {scenario.label} seed {seed}-{index}"
    return GroundMotion(Sampled(a, dt, name=name), Still(), name=name)


def near_fault_accelerations(scenario: Scenario, rng: np.random.Generator, dt: float = DT) -> tuple:
    """``(accelerations m/s^2, pulse)`` of one near-fault motion: a stochastic motion of ``scenario`` plus a
    Mavroeidis-Papageorgiou pulse, ``pulse`` its parameters (amplitude m/s, period s, gamma, phase rad, peak time
    s).  The pulse's period is :func:`pulse_period`, its amplitude the median PGV of Boore, Stewart, Seyhan and
    Atkinson (2014) for the scenario, gamma and nu drawn uniformly from :data:`PULSE_GAMMA` and
    :data:`PULSE_PHASE`, and its peak at the middle of the stochastic motion's strong motion."""
    import pygmm
    background = stochastic_accelerations(scenario, rng, dt)
    amplitude = float(pygmm.BooreStewartSeyhanAtkinson2014(scenario.pygmm()).pgv) / 100.0
    period = pulse_period(scenario.magnitude)
    gamma = float(rng.uniform(*PULSE_GAMMA))
    phase = float(rng.uniform(*PULSE_PHASE))
    energy = np.cumsum(background ** 2)
    middle = float(np.interp(0.5, energy / energy[-1], np.arange(len(background)) * dt))
    peak_time = max(middle, gamma * period / 2.0)
    n = max(len(background), math.ceil((peak_time + gamma * period / 2.0) / dt) + 1)
    t = np.arange(n) * dt
    a = np.pad(background, (0, n - len(background))) + pulse_acceleration(t, amplitude, period, gamma, phase,
                                                                           peak_time)
    return a, (amplitude, period, gamma, phase, peak_time)


def near_fault_record(scenario: Scenario, seed: int = 0, index: int = 0, dt: float = DT) -> tuple:
    """``(motion, pulse)``: motion ``index`` of the near-fault suite of ``scenario`` seeded ``seed``
    (:func:`near_fault_accelerations`), baseline-corrected as a record is, and its pulse's parameters."""
    a, pulse = near_fault_accelerations(scenario, motion_rng(seed, index), dt)
    amplitude, period = pulse[:2]
    name = f"near-fault {scenario.label} pulse {amplitude:.2g} m/s T_p {period:.2g} s seed {seed}-{index}"
    return GroundMotion(Sampled(baseline_correct(a, dt), dt, name=name), Still(), name=name), pulse


def near_fault_motion(scenario: Scenario, seed: int = 0, index: int = 0, dt: float = DT) -> GroundMotion:
    """Motion ``index`` of the near-fault suite of ``scenario`` seeded ``seed`` (:func:`near_fault_record`)."""
    return near_fault_record(scenario, seed, index, dt)[0]


def synthetic_suite(scenario: Scenario, count: int, seed: int = 0, *, pulses: bool = False, dt: float = DT,
                    variability: bool = True) -> dict:
    """``count`` synthetic motions of ``scenario`` in one call: ``{name: GroundMotion}``, stochastic
    (:func:`stochastic_motion`) or, with ``pulses``, near-fault (:func:`near_fault_motion`).  Motion k depends only
    on ``seed`` and k, so a larger suite of the same seed begins with the smaller one."""
    if not is_integer(count) or count < 1:
        raise ValueError(f"a synthetic suite needs a whole number of motions, at least 1, got {count!r}")
    motions = {}
    for index in range(count):
        motion = (near_fault_motion(scenario, seed, index, dt) if pulses
                  else stochastic_motion(scenario, seed, index, dt, variability))
        motions[motion.name] = motion
    return motions

"""Elastic response spectra of a ground motion.

For each period T (omega = 2 pi / T) and damping ratio zeta the relative
displacement of a linear oscillator, ``u'' + 2 zeta omega u' + omega^2 u = -a_g(t)``,
is integrated exactly for piecewise-linear ``a_g`` (Nigam and Jennings 1969;
Chopra, Dynamics of Structures, section 5.2).  Spectral displacement
SD = max |u|, pseudo-velocity PSV = omega SD, pseudo-acceleration PSA = omega^2 SD.
"""

from dataclasses import dataclass

import numpy as np

from ..inputs.excitation import unscaled

DEFAULT_PERIODS = np.geomspace(0.02, 5.0, 120)  # s


@dataclass(frozen=True)
class ResponseSpectrum:
    """periods (n,) s; sd (n,) m; psv (n,) m/s; psa (n,) m/s^2; damping ratio; pga m/s^2."""

    periods: np.ndarray
    sd: np.ndarray
    psv: np.ndarray
    psa: np.ndarray
    damping: float
    pga: float
    name: str = ""


def _coefficients(omega, zeta, dt):
    """Recurrence u_{i+1} = A u_i + B v_i + C p_i + D p_{i+1} (and A'..D' for v), unit mass, p = -a_g."""
    k = omega ** 2
    root = np.sqrt(1.0 - zeta ** 2)
    wd = omega * root
    e = np.exp(-zeta * omega * dt)
    s, c = np.sin(wd * dt), np.cos(wd * dt)
    a = e * (zeta / root * s + c)
    b = e * s / wd
    cc = (2 * zeta / (omega * dt) + e * (((1 - 2 * zeta ** 2) / (wd * dt) - zeta / root) * s
                                         - (1 + 2 * zeta / (omega * dt)) * c)) / k
    d = (1 - 2 * zeta / (omega * dt) + e * ((2 * zeta ** 2 - 1) / (wd * dt) * s + 2 * zeta / (omega * dt) * c)) / k
    a_v = -e * omega / root * s
    b_v = e * (c - zeta / root * s)
    c_v = (-1 / dt + e * ((omega / root + zeta / (dt * root)) * s + c / dt)) / k
    d_v = (1 - e * (zeta / root * s + c)) / (k * dt)
    return a, b, cc, d, a_v, b_v, c_v, d_v


def oscillator_response(acceleration, dt: float, periods, damping: float = 0.05) -> np.ndarray:
    """(n_steps, n_periods) relative displacement (m) of oscillators at rest at t = 0 under the
    ground acceleration samples ``acceleration`` (m/s^2, spacing ``dt`` s, linear in between)."""
    acc = np.asarray(acceleration, dtype=float)
    omega = 2.0 * np.pi / np.asarray(periods, dtype=float)
    if not 0.0 <= damping < 1.0:
        raise ValueError(f"damping ratio must be in [0, 1), got {damping}")
    if np.any(~np.isfinite(omega)) or np.any(omega <= 0):
        raise ValueError("periods must be positive and finite")
    a, b, c, d, a_v, b_v, c_v, d_v = _coefficients(omega, damping, dt)
    u = np.zeros_like(omega)
    v = np.zeros_like(omega)
    out = np.empty((len(acc), len(omega)))
    out[0] = u
    p = -acc
    for i in range(len(acc) - 1):
        u, v = a * u + b * v + c * p[i] + d * p[i + 1], a_v * u + b_v * v + c_v * p[i] + d_v * p[i + 1]
        out[i + 1] = u
    return out


def response_spectrum(motion, periods=DEFAULT_PERIODS, damping: float = 0.05, *, dt: float | None = None,
                      duration: float | None = None) -> ResponseSpectrum:
    """Elastic spectrum of the horizontal component of ``motion`` (a GroundMotion).

    dt : s, sampling of the acceleration; default the record's own step, a scaled record's too (0.005 s for other
        motions).
    duration : s, default the motion's end plus 4 times the longest period (free vibration after
        the record can hold the peak of long periods).
    """
    periods = np.asarray(periods, dtype=float)
    horizontal = motion.horizontal
    dt = dt or getattr(unscaled(horizontal), "dt", None) or 0.005
    end = motion.end_time
    if not np.isfinite(end) and duration is None:
        raise ValueError(f"the motion '{motion.name}' has no end: give a duration")
    duration = duration if duration is not None else end + 4.0 * periods.max()
    t = np.arange(0.0, duration + 0.5 * dt, dt)
    acc = np.asarray(horizontal.acceleration(t), dtype=float)
    u = oscillator_response(acc, dt, periods, damping)
    sd = np.max(np.abs(u), axis=0)
    omega = 2.0 * np.pi / periods
    return ResponseSpectrum(periods, sd, omega * sd, omega ** 2 * sd, damping, float(np.max(np.abs(acc))),
                            motion.name)


def spectrum_figure(spectra, title: str = "Elastic response spectra"):
    """Figure of PSA (m/s^2, with g on a second axis) and SD (m) against period for one or more
    :class:`ResponseSpectrum`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..inputs.records import G_STANDARD

    fig, (ax_a, ax_d) = plt.subplots(1, 2, figsize=(10, 4))
    for s in spectra:
        label = f"{s.name}, PGA {s.pga:.3g} m/s$^2$ ({s.pga / G_STANDARD:.3g} g)"
        ax_a.plot(s.periods, s.psa, label=label)
        ax_d.plot(s.periods, s.sd, label=label)
    damping = {s.damping for s in spectra}
    ax_a.set(xlabel="period (s)", ylabel="pseudo-acceleration (m/s$^2$)", xscale="log",
             title=f"PSA, damping {', '.join(f'{z:.0%}' for z in damping)}")
    in_g = ax_a.secondary_yaxis("right", functions=(lambda a: a / G_STANDARD, lambda g: g * G_STANDARD))
    in_g.set_ylabel("(g)")
    ax_d.set(xlabel="period (s)", ylabel="displacement (m)", xscale="log", yscale="log", title="SD")
    for ax in (ax_a, ax_d):
        ax.grid(True, which="both", alpha=0.3)
    ax_a.legend(fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig

"""Target spectra and the records of a suite selected and scaled to match one over a range of periods.

Targets (5%-damped pseudo-spectral acceleration, m/s^2):

- :func:`ec8_spectrum`: the horizontal elastic response spectrum of Eurocode 8 (EN 1998-1:2004, section 3.2.2.2,
  eq. 3.2-3.5, Tables 3.2 and 3.3) for a ground type, a design ground acceleration ``a_g`` and a spectrum type;
- :func:`model_spectrum`: a ground-motion model's median and log standard deviation for a scenario (pygmm's
  Akkar, Sandikkaya and Bommer 2014 for Europe and the Middle East, or Boore, Stewart, Seyhan and Atkinson 2014).

:func:`select_and_scale` scales each record by the factor that brings its spectrum nearest the target in the least
squares of their logarithms over the periods, ranks the records by what remains (the standard deviation of the log
ratio: the misfit of the spectrum's shape), and keeps the best ``count``; with ``floor`` (Eurocode 8's 0.9,
EN 1998-1 section 3.2.3.1.2 (4)) the kept records are then scaled by one more common factor, where needed, so that
their mean spectrum lies nowhere below ``floor`` times the target over the periods.
"""

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..inputs.records import G_STANDARD
from ..inputs.number_types import is_integer, is_real
from .spectra import response_spectrum

#: Eurocode 8's ground types: {spectrum type: {ground type: (S, T_B s, T_C s, T_D s)}} (EN 1998-1 Tables 3.2, 3.3)
EC8_GROUND = {
    1: {"A": (1.0, 0.15, 0.4, 2.0), "B": (1.2, 0.15, 0.5, 2.0), "C": (1.15, 0.20, 0.6, 2.0),
        "D": (1.35, 0.20, 0.8, 2.0), "E": (1.4, 0.15, 0.5, 2.0)},
    2: {"A": (1.0, 0.05, 0.25, 1.2), "B": (1.35, 0.05, 0.25, 1.2), "C": (1.5, 0.10, 0.25, 1.2),
        "D": (1.8, 0.10, 0.30, 1.2), "E": (1.6, 0.05, 0.25, 1.2)},
}
#: Eurocode 8's rule for a suite of records: its mean spectrum nowhere below this share of the elastic spectrum
EC8_FLOOR = 0.9
#: the ground-motion models a target may come from: name -> pygmm's class name
MODELS = {"ASB14": "AkkarSandikkayaBommer2014", "BSSA14": "BooreStewartSeyhanAtkinson2014"}


def ec8_spectrum(periods, ag: float, ground: str = "B", spectrum_type: int = 1, damping: float = 0.05) -> np.ndarray:
    """Eurocode 8's horizontal elastic spectrum S_e(T) (m/s^2) at ``periods`` (s, up to 4 s): ``ag`` (m/s^2) the
    design ground acceleration on ground type A, ``ground`` A to E, ``spectrum_type`` 1 (surface-wave magnitude
    above 5.5) or 2, ``damping`` the viscous damping ratio (eta = sqrt(0.10 / (0.05 + damping)), at least 0.55).

        T <= T_B:        a_g S (1 + T / T_B (2.5 eta - 1))
        T_B <= T <= T_C: 2.5 a_g S eta
        T_C <= T <= T_D: 2.5 a_g S eta T_C / T
        T_D <= T:        2.5 a_g S eta T_C T_D / T^2
    """
    if spectrum_type not in EC8_GROUND:
        raise ValueError(f"Eurocode 8 spectrum type must be 1 or 2, got {spectrum_type!r}")
    if ground not in EC8_GROUND[spectrum_type]:
        raise ValueError(f"Eurocode 8 ground type must be one of {', '.join(EC8_GROUND[1])}, got {ground!r}")
    if not (is_real(ag) and math.isfinite(ag) and ag > 0):
        raise ValueError(f"the design ground acceleration a_g must be a positive number of m/s^2, got {ag!r}")
    t = np.asarray(periods, dtype=float)
    if np.any(t < 0) or np.any(t > 4.0):
        raise ValueError(f"Eurocode 8's elastic spectrum is given from 0 to 4 s, asked for {t.min():g} to "
                         f"{t.max():g} s")
    s, t_b, t_c, t_d = EC8_GROUND[spectrum_type][ground]
    eta = max(math.sqrt(0.10 / (0.05 + damping)), 0.55)
    plateau = 2.5 * ag * s * eta
    away = np.maximum(t, t_b)  # the branches past T_B, evaluated where they apply
    return np.select([t <= t_b, t <= t_c, t <= t_d],
                     [ag * s * (1.0 + t / t_b * (2.5 * eta - 1.0)), np.full_like(t, plateau), plateau * t_c / away],
                     plateau * t_c * t_d / away ** 2)


def model_spectrum(periods, scenario, model: str = "ASB14") -> tuple[np.ndarray, np.ndarray]:
    """``(median m/s^2, log standard deviation)`` at ``periods`` (s) of the ground-motion model ``model`` (a key of
    :data:`MODELS`) for ``scenario`` (:class:`~dem_core.inputs.synthetic.Scenario`), interpolated in log-log
    between the model's periods."""
    import pygmm

    if model not in MODELS:
        raise ValueError(f"the ground-motion model must be one of {', '.join(MODELS)}, got {model!r}")
    found = getattr(pygmm, MODELS[model])(scenario.pygmm())
    t = np.asarray(periods, dtype=float)
    known = np.log(found.periods)
    if np.any(np.log(t) < known[0]) or np.any(np.log(t) > known[-1]):
        raise ValueError(f"{model} gives periods from {found.periods[0]:g} to {found.periods[-1]:g} s, asked for "
                         f"{t.min():g} to {t.max():g} s")
    median = np.exp(np.interp(np.log(t), known, np.log(found.spec_accels))) * G_STANDARD
    return median, np.interp(np.log(t), known, found.ln_stds)


@dataclass(frozen=True)
class Selection:
    """What :func:`select_and_scale` returns: ``table``, one row per record of the suite (``record``, ``factor``,
    the scale factor that brings its spectrum nearest the target, ``misfit``, the standard deviation of the log
    ratio left after it, ``selected``); ``common``, the factor applied on top to the selected records;
    ``periods`` (s), ``target`` and ``mean`` (m/s^2, the selected records' mean scaled spectrum)."""

    table: pd.DataFrame
    common: float
    periods: np.ndarray
    target: np.ndarray
    mean: np.ndarray

    @property
    def factors(self) -> dict:
        """{record: its scale factor, the common one included} of the selected records, best first."""
        chosen = self.table[self.table["selected"]]
        return dict(zip(chosen["record"], chosen["factor"] * self.common))


def select_and_scale(motions: dict, periods, target, count: int, *, largest_factor: float = 5.0,
                     floor: float | None = None) -> Selection:
    """The ``count`` records of ``motions`` ({name: GroundMotion}) whose 5%-damped spectra best match ``target``
    (m/s^2 at ``periods`` s) in shape, each scaled to it (see the module's docstring), among those whose factor lies
    within 1/``largest_factor`` to ``largest_factor``; ``floor`` (e.g. :data:`EC8_FLOOR`): a common factor of at
    least 1 that lifts the selected records' mean spectrum to at least ``floor`` times the target everywhere."""
    periods = np.asarray(periods, dtype=float)
    target = np.asarray(target, dtype=float)
    if not is_integer(count) or not 1 <= count <= len(motions):
        raise ValueError(f"count must be a whole number from 1 to the suite's {len(motions)} records, got {count!r}")
    if target.shape != periods.shape or not np.all(target > 0):
        raise ValueError("the target must give a positive acceleration at every period")
    rows, spectra = [], {}
    for name, motion in motions.items():
        spectra[name] = response_spectrum(motion, periods).psa
        log_ratio = np.log(target / spectra[name])
        rows.append({"record": name, "factor": float(np.exp(log_ratio.mean())), "misfit": float(log_ratio.std())})
    table = pd.DataFrame(rows)
    allowed = table["factor"].between(1.0 / largest_factor, largest_factor)
    if allowed.sum() < count:
        raise ValueError(f"only {int(allowed.sum())} records can be scaled to the target by a factor within "
                         f"1/{largest_factor:g} to {largest_factor:g}; {count} were asked for")
    chosen = table[allowed].sort_values("misfit").index[:count]
    table["selected"] = table.index.isin(chosen)
    table = table.sort_values(["selected", "misfit"], ascending=[False, True], ignore_index=True)
    picked = table[table["selected"]]
    mean = np.mean([spectra[name] * factor for name, factor in zip(picked["record"], picked["factor"])], axis=0)
    common = max(1.0, float(np.max(floor * target / mean))) if floor else 1.0
    return Selection(table, common, periods, target, mean * common)

"""What a run returns: time histories of every block, response measures, run facts.

The same type is returned by every engine, so results line up column by column.
Response measures follow docs/method.md section 3: rotation of each block,
residual displacement relative to the base, total sliding (accumulated
relative slip summed over interfaces), rocking (mean absolute rotation) and
overturning.
"""

import html
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ._connector_law import (ACCUMULATED, AXIAL_STRENGTH, PEAK_SHEAR, PEAK_TENSION, PLASTIC_SLIP, RUPTURE_STEP,
                             SLIP_CAPACITY, YIELD_STEP)
from .state import State

#: the measures of each block, in :meth:`Result.metrics`' columns, a batch's ``<measure>[<block>]`` columns and the
#: command line's metrics.csv: peak |theta| over every step (rad), peak |horizontal displacement| relative to the
#: base over the outputs (m), residual displacement (m), the slip at the block's joints, below and above it, added
#: (m: each joint counts for both its blocks), mean |theta| over the outputs (rad), whether it overturned and when
#: (s, NaN if never)
BLOCK_MEASURES = ("peak_abs_theta_rad", "peak_abs_displacement_m", "residual_displacement_m", "sliding_at_its_joints_m",
                  "mean_abs_theta_rad", "overturned", "overturn_time_s")
#: the measures of the scene, in :meth:`Result.measures`, :meth:`Result.summary` and a batch's row
SCENE_MEASURES = ("max_peak_abs_theta_rad", "total_sliding_m", "mean_rocking_rad", "overturned", "overturn_time_s")
#: the measures of each event of a sequence, in :attr:`Result.events`' ``<measure>[<interface or column>]`` columns:
#: each recorded interface's residual dislocation (m) and each column's residual tilt (rad)
EVENT_MEASURES = ("residual_dislocation_m", "residual_tilt_rad")


@dataclass(frozen=True, eq=False)
class Result:
    """Time histories and measures of one run.

    t : (n,) s, output times.
    x, y, theta : (n, n_blocks) centre-of-mass position (m) and rotation
        (rad, counter-clockwise) of each block, in scene order.
    base_x, base_y : (n,) ground displacement, m.
    names : block names, scene order.
    peak_theta : (n_blocks,) peak |theta| over every time step (not only outputs), rad.
    overturn_time : (n_blocks,) s, first time the block passed its critical
        angle or fell half its size, or the column (stack) it belongs to tipped
        its centre of mass past its base (:mod:`dem_core.engine.stacks`); NaN if never.
    interface_slip : {(name_a, name_b): m} the slip of every interface that slid: at an interface touching
        at the start, the travel of one block over the other measured on their motion (docs/method.md
        section 3), at a pair that met later its contact points' slip; None where a result carries no slip
        (sliding measures are then NaN).
    dt : s, the time step used; info : run facts (engine, stability limit,
        steps, compile and run wall times, ...).
    interfaces : ((name_a, name_b), ...) the interfaces touching at the start, whose slip is
        followed over time.
    slip_history : (n, n_interfaces) slip accumulated at each interface up to each output, m;
        None where a result carries no slip.
    critical_angle : (n_blocks,) each block's own critical angle atan(b/h), rad.
    columns : (:class:`~dem_core.engine.stacks.Column`, ...) the stacks of blocks standing on the
        base (a column's drums and capital) with the tilt at which each tips over as one body.
    final_state : the native engine's whole :class:`~dem_core.engine.state.State` at the run's end (a copy), from
        which another run can go on exactly (``simulate(..., start=result)``); None from another engine.
    model_digest : a digest of the compiled model the run stepped ('' from another engine), which a run going on
        from this one must share.
    lost_stability : why the run lost stability, '' if it did not (a result carried by
        :class:`~dem_core.simulation.SimulationUnstable`).
    events : under a sequence of ground motions (:func:`~dem_core.inputs.excitation.sequence`), one row per event
        reached: ``event`` (1, 2, ...), ``motion`` (its name), ``start_s`` and ``end_s`` (the end of its rest, or
        where the run ended), then at that end against the run's start ``residual_dislocation_m[a/b]`` of each
        recorded interface (m) and ``residual_tilt_rad[label]`` of each column ("bottom..top") and each block
        outside a column (rad; :mod:`dem_core.engine.residual`); None under a single motion.
    connectors : one row per connector of the scene (:mod:`dem_core.inputs.connectors`), in its order: ``name``,
        ``kind``, ``peak_shear_N``, ``peak_tension_N``, ``yielded`` and ``yield_time_s`` (NaN if it did not),
        ``ruptured`` and ``rupture_time_s``, ``pulled_out`` (it ruptured in tension, not in shear),
        ``residual_slip_m`` (its shear spring's plastic slip at the end) and
        ``plastic_slip_m`` (taken over every excursion, of its capacity ``slip_capacity_m``); None without connectors.
    connector_history : (n, n_connectors, 4) at each output each connector's shear force and tension (N), slip
        and opening (m): the slip of the second block's anchor over the first's along the joint (+x where the joint
        is level), the shear force positive where it resists a positive slip; None without connectors.
    """

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    theta: np.ndarray
    base_x: np.ndarray
    base_y: np.ndarray
    names: tuple
    peak_theta: np.ndarray
    overturn_time: np.ndarray
    interface_slip: dict
    dt: float
    info: dict = field(default_factory=dict)
    interfaces: tuple = ()
    slip_history: np.ndarray | None = None
    critical_angle: np.ndarray | None = None
    columns: tuple = ()
    final_state: State | None = None
    model_digest: str = ""
    lost_stability: str = ""
    events: pd.DataFrame | None = None
    connectors: pd.DataFrame | None = None
    connector_history: np.ndarray | None = None

    def governing_angles(self) -> np.ndarray:
        """(n_blocks,) rad: the rotation at which each block is judged to overturn: for a column's drums the
        column's critical angle, for every other block its own; ValueError for a result without critical angles
        (an engine that does not report them)."""
        if self.critical_angle is None:
            raise ValueError("the result carries no critical angles (an engine that does not report them)")
        alpha = np.array(self.critical_angle, dtype=float)
        for column in self.columns:
            for name in column.blocks:
                alpha[self.index(name)] = column.critical_angle
        return alpha

    @property
    def damage_ratio(self) -> float:
        """The largest over the blocks of peak |theta| over its governing critical angle (:meth:`governing_angles`),
        the measure every study uses; NaN for a result without critical angles."""
        if self.critical_angle is None:
            return float("nan")
        return float(np.max(self.peak_theta / self.governing_angles()))

    def __repr__(self) -> str:
        """One line: the engine, the motion, the blocks, the duration and step, the peak and the wall time."""
        info = self.info
        engine = " ".join(str(info[k]) for k in ("engine", "integrator") if k in info)
        fate = f"overturned at {self.time_of_overturn:.3g} s" if self.overturned else "standing"
        duration = float(self.t[-1]) if len(self.t) else 0.0
        return (f"Result({engine}, {info.get('excitation', 'no motion')}, {self.n_blocks} blocks, {duration:.4g} s at "
                f"dt {self.dt:.3g} s: peak |theta|/alpha {self.damage_ratio:.3g}, {fate}; "
                f"{info.get('run_time_s', float('nan')):.3g} s)")

    def _repr_html_(self) -> str:
        """A notebook's summary: the run's facts in a table, then each block's measures (:meth:`metrics`)."""
        info = self.info
        facts = {"engine": info.get("engine", ""), "integrator": info.get("integrator", ""),
                 "ground motion": info.get("excitation", ""), "blocks": self.n_blocks,
                 "duration, s": f"{float(self.t[-1]) if len(self.t) else 0.0:.4g}", "dt, s": f"{self.dt:.3g}",
                 "peak |theta|/alpha": f"{self.damage_ratio:.3g}",
                 "overturned": f"at {self.time_of_overturn:.4g} s" if self.overturned else "no",
                 "wall time, s": f"{info.get('run_time_s', float('nan')):.3g}"}
        rows = "".join(f"<tr><th style='text-align:left'>{k}</th><td>{html.escape(str(v))}</td></tr>"
                       for k, v in facts.items())
        return f"<table>{rows}</table>" + self.metrics().to_html(index=False, float_format=lambda v: f"{v:.4g}")

    def connector_frame(self) -> pd.DataFrame:
        """:attr:`connector_history` as a table: ``t`` (s) and per connector ``shear_N[name]``, ``tension_N[name]``,
        ``slip_m[name]``, ``opening_m[name]``; ValueError without connectors."""
        if self.connectors is None:
            raise ValueError("this run's scene has no connectors")
        columns = {"t": self.t}
        for k, name in enumerate(self.connectors.name):
            for d, quantity in enumerate(("shear_N", "tension_N", "slip_m", "opening_m")):
                columns[f"{quantity}[{name}]"] = self.connector_history[:, k, d]
        return pd.DataFrame(columns)

    @property
    def n_blocks(self) -> int:
        return len(self.names)

    def index(self, name: str) -> int:
        """Column of block ``name`` in x, y, theta."""
        try:
            return self.names.index(name)
        except ValueError:
            raise KeyError(f"no block named {name!r}; blocks are {', '.join(self.names)}") from None

    @property
    def relative_x(self) -> np.ndarray:
        """(n, n_blocks) horizontal position relative to the moving base, m."""
        return self.x - self.base_x[:, None]

    @property
    def residual_displacement(self) -> np.ndarray:
        """(n_blocks,) final minus initial horizontal position relative to the base, m."""
        rel = self.relative_x
        return rel[-1] - rel[0]

    @property
    def block_sliding(self) -> np.ndarray:
        """(n_blocks,) accumulated slip summed over each block's interfaces, m."""
        if self.interface_slip is None:
            return np.full(self.n_blocks, np.nan)
        total = np.zeros(self.n_blocks)
        for (a, b), s in self.interface_slip.items():
            for n in (a, b):
                if n in self.names:
                    total[self.names.index(n)] += s
        return total

    @property
    def total_sliding(self) -> float:
        """Accumulated relative slip summed over all interfaces, m."""
        if self.interface_slip is None:
            return float("nan")
        return float(sum(self.interface_slip.values()))

    @property
    def mean_rocking(self) -> np.ndarray:
        """(n_blocks,) time average of |theta| over the outputs, rad."""
        return np.mean(np.abs(self.theta), axis=0)

    @property
    def rocking(self) -> float:
        """Mean absolute rotation of all blocks over the run, rad (the thesis' 'rocking')."""
        return float(np.mean(np.abs(self.theta)))

    @property
    def overturned(self) -> bool:
        return bool(np.any(np.isfinite(self.overturn_time)))

    @property
    def time_of_overturn(self) -> float:
        """First overturn of any block, s (NaN if none)."""
        return float(np.nanmin(self.overturn_time)) if self.overturned else float("nan")

    @property
    def peak_displacement(self) -> np.ndarray:
        """(n_blocks,) peak |horizontal displacement| relative to the base from the start, over the outputs, m."""
        return np.max(np.abs(self.relative_x - self.relative_x[:1]), axis=0)

    def block_measures(self) -> dict:
        """The :data:`BLOCK_MEASURES`, each a (n_blocks,) array in scene order: peak |theta| (rad), peak and
        residual displacement and the slip at its joints (m), mean |theta| (rad), overturned (bool), when (s)."""
        return {"peak_abs_theta_rad": self.peak_theta, "peak_abs_displacement_m": self.peak_displacement,
                "residual_displacement_m": self.residual_displacement, "sliding_at_its_joints_m": self.block_sliding,
                "mean_abs_theta_rad": self.mean_rocking, "overturned": np.isfinite(self.overturn_time),
                "overturn_time_s": self.overturn_time}

    def metrics(self) -> pd.DataFrame:
        """One row per block: ``block`` and the :data:`BLOCK_MEASURES` (:meth:`block_measures`)."""
        return pd.DataFrame({"block": list(self.names), **self.block_measures()}, columns=["block", *BLOCK_MEASURES])

    def interface_metrics(self) -> pd.DataFrame:
        """One row per interface: ``interface`` ("drum1/drum2": its two bodies in the scene's order, "base" for the
        ground) and ``sliding_m``, the slip accumulated there over the run (m; 0 where it did not slide, NaN when
        the engine does not measure it).  The interfaces touching at the start come first, in the scene's order,
        then those that met later and slid; the column adds up to the total sliding."""
        slips = self.interface_slip
        pairs = list(dict.fromkeys([*map(tuple, self.interfaces), *(slips or {})]))
        return pd.DataFrame({"interface": [f"{a}/{b}" for a, b in pairs],
                             "sliding_m": [float("nan") if slips is None else float(slips.get(pair, 0.0))
                                           for pair in pairs]}, columns=["interface", "sliding_m"])

    def measures(self) -> dict:
        """The scene's :data:`SCENE_MEASURES`: peak |theta| of any block (rad), total sliding (m), mean rocking
        (rad), whether any block overturned and when first (s, NaN if none)."""
        return {"max_peak_abs_theta_rad": float(np.max(self.peak_theta)), "total_sliding_m": self.total_sliding,
                "mean_rocking_rad": self.rocking, "overturned": self.overturned,
                "overturn_time_s": self.time_of_overturn}

    def summary(self) -> dict:
        """The scene's measures (:meth:`measures`), the step and the run's facts."""
        return {**self.measures(), "dt_s": self.dt, **self.info}

    def to_frame(self) -> pd.DataFrame:
        """Tidy table: one row per output time and block (t, block, x, y, theta, x_rel, base_x, base_y)."""
        n, nb = self.x.shape
        return pd.DataFrame({
            "t": np.repeat(self.t, nb),
            "block": np.tile(np.array(self.names, dtype=object), n),
            "x": self.x.ravel(),
            "y": self.y.ravel(),
            "theta": self.theta.ravel(),
            "x_rel": self.relative_x.ravel(),
            "base_x": np.repeat(self.base_x, nb),
            "base_y": np.repeat(self.base_y, nb),
        })


#: the engine's connector slips and shear forces run along ``(-n_y, n_x)``; results give them along the interface's
#: tangent ``(n_y, -n_x)``, +x where the joint is level: the sign of each output column (shear force, tension, slip,
#: opening)
ALONG_TANGENT = np.array([-1.0, 1.0, -1.0, 1.0])


def connector_table(scene, model, connectors: np.ndarray, dt: float) -> pd.DataFrame | None:
    """:attr:`Result.connectors` of a run of ``scene`` (compiled as ``model``) whose connectors' state at its end is
    ``connectors`` (n_c, N_STATE, in the model's order; :mod:`._connector_law`), at step ``dt`` (s)."""
    if not scene.connectors:
        return None
    state = np.empty_like(connectors)
    state[model.connectors.order] = connectors
    law = np.empty_like(model.connectors.law)
    law[model.connectors.order] = model.connectors.law

    def time(column):
        steps = state[:, column]
        return np.where(steps >= 0, steps * dt, np.nan)

    return pd.DataFrame({
        "name": [c.name for c in scene.connectors], "kind": [c.kind.name for c in scene.connectors],
        "peak_shear_N": state[:, PEAK_SHEAR], "peak_tension_N": state[:, PEAK_TENSION],
        "yielded": state[:, YIELD_STEP] >= 0, "yield_time_s": time(YIELD_STEP),
        "ruptured": state[:, RUPTURE_STEP] >= 0, "rupture_time_s": time(RUPTURE_STEP),
        "pulled_out": (state[:, RUPTURE_STEP] >= 0) & (state[:, PEAK_TENSION] >= law[:, AXIAL_STRENGTH]),
        "residual_slip_m": 0.0 - state[:, PLASTIC_SLIP], "plastic_slip_m": state[:, ACCUMULATED],
        "slip_capacity_m": law[:, SLIP_CAPACITY]})


def connector_outputs(model, outputs: np.ndarray) -> np.ndarray:
    """:attr:`Result.connector_history` from a run's outputs (n, n_c, 4) in the model's order: in the scene's."""
    history = np.empty_like(outputs)
    history[:, model.connectors.order] = outputs * ALONG_TANGENT + 0.0  # + 0.0: no -0.0 in the files
    return history

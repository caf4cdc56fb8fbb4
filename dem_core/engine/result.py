"""What a run returns: time histories of every block, response measures, run facts.

The same type is returned by every engine, so results line up column by column.
Response measures follow docs/method.md section 3: rotation of each block,
residual displacement relative to the base, total sliding (accumulated
relative slip summed over interfaces), rocking (mean absolute rotation) and
overturning.
"""

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

#: the measures of each block, in :meth:`Result.metrics`' columns, a batch's ``<measure>[<block>]`` columns and the
#: command line's metrics.csv: peak |theta| over every step (rad), peak |horizontal displacement| relative to the
#: base over the outputs (m), residual displacement (m), the slip at the block's joints, below and above it, added
#: (m: each joint counts for both its blocks), mean |theta| over the outputs (rad), whether it overturned and when
#: (s, NaN if never)
BLOCK_MEASURES = ("peak_abs_theta_rad", "peak_abs_displacement_m", "residual_displacement_m", "sliding_at_its_joints_m",
                  "mean_abs_theta_rad", "overturned", "overturn_time_s")
#: the measures of the scene, in :meth:`Result.measures`, :meth:`Result.summary` and a batch's row
SCENE_MEASURES = ("max_peak_abs_theta_rad", "total_sliding_m", "mean_rocking_rad", "overturned", "overturn_time_s")


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

    def metrics(self) -> pd.DataFrame:
        """One row per block: ``block`` and the :data:`BLOCK_MEASURES`."""
        return pd.DataFrame({
            "block": list(self.names),
            "peak_abs_theta_rad": self.peak_theta,
            "peak_abs_displacement_m": self.peak_displacement,
            "residual_displacement_m": self.residual_displacement,
            "sliding_at_its_joints_m": self.block_sliding,
            "mean_abs_theta_rad": self.mean_rocking,
            "overturned": np.isfinite(self.overturn_time),
            "overturn_time_s": self.overturn_time,
        }, columns=["block", *BLOCK_MEASURES])

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

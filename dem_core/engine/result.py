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
    interface_slip : {(name_a, name_b): m} accumulated slip per interface that slid,
        or None when the engine does not measure it (sliding measures are then NaN).
    dt : s, the time step used; info : run facts (engine, stability limit,
        steps, compile and run wall times, ...).
    interfaces : ((name_a, name_b), ...) the interfaces touching at the start, whose slip is
        followed over time.
    slip_history : (n, n_interfaces) slip accumulated at each interface up to each output, m;
        None when the engine does not measure it.
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

    def metrics(self) -> pd.DataFrame:
        """One row per block: peak |theta|, residual displacement, sliding, rocking, overturn."""
        return pd.DataFrame({
            "block": list(self.names),
            "peak_abs_theta_rad": self.peak_theta,
            "residual_displacement_m": self.residual_displacement,
            "sliding_m": self.block_sliding,
            "mean_abs_theta_rad": self.mean_rocking,
            "overturned": np.isfinite(self.overturn_time),
            "overturn_time_s": self.overturn_time,
        })

    def summary(self) -> dict:
        """Scene-level measures: total sliding, rocking, overturn, and run facts."""
        return {
            "total_sliding_m": self.total_sliding,
            "mean_rocking_rad": self.rocking,
            "max_peak_abs_theta_rad": float(np.max(self.peak_theta)),
            "overturned": self.overturned,
            "overturn_time_s": self.time_of_overturn,
            "dt_s": self.dt,
            **self.info,
        }

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

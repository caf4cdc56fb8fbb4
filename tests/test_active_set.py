"""The direct solve of Moreau-Jean's contact problem by statuses (dem_core/engine/_active_set.py): its Delassus band
and its band solver against dense ones, its answer against Gauss-Seidel's converged one, and its work on a
column."""

import numpy as np

import dem_core
from dem_core import excitation, scenes
from dem_core.engine._active_set import HALF_BAND, delassus_band, half_band, responses, solve_band
from dem_core.engine._points import INC, N_COLUMNS, NX, NY, REF, RIX, RIY, RRX, RRY


def test_the_band_solver_solves_a_band_system():
    """A diagonally dominant band matrix of 40 unknowns and half-band 7: the solution of numpy's dense solver to
    1e-12."""
    rng = np.random.default_rng(3)
    size, width = 40, 7
    dense = np.zeros((size, size))
    for u in range(size):
        for v in range(max(0, u - width), min(size, u + width + 1)):
            dense[u, v] = rng.normal()
        dense[u, u] = 20.0
    rhs = rng.normal(size=size)
    band = np.zeros((size, 2 * HALF_BAND + 1))
    for u in range(size):
        for v in range(max(0, u - width), min(size, u + width + 1)):
            band[u, v - u + HALF_BAND] = dense[u, v]
    x = rhs.copy()
    assert solve_band(band, x, size, width)
    assert np.max(np.abs(x - np.linalg.solve(dense, rhs))) < 1e-12


def test_the_delassus_band_is_h_m_inverse_h_transpose():
    """A column of a fixed base and four drums, two points at each interface with random normals and lever arms:
    the band holds the dense ``W = H M^-1 H^T`` to rounding, and ``W`` has nothing outside the band."""
    rng = np.random.default_rng(5)
    n_blocks, n = 5, 8
    inv_mass = np.r_[0.0, 1.0 / rng.uniform(500.0, 2000.0, n_blocks - 1)]
    inv_inertia = np.r_[0.0, 1.0 / rng.uniform(100.0, 900.0, n_blocks - 1)]
    rows = np.zeros((n, N_COLUMNS))
    ints = np.zeros((n, 6), np.int64)
    for c in range(n):
        below, above = c // 2, c // 2 + 1
        ints[c, INC], ints[c, REF] = (above, below) if c % 4 < 2 else (below, above)
        angle = rng.uniform(0.0, 2.0 * np.pi)
        rows[c, NX], rows[c, NY] = np.cos(angle), np.sin(angle)
        rows[c, [RIX, RIY, RRX, RRY]] = rng.uniform(-0.6, 0.6, 4)
    jac, resp = np.empty((2 * n, 6)), np.empty((2 * n, 6))
    first, last = np.empty(n_blocks, np.int64), np.empty(n_blocks, np.int64)
    responses(rows, ints, inv_mass, inv_inertia, n, jac, resp)
    width = half_band(ints, inv_mass, n, first, last)
    band = np.full((2 * n, 2 * HALF_BAND + 1), np.nan)
    delassus_band(ints, n, width, first, last, jac, resp, band)
    h = np.zeros((2 * n, 3 * n_blocks))
    for u in range(2 * n):
        c = u // 2
        h[u, 3 * ints[c, INC]:3 * ints[c, INC] + 3] += jac[u, :3]
        h[u, 3 * ints[c, REF]:3 * ints[c, REF] + 3] += jac[u, 3:]
    dense = h @ np.diag(np.column_stack([inv_mass, inv_mass, inv_inertia]).ravel()) @ h.T
    scale = np.max(np.abs(dense))
    for u in range(2 * n):
        for v in range(2 * n):
            if abs(v - u) <= width:
                assert abs(band[u, v - u + HALF_BAND] - dense[u, v]) < 1e-13 * scale, (u, v)
            else:
                assert dense[u, v] == 0.0, (u, v)


def test_a_vanishing_pivot_is_refused():
    band = np.zeros((2, 2 * HALF_BAND + 1))
    band[1, HALF_BAND] = 1.0
    assert not solve_band(band, np.ones(2), 2, 1)


def column_run(drums, passes, sweeps, duration=3.0):
    run = dem_core.Simulation(scenes.column(drums), excitation.record("el_centro_1940", pga=2.5), duration,
                              output_dt=0.01, integrator="moreau")
    run.settings = run.settings.replace(status_passes=passes, max_sweeps=sweeps)
    run.advance()
    return run.result()


def test_the_direct_solve_gives_gauss_seidels_converged_answer():
    """A 3-drum column rocking under El Centro for 3 s: solved by statuses, and by Gauss-Seidel alone with sweeps
    enough to meet its tolerance every step, the drums' rotations agree to 1e-7 rad.  Both solves end within
    their tolerance, 1e-6 g dt (1e-8 m/s at dt = 1e-3 s) of the exact velocities, so over 3000 steps of 1e-3 s the
    positions part by at most 3e-8 m, 6e-8 rad over a drum's half-width of 0.5 m."""
    direct = column_run(3, 8, 50)
    swept = column_run(3, 0, 20000)
    assert swept.info["unconverged_steps"] == 0
    assert np.max(np.abs(direct.theta)) > 1e-3
    assert np.max(np.abs(direct.theta - swept.theta)) < 1e-7


def test_a_resting_column_takes_one_direct_solve_a_step():
    """The 8-drum column at rest: the statuses hold in one pass every step, so Gauss-Seidel never sweeps (alone it
    sweeps 50 times a step and does not meet its tolerance)."""
    result = dem_core.simulate(scenes.column(8), None, 1.0, integrator="moreau")
    info = result.info
    assert info["status_passes_per_step"] == 1.0 and info["status_fallbacks"] == 0
    assert info["sweeps_per_step"] == 0.0 and info["unconverged_steps"] == 0

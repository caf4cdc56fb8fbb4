"""The direct solve of Moreau-Jean's contact problem by statuses (dem_core/engine/_active_set.py): its statuses'
matrix and its block solver against dense ones, its answer against Gauss-Seidel's converged one, and its work on a
column."""

import numpy as np

import dem_core
from dem_core import excitation, scenes
from dem_core.engine._active_set import (BLOCK_REACH, OPEN, REGULARISATION, SLIDE_UP, STICK, first_coupled, half_band,
                                         responses, solve_blocks, statuses_matrix)
from dem_core.engine._points import (CONNECTOR, FRICTION, INC, N_COLUMNS, N_INTS, NX, NY, REF, RIX, RIY, RRX, RRY, WNN,
                                     WNT, WTT)


def block_system(rng, n, reach, symmetric):
    """A random system of ``n`` points' 2 x 2 blocks coupling points up to ``reach`` apart, block-diagonally
    dominant: its dense matrix, its envelope (every point's last coupled unknown) and its band storage."""
    size = 2 * n
    dense = np.zeros((size, size))
    for u in range(size):
        for v in range(size):
            if abs(u // 2 - v // 2) <= reach:
                dense[u, v] = rng.normal()
    if symmetric:
        dense = dense + dense.T
    dense += 20.0 * np.eye(size)
    end = np.array([min(2 * (u // 2 + reach) + 1, size - 1) for u in range(size)], np.int64)
    band = np.full((n, 2 * BLOCK_REACH + 1, 4), np.nan)
    for c in range(n):
        for d in range(max(0, c - reach), min(n, c + reach + 1)):
            band[c, BLOCK_REACH + d - c] = dense[2 * c:2 * c + 2, 2 * d:2 * d + 2].ravel()
    return dense, end, band


def test_the_block_solver_solves_a_band_system():
    """20 points of 2 x 2 blocks coupling points up to 3 apart, general and symmetric (the symmetric solve's
    elimination reads the diagonal blocks and those right of them alone), with every fourth point open (its unknowns given): numpy's dense solution of the
    same system (open rows the identity) to 1e-12."""
    rng = np.random.default_rng(3)
    n = 20
    for symmetric in (False, True):
        for opened in (False, True):
            dense, end, band = block_system(rng, n, 3, symmetric)
            status = np.full(n, STICK, np.int64)
            if opened:
                status[1::4] = OPEN
            rhs = rng.normal(size=2 * n)
            system = dense.copy()
            for c in np.flatnonzero(status == OPEN):
                system[2 * c:2 * c + 2] = 0.0
                system[2 * c, 2 * c] = system[2 * c + 1, 2 * c + 1] = 1.0
            x = rhs.copy()
            if symmetric:  # the blocks left of the diagonal are never read, but at an open point's columns
                for c in range(n):
                    for d in range(max(0, c - 3), c):
                        if status[d] != OPEN:
                            band[c, BLOCK_REACH + d - c] = np.nan
            assert solve_blocks(status, band, x, n, end, symmetric)
            assert np.max(np.abs(x - np.linalg.solve(system, rhs))) < 1e-12, (symmetric, opened)


def column_points(rng, n_blocks, n):
    """A column of a fixed base and ``n_blocks - 1`` drums, two points at each interface with random normals and
    lever arms: (inv_mass, inv_inertia, rows, ints)."""
    inv_mass = np.r_[0.0, 1.0 / rng.uniform(500.0, 2000.0, n_blocks - 1)]
    inv_inertia = np.r_[0.0, 1.0 / rng.uniform(100.0, 900.0, n_blocks - 1)]
    rows = np.zeros((n, N_COLUMNS))
    ints = np.zeros((n, N_INTS), np.int64)
    ints[:, CONNECTOR] = -1
    for c in range(n):
        below, above = c // 2, c // 2 + 1
        ints[c, INC], ints[c, REF] = (above, below) if c % 4 < 2 else (below, above)
        angle = rng.uniform(0.0, 2.0 * np.pi)
        rows[c, NX], rows[c, NY] = np.cos(angle), np.sin(angle)
        rows[c, [RIX, RIY, RRX, RRY]] = rng.uniform(-0.6, 0.6, 4)
        rows[c, FRICTION] = 0.7
    return inv_mass, inv_inertia, rows, ints


def test_the_statuses_matrix_is_h_m_inverse_h_transpose():
    """A column of a fixed base and four drums, two points at each interface: with every point sticking the band
    holds the dense ``W = H M^-1 H^T`` (its diagonal made compliant) to rounding within the envelope, ``W`` has
    nothing outside it, and each row holds its own block; a sliding point's tangential row is its sliding law's."""
    rng = np.random.default_rng(5)
    n_blocks, n = 5, 8
    inv_mass, inv_inertia, rows, ints = column_points(rng, n_blocks, n)
    jac, resp = np.empty((2 * n, 6)), np.empty((2 * n, 6))
    first, last, end = np.empty(n_blocks, np.int64), np.empty(n_blocks, np.int64), np.empty(2 * n, np.int64)
    responses(rows, ints, inv_mass, inv_inertia, n, jac, resp)
    half_band(ints, inv_mass, n, first, last, end)
    h = np.zeros((2 * n, 3 * n_blocks))
    for u in range(2 * n):
        c = u // 2
        h[u, 3 * ints[c, INC]:3 * ints[c, INC] + 3] += jac[u, :3]
        h[u, 3 * ints[c, REF]:3 * ints[c, REF] + 3] += jac[u, 3:]
    dense = h @ np.diag(np.column_stack([inv_mass, inv_mass, inv_inertia]).ravel()) @ h.T
    scale = np.max(np.abs(dense))
    status = np.full(n, STICK, np.int64)
    band = np.full((n, 2 * BLOCK_REACH + 1, 4), np.nan)
    statuses_matrix(status, rows, ints, inv_mass, n, end, 1.0, jac, resp, band)
    compliant = dense + REGULARISATION * np.diag(np.diag(dense))
    for u in range(2 * n):
        for v in range(2 * n):
            c, d = u // 2, v // 2
            if first_coupled(c, end) <= d <= end[u] // 2:
                stored = band[c, BLOCK_REACH + d - c, 2 * (u % 2) + v % 2]
                assert abs(stored - compliant[u, v]) < 1e-13 * scale, (u, v)
            else:
                assert dense[u, v] == 0.0, (u, v)
    for c in range(n):
        assert np.allclose(rows[c, [WNN, WNT, WTT]], dense[[2 * c, 2 * c, 2 * c + 1], [2 * c, 2 * c + 1, 2 * c + 1]],
                           rtol=1e-13, atol=0.0)
    status[3] = SLIDE_UP
    statuses_matrix(status, rows, ints, inv_mass, n, end, 1.0, jac, resp, band)
    for d in range(first_coupled(3, end), end[6] // 2 + 1):  # P_t - (-mu) P_n, the slope -sign mu
        assert list(band[3, BLOCK_REACH + d - 3, 2:]) == ([-0.7, 1.0] if d == 3 else [0.0, 0.0])


def test_a_vanishing_pivot_is_refused():
    """A point whose 2 x 2 block is singular."""
    band = np.zeros((1, 2 * BLOCK_REACH + 1, 4))
    band[0, BLOCK_REACH] = [1.0, 2.0, 2.0, 4.0]
    assert not solve_blocks(np.array([STICK]), band, np.ones(2), 1, np.array([1, 1]), False)


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

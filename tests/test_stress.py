"""The stability stress tests run each native engine name with its own integrator: ``dem`` is the explicit core,
whose automatic step and stability limit are what the contact-stiffness sweep and the time-step ladder map."""

import numpy as np
import pandas as pd
import pytest

from comparisons.cases import catalogue
from comparisons.harness import stress


@pytest.fixture(scope="module")
def sweep():
    return pd.DataFrame(stress.stiffness_sweep(quick=True, progress=False))


def test_the_explicit_cores_step_in_the_stiffness_sweep_falls_as_one_over_the_root_of_kn(sweep):
    """Central differences are stable below 2 / omega with omega proportional to sqrt(K_n): the automatic step
    times sqrt(K_n) is one constant over the sweep (a fixed-step integrator would give one step at every K_n)."""
    steps = sweep[sweep.metric == "dt_s"]
    kn = steps.setting.str.removeprefix("kn = ").astype(float).to_numpy()
    assert len(kn) >= 3 and kn.max() / kn.min() >= 1e4
    scaled = steps.value.to_numpy() * np.sqrt(kn)
    np.testing.assert_allclose(scaled, scaled[0], rtol=1e-9)


def test_a_stiff_contact_rocks_as_housners_rigid_block(sweep):
    """At K_n of 1e10 N/m^2 and more the contact is rigid enough for free rocking's analytical reference: each
    error within the band the free-rocking case gives the explicit core at its default K_n."""
    case = catalogue.case("free_rocking")
    stiff = sweep[(sweep.setting.str.removeprefix("kn = ").astype(float) >= 1e10) & (sweep.metric != "dt_s")]
    assert len(stiff) >= 4 and (stiff.status == "ok").all()
    for metric, value in zip(stiff.metric, stiff.value, strict=True):
        assert case.within_band(metric, "dem", value), (metric, value)


def test_central_differences_past_twice_the_stability_limit_stop_with_an_error():
    """At 2 and 3 x the limit the explicit core is unstable: each run must stop and say that energy grew."""
    ladder = pd.DataFrame(stress.time_step_ladder(quick=True, progress=False))
    dem = ladder[ladder.engine == "dem"]
    beyond = dem[dem.setting.isin(["2 x limit", "3 x limit"])]
    assert len(beyond) == 4
    assert (beyond.status == "stopped").all()
    assert beyond.message.str.contains("gained energy").all()
    assert (dem[dem.setting == "1 x limit"].status == "ok").all()

"""Running a scene under ground motion: ``simulate(scene, excitation, ...)`` and :class:`Simulation`.

This module joins what a run is given (:mod:`dem_core.inputs`: the scene, the ground motion) to the
engine (:mod:`dem_core.engine`).  The scene compiles into an immutable
:class:`~dem_core.engine.model.Model`, and after that the engine reads only the model and the run's
:class:`~dem_core.engine.settings.Settings`; the mutable :class:`~dem_core.engine.state.State` is advanced by the
compiled driver (:mod:`dem_core.engine._driver`) in chunks, and the outputs gathered into a
:class:`~dem_core.engine.result.Result`.  :class:`Simulation` holds them, so a run can be
advanced a piece at a time, pickled and continued.  The scene is kept for the blocks' names.
"""

import bisect
import contextlib
import hashlib
import math
import os
import signal
import sys
import threading
import time
import warnings
from typing import NamedTuple

import numba
import numpy as np
import pandas as pd

from .engine import _driver, stability
from .engine._checks import mechanical_energy
from .engine._ground import ground_at, ground_samples
from .engine.contact import LAWS
from .engine.model import Model, compile_model, interface_pairs
from .engine.model_arrays import ModelArrays, model_arrays
from .engine.residual import residual_state
from .engine.result import EVENT_MEASURES, Result, connector_outputs, connector_table
from .engine.scratch import make_scratch
from .engine.settings import (EXPLICIT, INTEGRATORS, LOAD_CELL_LEAD, MOREAU, MOREAU_ACTIVE_GAP, MOREAU_DT,
                              MOREAU_MAX_SUBSTEPS, MOREAU_MAX_SWEEPS, MOREAU_PROJECTION_SWEEPS, MOREAU_RESCUE_SWEEPS,
                              MOREAU_RETRIES, MOREAU_SHORTEST_SUBSTEP, MOREAU_SLOP, MOREAU_SOLVER_FAILURE,
                              MOREAU_SOLVER_TOLERANCE, MOREAU_STATUS_PASSES, MOREAU_THETA, MOREAU_TIME_FRACTION,
                              STATUS_ENERGY, STATUS_FELL_OFF, STATUS_FULL, STATUS_NONFINITE, STATUS_OK,
                              STATUS_OVERTURNED, STATUS_RUNAWAY, STATUS_UNCONVERGED, Settings, interface_stride,
                              make_settings)
from .engine.stacks import columns, find_stacks
from .engine.state import (
    LISTED,
    NARROW,
    OUTPUTS,
    PAIR_KEY,
    REBUILDS,
    RETIRED,
    SHORTENED,
    SOLVER_SWEEPS,
    STATUS_FALLBACKS,
    STATUS_PASSES,
    SUBSTEPPED,
    UNCONVERGED,
    Outputs,
    State,
    continued,
    empty_outputs,
    initial_state,
)
from .inputs.excitation import GroundMotion, MotionSequence, refuse_extreme, still, velocity_range
from .inputs.run_settings import (DEFAULT_SAFETY, DEFAULT_STEPS_PER_IMPACT, check_settings, check_step_fraction,
                                  check_step_options, integrator_code, seconds)
from .inputs.scene import Scene
from .inputs.text_files import shown

#: a block moving faster than this multiple of the fastest physical speed stops the run
SPEED_LIMIT_FACTOR = 10.0
#: energy gained beyond the ground's work, as a fraction of sum(m g R) plus the gross ground work, that stops the run
ENERGY_TOLERANCE = 0.05
#: with stop_at_overturn=False, while a block is overturned (past its critical angle or fallen), central differences
#: take each step in substeps no longer than this fraction of the automatic step for toppled blocks: a pile of fallen
#: blocks has more and stiffer contacts than the standing scene the stability limit is computed for (the 8-drum
#: column under El Centro at 10 m/s^2 goes through its collapse at a quarter of the step, not at a half)
COLLAPSE_STEP_FACTOR = 0.25
#: wall time (s) a chunk of steps aims at between progress updates, and the steps of a run's first chunk
CHUNK_SECONDS = 0.25
FIRST_CHUNK = 2000

_PACKAGE = os.path.dirname(os.path.abspath(__file__))


def warn_caller(message: str, category=RuntimeWarning) -> None:
    """``warnings.warn`` attributed to the first frame outside ``dem_core``: the user's line that started the
    run, whether through :func:`simulate`, :class:`Simulation` or an analysis."""
    frame, level = sys._getframe(1), 2
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(_PACKAGE + os.sep):
        frame, level = frame.f_back, level + 1
    warnings.warn(message, category, stacklevel=level)


class SimulationUnstable(RuntimeError):
    """A run lost stability, in the native core or in an engine of :mod:`adapters`; ``partial`` holds
    the result up to the last good output."""

    def __init__(self, message: str, partial: Result | None):
        super().__init__(message)
        self.partial = partial


def run_duration(excitation: GroundMotion, duration: float | None) -> float:
    """The duration (s) of a run: ``duration``, or the excitation's natural end when None (a record's,
    a pulse's); ``ValueError`` when there is neither or it is not positive and finite."""
    if duration is None:
        duration = excitation.end_time
        if not np.isfinite(duration) or duration <= 0:
            raise ValueError(f"give a duration: the excitation '{excitation.name}' has no natural end")
    return seconds("duration", duration)


def check_run_arguments(scene, excitation) -> GroundMotion:
    """The scene and the ground motion of a run checked at the door: ``TypeError`` naming the argument when
    either is of the wrong kind (a scene file's path or a dict where a :class:`~dem_core.Scene` is
    expected, a number where a ground motion is); returns the excitation, :func:`still` for None."""
    if not isinstance(scene, Scene):
        if isinstance(scene, (str, os.PathLike)):
            hint = (f"the path {str(scene)!r}: read a scene file with dem_core.inputs.scene_file.load(path), whose "
                    f".scene is the Scene")
        elif isinstance(scene, dict):
            hint = "a dict: build a Scene with dem_core.scenes (column, colonnade, ...) or dem_core.Scene(...)"
        else:
            hint = f"{type(scene).__name__} {shown(scene)}"
        raise TypeError(f"scene must be a dem_core.Scene, got {hint}")
    if excitation is None:
        return still()
    if not isinstance(excitation, GroundMotion):
        raise TypeError(f"excitation must be a ground motion (dem_core.excitation.record(...), harmonic(...), "
                        f"sine_pulse(...), ...) or None, got {type(excitation).__name__} {shown(excitation)}")
    return excitation


class SceneSetUp(NamedTuple):
    """What a run's set-up derives from its scene and step options alone (:func:`set_up_scene`), shared by runs of
    one scene under different motions (a batch's members): the ``scene`` and the ``options`` it was made with, the
    ``stacks``, the compiled ``model`` and its ``digest`` (:func:`model_digest`), its ``arrays`` (what the driver
    reads of it) and the ``columns``; for central differences the stability ``limit`` and the shortest ``impact``
    (s), the step ``dt`` (s) and the ``substeps`` a step past alpha is taken in (Moreau-Jean: inf, NaN, None, since
    its step depends on the motion, and 1)."""

    scene: object
    options: dict
    stacks: list
    model: Model
    digest: str
    arrays: ModelArrays
    columns: tuple
    limit: float
    impact: float
    dt: float | None
    substeps: int


def set_up_scene(scene, dt: float | None = None, *, safety: float = DEFAULT_SAFETY,
                 steps_per_impact: float = DEFAULT_STEPS_PER_IMPACT, step_fraction: float = 1.0,
                 stop_at_overturn: bool = True, enforce_stability_limit: bool = True,
                 integrator: str | None = None) -> SceneSetUp:
    """The :class:`SceneSetUp` of ``scene`` with the step options of :class:`Simulation` (the same names and
    defaults); ``ValueError`` naming a wrong option (Moreau-Jean's ``dt`` is checked with the motion, by
    :func:`moreau_time_step`), and the warning of a step beyond the stability limit."""
    check_step_options(safety, steps_per_impact, step_fraction)
    integrator = integrator_for(scene, integrator)
    options = dict(dt=dt, safety=safety, steps_per_impact=steps_per_impact, step_fraction=step_fraction,
                   stop_at_overturn=stop_at_overturn, enforce_stability_limit=enforce_stability_limit,
                   integrator=integrator)
    if integrator_code(integrator) == MOREAU and scene.contact.law != "corner":
        raise ValueError(f"the Moreau-Jean integrator works on the corner law's contact points; the scene's "
                         f"contact law is {scene.contact.law!r}")
    given = scene.contact.explicit_restitution
    if integrator == "explicit" and given is not None and 0.0 < scene.contact.impact_restitution < given:
        raise ValueError(f"restitution {scene.contact.impact_restitution:g}: the explicit core's dashpots give at "
                         f"least {given:g} (docs/method.md 1.3); ask 0 for that, or give a damping_ratio, or run "
                         f"Moreau-Jean, which gives any restitution")
    stacks = find_stacks(scene)
    model = compile_model(scene, stacks)
    if integrator_code(integrator) == MOREAU:
        return SceneSetUp(scene, options, stacks, model, model_digest(model), model_arrays(model),
                          columns(scene, stacks), math.inf, math.nan, None, 1)
    limit = stability.stability_limit(model)
    impact = stability.impact_duration(model)
    dt = _time_step(model, dt, limit, impact, safety, steps_per_impact, step_fraction, enforce_stability_limit)
    if dt > limit:
        warn_caller(f"dt = {dt:.4g} s is {dt / limit:.2f} times the stability limit {limit:.4g} s "
                    f"(enforce_stability_limit=False): the result says so in info['beyond_stability_limit']")
    substeps = 1
    if not stop_at_overturn:
        collapse = COLLAPSE_STEP_FACTOR * _time_step(model, None, stability.stability_limit(model, toppled=True),
                                                     impact, safety, steps_per_impact, step_fraction, True)
        substeps = max(1, math.ceil(dt / collapse - 1e-9))
    return SceneSetUp(scene, options, stacks, model, model_digest(model), model_arrays(model), columns(scene, stacks),
                      limit, impact, dt, substeps)


class Simulation:
    """One run of a scene: the compiled model, the state, the ground motion and the outputs so far.

    ``Simulation(scene, excitation, duration, ...)`` takes the arguments of :func:`simulate`, and
    ``scene_set_up``, the scene's :func:`set_up_scene` with the same step options, where runs of one scene share
    it; :meth:`advance` takes steps (all that remain by default), :meth:`result` gathers what was
    computed.  ``status`` is None while the run can go on, else why it ended.  ``outputs``, the
    :class:`~dem_core.engine.state.Outputs` of ``output_rows`` rows, is made at the first step (None until then:
    the members of a GPU batch write theirs into the batch's arrays), and the scratch with it.

    Under a sequence of ground motions (:func:`~dem_core.inputs.excitation.sequence`) event ``e`` starts at step
    ``event_starts[e]`` (:meth:`~dem_core.inputs.excitation.MotionSequence.event_steps`) and no call of the
    compiled driver spans an event's start: a chunk within event ``e`` reads the samples a run of that event alone
    (``event_motions[e]``, its motion followed by its rest) reads at its own steps, so that the run is, bit for bit,
    the run of its first event followed by runs each going on from the one before (``start=``).  At each event's
    end ``event_rows`` gains its residual state (:attr:`Result.events`).
    """

    def __init__(self, scene, excitation: GroundMotion | None = None, duration: float | None = None,
                 dt: float | None = None, output_dt: float | None = None, *, ground_motion: str = "inertial",
                 safety: float = DEFAULT_SAFETY, steps_per_impact: float = DEFAULT_STEPS_PER_IMPACT,
                 step_fraction: float = 1.0, stop_at_overturn: bool = True, enforce_stability_limit: bool = True,
                 parallel: bool = False, integrator: str | None = None, theta: float = MOREAU_THETA,
                 scene_set_up: SceneSetUp | None = None, start: Result | None = None):
        excitation = check_run_arguments(scene, excitation)
        check_settings(duration=duration, dt=dt, output_dt=output_dt, ground_motion=ground_motion, safety=safety,
                       steps_per_impact=steps_per_impact, step_fraction=step_fraction, integrator=integrator,
                       theta=theta)
        integrator = integrator_for(scene, integrator)
        step_options = dict(dt=dt, safety=safety, steps_per_impact=steps_per_impact, step_fraction=step_fraction,
                            stop_at_overturn=stop_at_overturn, enforce_stability_limit=enforce_stability_limit,
                            integrator=integrator)
        given_duration, duration = duration, run_duration(excitation, duration)
        output_dt = 0.01 if output_dt is None else seconds("output_dt", output_dt)
        refuse_extreme(excitation, duration)
        if scene_set_up is None:
            scene_set_up = set_up_scene(scene, **step_options)
        elif scene_set_up.scene is not scene or scene_set_up.options != step_options:
            raise ValueError("scene_set_up was made for another scene or other step options than this run's")
        self.scene, self.ground_motion = scene, ground_motion
        self.model: Model = scene_set_up.model
        self.model_digest = scene_set_up.digest
        if start is not None:
            _check_start(start, scene, self.model_digest, integrator)
        self.stacks = scene_set_up.stacks
        self.columns = scene_set_up.columns
        self.integrator = integrator
        code = integrator_code(integrator)
        self.limit, self.impact = scene_set_up.limit, scene_set_up.impact
        auto_dt = dt is None
        substeps = scene_set_up.substeps
        if code == MOREAU:
            dt = moreau_time_step(self.model, excitation, dt, step_fraction)
        else:
            dt = scene_set_up.dt
        self.excitation, self.event_starts, self.event_motions, end = _events_on_steps(excitation, dt)
        n_steps = end if end is not None and given_duration is None else math.ceil(duration / dt - 1e-9)
        stride = max(1, round(output_dt / dt))
        n_out = n_steps // stride + 2
        _check_run_size(self.model, scene.block_names, duration, dt, auto_dt, n_steps, n_out, self.limit,
                        self.impact)
        self.arrays: ModelArrays = scene_set_up.arrays
        self.settings: Settings = run_settings(self.model, code, dt, n_steps, stride,
                                               _speed_limit(self.model, excitation, duration), stop_at_overturn,
                                               ground_motion == "inertial", substeps, theta)
        self.state: State = self._first_state(start)
        self.start_pos = self.state.pos.copy()
        self.event_rows: list = []
        self.threaded = bool(parallel and code == EXPLICIT and numba.get_num_threads() > 1)
        self.output_rows = n_out
        self.outputs: Outputs | None = None
        self.scratch = None
        self.status, self.stopped_by = None, None
        self.compile_time = _ensure_compiled(self)
        self.run_time = 0.0

    def _first_state(self, start: Result | None) -> State:
        """The state the run starts from, its energy ledger started from the blocks' energy then: the scene's, the
        blocks at rest relative to the ground (moving with it under a moving base, at their velocities' time), or
        ``start``'s final state with the bodies moved with the base to where this run's ground puts it
        (:func:`move_with_base`)."""
        if start is None:
            state = initial_state(self.model)
            if not self.inertial:
                at = -self.ground_lead * self.dt
                state.vel[1:, :2] = np.array(self.excitation.velocity(np.array([at])))[:, 0]
        else:
            state = continued(start.final_state)
            move_with_base(state, self._samples(0, 0), self.settings)
        state.ledger[0] = self._energy(state)
        return state

    def _energy(self, state: State) -> float:
        """J, the mechanical energy of the blocks at ``state``."""
        b = self.model.bodies
        return mechanical_energy(state.pos, state.vel, b.mass, b.inv_inertia, self.model.gravity)

    def __getstate__(self) -> dict:
        # the scratch is made again where the run goes on
        return {**self.__dict__, "scratch": None}

    @property
    def kernel(self):
        """The compiled driver this run steps by."""
        return _driver.drive_threaded if self.threaded else _driver.drive_serial

    @property
    def dt(self) -> float:
        return self.settings.dt

    @property
    def step(self) -> int:
        return self.state.step

    def advance(self, steps: int | None = None, progress=None) -> bool:
        """Take ``steps`` steps (all that remain if None) unless the run ends first, in chunks of about
        ``CHUNK_SECONDS`` of wall time; ``progress`` is called with (steps done, steps in all) before the first
        chunk and after each.  Returns whether the run can go on.  An unstable run ends with ``status`` set and
        nothing raised (see :meth:`result`); Ctrl-C is taken after the chunk it came in, the state whole."""
        last = self.settings.last_step
        goal = last if steps is None else min(self.step + steps, last)
        if progress is not None:
            progress(self.step, last)
        chunk = FIRST_CHUNK
        while self.status is None and self.step < goal:
            started = time.perf_counter()
            self._take(min(chunk, goal - self.step, self._event_end() - self.step))
            if progress is not None:
                progress(self.step, last)
            chunk = next_chunk(chunk, time.perf_counter() - started)
        return self.status is None

    def _take(self, steps: int) -> None:
        """One call of the compiled driver for ``steps`` steps (taken again, from a copy of the state, with a
        store that filled doubled), its status kept; Ctrl-C is held back until it returns."""
        samples = self._samples(self.step, steps)
        started = time.perf_counter()
        with _interrupt_after_the_kernel() as interrupted:
            while True:
                kept = self.state.copy()
                status, i, j = self.kernel(self.arrays, self.settings, self.state, self._outputs(), self._scratch(),
                                           samples, steps)
                if status != STATUS_FULL:
                    break
                self.state, self.scratch = kept.grown(i), None
        self.run_time += time.perf_counter() - started
        if status != STATUS_OK:
            self.status, self.stopped_by = status, (i, j)
        elif self.step >= self.settings.last_step:
            self.status = STATUS_OK
        self._pass_event_end()
        if interrupted:
            raise KeyboardInterrupt  # after the chunk: the state is whole and the run can go on

    def empty_outputs(self, rows: int) -> Outputs:
        """Blank :class:`~dem_core.engine.state.Outputs` of ``rows`` rows for this run's bodies, interfaces and
        connectors."""
        return empty_outputs(rows, len(self.model.bodies.mass), len(self.model.interface_keys),
                             len(self.model.connectors.law))

    def _outputs(self) -> Outputs:
        if self.outputs is None:
            self.outputs = self.empty_outputs(self.output_rows)
        return self.outputs

    def _scratch(self):
        if self.scratch is None:
            self.scratch = self.new_scratch()
        return self.scratch

    def new_scratch(self):
        """A :class:`~dem_core.engine.scratch.Scratch` for this run's model, store and integrator."""
        return make_scratch(self.arrays, self.state.capacities[0], (self.settings.integrator,),
                            (self.settings.contact_law,))

    def _samples(self, first: int, steps: int) -> np.ndarray:
        """(4, steps + 2): the ground motion's samples for this run's steps ``first`` .. ``first + steps``
        (:func:`dem_core.engine._ground.ground_samples`), all within the event that step ``first`` is in: that event's
        motion at its own steps."""
        event = self._event(first)
        return ground_samples(self.event_motions[event], self.dt, self.inertial, self.ground_lead,
                              first - int(self.event_starts[event]), steps)

    def _event(self, step: int) -> int:
        """The event that ``step`` is in (0 under a single motion)."""
        return bisect.bisect_right(self.event_starts, step) - 1

    def _event_end(self) -> int:
        """The step at which the event of the present step ends: the next one's start, or the run's last step."""
        following = self._event(self.step) + 1
        return int(self.event_starts[following]) if following < len(self.event_starts) else self.settings.last_step

    def _pass_event_end(self) -> None:
        """Under a sequence, at the end of an event (the next one's start, or where the run ended within it): its row
        of :attr:`event_rows`, and while the run goes on the bodies moved with the base to where the next event's
        ground puts it (:func:`move_with_base`; nothing moves under the inertial load), the energy ledger following."""
        if not isinstance(self.excitation, MotionSequence):
            return
        event, closed = self._event(self.step), len(self.event_rows)
        if closed == event - 1 and self.step == self.event_starts[event]:
            self.event_rows.append(self._event_row(event - 1))
            if self.status is None:
                before = self._energy(self.state)
                move_with_base(self.state, self._samples(self.step, 0), self.settings)
                self.state.ledger[0] += self._energy(self.state) - before
        elif closed == event and self.status is not None and self.step > self.event_starts[event]:
            self.event_rows.append(self._event_row(event))

    def _event_row(self, event: int) -> dict:
        """Event ``event``'s row of :attr:`Result.events`, at the present step."""
        bodies = self.scene.bodies
        dislocation, tilt = EVENT_MEASURES
        found = residual_state(self.model, self.columns, self.scene.block_names, self.start_pos, self.state.pos)
        return {"event": event + 1, "motion": self.excitation.events[event].motion.name,
                "start_s": float(self.event_starts[event] * self.dt), "end_s": self.step * self.dt,
                **{f"{dislocation}[{bodies[a].name}/{bodies[b].name}]": float(d)
                   for (a, b), d in zip(interface_pairs(self.model), found.dislocation)},
                **{f"{tilt}[{label}]": value for label, value in found.tilt.items()}}

    @property
    def inertial(self) -> bool:
        """Whether the blocks move relative to the ground under its inertial load (else the base moves)."""
        return self.ground_motion == "inertial"

    @property
    def ground_lead(self) -> float:
        """Steps by which a step's load cell, and a moving base's velocity, start before it (the integrator's
        ``LOAD_CELL_LEAD``)."""
        return LOAD_CELL_LEAD[self.settings.integrator]

    def result(self) -> Result:
        """The run so far as a :class:`Result`; raises :class:`SimulationUnstable`, carrying that
        result, if the run lost stability."""
        scene, dt, state = self.scene, self.dt, self.state
        counters = state.counters
        written = int(counters[OUTPUTS])
        outputs = self.empty_outputs(0) if self.outputs is None else self.outputs
        out_t = outputs.step[:written] * dt
        out = outputs.pos[:written]
        x, y, ground_x, ground_y = self._in_fixed_frame(out_t, out)
        theta = out[:, 1:, 2]
        step = self.step
        bodies = scene.bodies
        info = {
            "engine": "dem",
            "integrator": self.integrator,
            "contact_law": LAWS[self.model.law.law],
            "kn": self.model.law.kn,
            "stability_limit_s": self.limit,
            "impact_duration_s": self.impact,
            "dt_over_limit": dt / self.limit,
            "steps": step,
            "narrow_phase_per_step": int(counters[NARROW]) / max(step, 1),
            "pair_lists": int(counters[REBUILDS]),
            "ground_motion": self.ground_motion,
            "excitation": self.excitation.name,
            "compile_time_s": self.compile_time,
            "run_time_s": self.run_time,
        }
        if self.settings.integrator == MOREAU:
            for key in ("kn", "stability_limit_s", "impact_duration_s", "dt_over_limit"):
                info.pop(key)
            info["theta"] = self.settings.theta
            info["sweeps_per_step"] = int(counters[SOLVER_SWEEPS]) / max(step, 1)
            info["unconverged_steps"] = int(counters[UNCONVERGED])
            info["status_passes_per_step"] = int(counters[STATUS_PASSES]) / max(step, 1)
            info["status_fallbacks"] = int(counters[STATUS_FALLBACKS])
            info["shortened_parts"] = int(counters[SHORTENED])
            info["restitution"] = self.model.law.restitution
        else:
            info["collapse_substeps"] = self.settings.substeps
            info["restitution"] = scene.contact.explicit_restitution
            info["substepped_steps"] = int(counters[SUBSTEPPED])
        if dt > self.limit:
            info["beyond_stability_limit"] = (f"dt = {dt:.4g} s is {dt / self.limit:.2f} times the stability limit "
                                              f"{self.limit:.4g} s: the scheme is unstable there and the result may be "
                                              f"wrong without any check noticing")
        stack_step = state.stack_step
        tipped = [k for k in range(len(self.stacks)) if 0 <= stack_step[k] <= step]
        if tipped:
            info["tipped_stacks"] = {_stack_label(scene, self.stacks[k]): float(stack_step[k] * dt) for k in tipped}
        i = self.stopped_by[0] if self.stopped_by else 0
        if self.status == STATUS_OVERTURNED:
            whole = [k for k in tipped if stack_step[k] == step and self.stacks[k].blocks[0] == i - 1]
            what = (f"the stack {_stack_label(scene, self.stacks[whole[0]])} tipped past its base"
                    if whole else f"block '{bodies[i].name}' overturned")
            info["ended_at_overturn"] = f"{what} at t = {step * dt:.6g} s"
        overturn_step = state.overturn_step[1:]
        over_t = np.where(overturn_step >= 0, overturn_step * dt, np.nan)
        pairs = interface_pairs(self.model)
        lost = self._stop_message(out_t) if self.status not in (None, STATUS_OK, STATUS_OVERTURNED) else ""
        result = Result(out_t, x, y, theta, ground_x, ground_y, tuple(scene.block_names),
                        state.peak_theta[1:].copy(), over_t, self._interface_slip(), dt, info,
                        interfaces=tuple((bodies[a].name, bodies[b].name) for a, b in pairs),
                        slip_history=outputs.slip[:written].copy(),
                        critical_angle=self.model.bodies.critical_angle[1:].copy(),
                        columns=self.columns, final_state=state.copy(), model_digest=self.model_digest,
                        lost_stability=lost,
                        events=(pd.DataFrame(self.event_rows) if isinstance(self.excitation, MotionSequence)
                                else None),
                        connectors=connector_table(scene, self.model, state.connectors, dt),
                        connector_history=(connector_outputs(self.model, outputs.connectors[:written])
                                           if scene.connectors else None))
        if lost:
            raise SimulationUnstable(lost, result)
        return result

    def _in_fixed_frame(self, out_t: np.ndarray, out: np.ndarray) -> tuple:
        """``(x, y, ground_x, ground_y)`` (n, n_blocks) and (n,) m: the blocks' centres at the outputs ``out``
        (n, nb, 3), times ``out_t`` (s), in the fixed frame, and the ground's displacement.  Under the inertial load
        the kernel moves the blocks relative to the ground, whose displacement is added back; under a moving base the
        base is where the motion puts it, or under a sequence where its event's own motion does (each event's base
        starts where its motion starts, :func:`move_with_base`): the blocks are then placed relative to it on the
        sequence's ground."""
        x, y = out[:, 1:, 0], out[:, 1:, 1]
        base = out[:, 0, :2] - self.model.bodies.centroid0[0]
        if not self.inertial and not isinstance(self.excitation, MotionSequence):
            return x, y, base[:, 0], base[:, 1]
        ground_x, ground_y = self.excitation.displacement(out_t)
        if not self.inertial:
            x, y = x - base[:, :1], y - base[:, 1:]
        return x + ground_x[:, None], y + ground_y[:, None], ground_x, ground_y

    def _interface_slip(self) -> dict:
        """{(name_a, name_b): m} of every pair that slid: recorded interfaces, pairs listed now, and
        pairs that left the list."""
        bodies = self.scene.bodies
        n = len(bodies)
        total = {}
        state = self.state
        for (a, b), s in zip(interface_pairs(self.model), state.interface_slip):
            total[a * n + b] = float(s)
        listed, retired = state.counters[LISTED], state.counters[RETIRED]
        for key, s in zip(state.pair_ids[:listed, PAIR_KEY], state.pair_slip[:listed]):
            total[int(key)] = total.get(int(key), 0.0) + float(s)
        for key, s in zip(state.retired_key[:retired], state.retired_slip[:retired]):
            total[int(key)] = total.get(int(key), 0.0) + float(s)
        return {(bodies[k // n].name, bodies[k % n].name): s for k, s in sorted(total.items()) if s > 0}

    def _stop_message(self, out_t) -> str:
        scene, status, dt, step = self.scene, self.status, self.dt, self.step
        bodies = scene.bodies
        i, j = self.stopped_by
        if status == STATUS_NONFINITE:
            what = f"the state of block '{bodies[i].name}' became non-finite"
        elif status == STATUS_RUNAWAY:
            what = (f"block '{bodies[i].name}' moved faster than {self.settings.speed_limit:.3g} m/s relative to "
                    f"the ground, {SPEED_LIMIT_FACTOR:g} times the fastest speed its fall and the ground motion can "
                    f"give")
        elif status == STATUS_FELL_OFF:
            what = f"block '{bodies[i].name}' fell off the edge of the base; make the base wider (base_width)"
        elif status == STATUS_ENERGY:
            what = (f"the blocks gained energy that neither gravity nor the ground supplied "
                    f"(more than {ENERGY_TOLERANCE:.0%} of the energy scale)")
        elif status == STATUS_UNCONVERGED:
            what = (f"the contact solve did not converge at block '{bodies[i].name}': after "
                    f"{self.settings.max_sweeps + self.settings.rescue_sweeps} Gauss-Seidel sweeps a velocity "
                    f"still changed by more than {self.settings.solver_failure:g} g dt a sweep, with the step's part "
                    f"taken again at down to 1/{2 ** MOREAU_RETRIES} of its length")
        elif LAWS[self.model.law.law] == "corner":
            what = (f"blocks '{bodies[i].name}' and '{bodies[j].name}' interpenetrate by more than "
                    f"{self.model.law.max_penetration:.0%} of the smaller block's size")
        else:
            what = (f"blocks '{bodies[i].name}' and '{bodies[j].name}' overlap by more than "
                    f"{self.model.law.max_penetration:.0%} of the smaller block's area")
        if status == STATUS_FELL_OFF:
            advice = "nothing after this time is physical"
        elif self.settings.integrator == MOREAU:
            advice = f"reduce dt below {dt:.4g} s"
        else:
            advice = f"reduce dt below {dt:.4g} s or check the contact parameters (kn = {self.model.law.kn:.3g})"
        last = out_t[-1] if len(out_t) else 0.0
        return (f"simulation stopped at t = {step * dt:.6g} s (step {step}, dt = {dt:.4g} s): {what}; {advice}. "
                f"The result up to t = {last:.6g} s is in this error's .partial")


def _events_on_steps(excitation: GroundMotion, dt: float) -> tuple:
    """``(the motion as the run takes it, (E,) int64 the step each event starts at, the E events' motions each with
    its rest, the step the last event's rest ends at)``: a sequence with its events on whole steps of ``dt`` (s)
    (:meth:`~dem_core.inputs.excitation.MotionSequence.on_steps`), or a single motion as one event and None."""
    if not isinstance(excitation, MotionSequence):
        return excitation, np.zeros(1, np.int64), (excitation,), None
    steps = excitation.event_steps(dt)
    on_steps = excitation.on_steps(dt)
    return on_steps, steps[:-1], tuple(event.alone for event in on_steps.events), int(steps[-1])


def move_with_base(state: State, samples: np.ndarray, settings: Settings) -> None:
    """Move every body of ``state`` with the base, from where the base is to where the first column of ``samples``
    (:func:`~dem_core.engine._ground.ground_samples` from a motion's first step) places it, and change their
    velocities by the base's change of velocity: the blocks keep their places and motions relative to the base.  Under
    the inertial load, whose base stays put, nothing changes."""
    window = np.zeros((6, 2))
    ground_at(samples, 0, settings.scale, settings.start_x, settings.start_y, settings.dt, settings.inertial == 1,
              window, 0)
    shift = window[2:4, 0] - state.pos[0, :2]
    kick = window[4:6, 0] - state.vel[0, :2]
    if np.any(shift != 0.0) or np.any(kick != 0.0):
        state.pos[:, :2] += shift
        state.built_at[:, :2] += shift
        state.vel[:, :2] += kick


def _check_start(start, scene, digest: str, integrator: str) -> None:
    """``TypeError``/``ValueError`` in one line where a run of ``scene`` (its model's ``digest``) under ``integrator``
    cannot go on from ``start``: not a result, a result without the native engine's final state, of a run that lost
    stability or stopped at an overturn, of another scene or another integrator."""
    if not isinstance(start, Result):
        raise TypeError(f"start must be a Result of dem_core.simulate, got {type(start).__name__} {shown(start)}")
    if start.final_state is None:
        raise ValueError(f"start: the result carries no final state (engine {start.info.get('engine', '?')!r}): only "
                         f"the native engine's results (dem_core.simulate) can be gone on from")
    if start.lost_stability:
        raise ValueError(f"start: the result's run lost stability, so its final state is not one to go on from: "
                         f"{start.lost_stability}")
    ended = start.info.get("ended_at_overturn", start.info.get("stopped"))  # "stopped": its older name
    if ended is not None:
        raise ValueError(f"start: the result's run stopped when {ended}: run it with stop_at_overturn=False to go on "
                         f"through the collapse")
    if tuple(start.names) != tuple(scene.block_names):
        raise ValueError(f"start: the result is of a scene with blocks {', '.join(start.names)}, this scene's are "
                         f"{', '.join(scene.block_names)}")
    if start.model_digest != digest:
        raise ValueError("start: the result is of another scene with the same block names (its compiled model, "
                         "geometry, masses, contact or friction, differs from this scene's)")
    if start.info.get("integrator") != integrator:
        raise ValueError(f"start: the result ran integrator {start.info.get('integrator')!r}, this run "
                         f"{integrator!r}: a run goes on from a state of its own integrator")


def model_digest(model: Model) -> str:
    """Hex digest of every array and number of a compiled ``model``: equal for the models of scenes that step alike."""
    digest = hashlib.sha256()
    parts = [model]
    while parts:
        part = parts.pop()
        if isinstance(part, tuple):
            parts.extend(reversed(part))
        elif part is None or isinstance(part, str):
            digest.update(repr(part).encode())
        else:
            array = np.ascontiguousarray(part)
            digest.update(f"{array.dtype.str}{array.shape}".encode())
            digest.update(array.tobytes())
    return digest.hexdigest()[:16]


def next_chunk(steps: int, seconds: float) -> int:
    """The steps of the next chunk after one of ``steps`` that took ``seconds``: about ``CHUNK_SECONDS`` of wall time
    at that pace, at least 100 steps and at most 50 times the last chunk."""
    return int(min(max(steps * CHUNK_SECONDS / max(seconds, 1e-6), 100), 50 * steps))


def simulate(scene, excitation: GroundMotion | None = None, duration: float | None = None,
             dt: float | None = None, output_dt: float | None = None, *,
             ground_motion: str = "inertial", safety: float = DEFAULT_SAFETY,
             steps_per_impact: float = DEFAULT_STEPS_PER_IMPACT, step_fraction: float = 1.0,
             stop_at_overturn: bool = True, enforce_stability_limit: bool = True, progress=None,
             parallel: bool = False, integrator: str | None = None, theta: float = MOREAU_THETA,
             start: Result | None = None) -> Result:
    """Simulate ``scene`` under ``excitation`` with the native DEM.

    scene : :class:`~dem_core.inputs.scene.Scene` (its ``contact.law`` chooses the contact law).
    excitation : :class:`~dem_core.inputs.excitation.GroundMotion` (None: no ground motion); a sequence of motions
        (:func:`~dem_core.inputs.excitation.sequence`) runs event by event, each event's residual state in the
        result's ``events`` (:class:`Simulation`).
    duration : s; default the excitation's natural end (records, pulses; a sequence's last rest).
    dt : s; None picks the integrator's: Moreau-Jean's :func:`moreau_time_step` (1e-3 s unless the motion or the
        scene is faster), and for the explicit core the smaller of ``safety`` x the stability limit
        (:func:`dem_core.engine.stability.stability_limit`) and the shortest impact
        over ``steps_per_impact`` (:func:`dem_core.engine.stability.impact_duration`).
        An explicit dt above the limit is refused.
    step_fraction : with dt None, the automatic step is multiplied by this (in (0, 1]; a convergence
        study's ``auto/N`` is ``1/N``), without compiling the scene a second time as
        ``dt=automatic_time_step(scene) / N`` would.
    output_dt : s between outputs (rounded to a whole number of steps; the
        final state is always an output); default 0.01 s.
    ground_motion : ``"inertial"`` (base fixed, load ``-m a_g`` on every block,
        docs/method.md section 2) or ``"moving_base"`` (the base follows u_g, v_g).
        Either way positions are reported in the fixed frame, with
        ``base_x`` the ground displacement.
    stop_at_overturn : end the run when a block first overturns (passes its
        critical angle or falls half its size) or a column tips past its base; the result then
        ends at that time and ``info["ended_at_overturn"]`` says why.  With False the run goes on
        through the collapse.  Central differences then take every step during which a block is
        overturned in ``info["collapse_substeps"]`` substeps, each short enough for blocks lying on
        their long sides (see :func:`dem_core.engine.stability.stability_limit`) and for piles of
        fallen blocks (``COLLAPSE_STEP_FACTOR``); ``info["substepped_steps"]`` counts them.
    enforce_stability_limit : refuse an explicit dt above the stability limit.
        Only for stress tests that study what happens past it
        (``python -m comparisons stability-probe``); such a result says so in ``info``.
    progress : None, or a callable ``(steps done, steps in all)`` called once the run is set up (its
        engine compiled) and every quarter second or so after (the command line passes a progress bar).
    parallel : spread the contacts over numba's threads (``NUMBA_NUM_THREADS``).  Off by default: on
        few cores the threads' overhead can outweigh the gain (docs/performance.md), so measure yours
        before turning it on.  The trajectory is the serial kernel's, bit for bit.  Explicit integrator only.
    integrator : ``"moreau"`` (Moreau-Jean time stepping at the velocity level on the corner law's points, rigid
        contacts with no stiffness and no stability limit, docs/method.md 1.8) or ``"explicit"`` (central
        differences on the contact springs, docs/method.md 1.6); None: :func:`integrator_for`'s, Moreau-Jean
        unless the scene's law is the overlap-area law.  With ``"moreau"`` ``safety``, ``steps_per_impact`` and
        ``enforce_stability_limit`` do not apply, and the contact law must be the corner law.
    theta : Moreau-Jean's weight of the new velocity in the position update, in [0.5, 1] (``MOREAU_THETA``).
    start : a :class:`Result` of this scene under the same integrator to go on from: the run starts from its final
        state (:attr:`Result.final_state`: positions, velocities, the listed pairs with their contact memory and
        impulses), the blocks moved with the base to where this run's ground puts it (under a moving base), and
        reports its own time from 0 and its own measures.  Under the inertial load a run going on from a run of a
        motion and its rest is, bit for bit, the rest of a run of the two as a sequence.  Refused in one line: a
        result without a final state (another engine's), of another scene (its block names or its compiled model
        differ) or integrator, or of a run that lost stability or stopped at an overturn.

    Raises ``ValueError`` for bad arguments (a dt above the stability limit, a ground motion peaking
    above :data:`~dem_core.inputs.excitation.EXTREME_PGA_G` among them) and :class:`SimulationUnstable`,
    carrying the result up to that point, when the run loses stability or a block leaves the base.
    """
    run = Simulation(scene, excitation, duration, dt, output_dt, ground_motion=ground_motion, safety=safety,
                     steps_per_impact=steps_per_impact, step_fraction=step_fraction, stop_at_overturn=stop_at_overturn,
                     enforce_stability_limit=enforce_stability_limit, parallel=parallel, integrator=integrator,
                     theta=theta, start=start)
    run.advance(progress=progress)
    return run.result()


@contextlib.contextmanager
def _interrupt_after_the_kernel():
    """Hold Ctrl-C back while the compiled kernel runs: an exception raised in the Python code that numba's
    compiled code calls back crashes the process.  Yields a list that is true after the block if Ctrl-C came
    (the caller raises ``KeyboardInterrupt`` then).  In threads other than the main one SIGINT is not
    delivered, and nothing changes."""
    came = []
    if threading.current_thread() is not threading.main_thread():
        yield came
        return
    previous = signal.signal(signal.SIGINT, lambda signum, frame: came.append(signum))
    try:
        yield came
    finally:
        signal.signal(signal.SIGINT, previous)


def _stack_label(scene, stack) -> str:
    names = [scene.blocks[b].name for b in stack.blocks]
    return f"{names[0]}..{names[-1]}"


def automatic_time_step(scene, *, toppled: bool = False, safety: float = DEFAULT_SAFETY,
                        steps_per_impact: float = DEFAULT_STEPS_PER_IMPACT) -> float:
    """The step :func:`simulate` chooses when given none, s: the smaller of ``safety`` times the
    stability limit (with ``toppled``, the limit of blocks lying on their long sides) and the
    shortest impact over ``steps_per_impact``.  (Going on through a collapse, ``simulate`` takes the steps
    during which a block is overturned in substeps of at most ``COLLAPSE_STEP_FACTOR`` of the toppled value.)"""
    model = compile_model(scene)
    limit = stability.stability_limit(model, toppled=toppled)
    return _time_step(model, None, limit, stability.impact_duration(model), safety, steps_per_impact, 1.0, True)


def moreau_time_step(model, excitation: GroundMotion, dt: float | None = None, step_fraction: float = 1.0) -> float:
    """Moreau-Jean's step, s: ``dt`` if given, else ``MOREAU_DT``, or ``MOREAU_TIME_FRACTION`` of the shortest time
    of the motion (:attr:`GroundMotion.time_scale`) or of the scene (``1/p = sqrt(4 R / (3 g))`` of its smallest
    block, R the circumradius) where that is shorter, times ``step_fraction``."""
    check_step_fraction(step_fraction)
    if dt is not None:
        if step_fraction != 1.0:
            raise ValueError(f"step_fraction ({step_fraction}) applies to the automatic step; give it or dt, not both")
        return seconds("dt", dt)
    agile = math.sqrt(4.0 * float(model.bodies.radius[1:].min()) / (3.0 * model.gravity))
    return min(MOREAU_DT, MOREAU_TIME_FRACTION * min(excitation.time_scale, agile)) * step_fraction


def integrator_for(scene, integrator: str | None = None) -> str:
    """``integrator`` (``ValueError`` naming the choices if it is none of :data:`INTEGRATORS`), or where None the
    default: Moreau-Jean on the corner law's points, as accurate as the explicit core and many times faster
    (docs/method.md 1.8), and the explicit core for the overlap-area law, whose only integrator it is."""
    if integrator is None:
        return INTEGRATORS[MOREAU] if scene.contact.law == "corner" else INTEGRATORS[EXPLICIT]
    integrator_code(integrator)
    return integrator


def _time_step(model, dt, limit, impact, safety, steps_per_impact, step_fraction, enforce) -> float:
    check_step_options(safety, steps_per_impact, step_fraction)
    if dt is None:
        automatic = min(safety * limit, impact / steps_per_impact)
        return automatic if step_fraction == 1.0 else automatic * step_fraction
    if step_fraction != 1.0:
        raise ValueError(f"step_fraction ({step_fraction}) applies to the automatic step; give it or dt, not both")
    dt = seconds("dt", dt)
    if dt > limit and enforce:
        raise ValueError(f"dt = {dt:.4g} s is above the stability limit {limit:.4g} s of this scene "
                         f"(contact stiffness kn = {model.law.kn:.3g}); use dt <= {limit:.4g} or dt=None")
    return float(dt)


def _speed_limit(model, excitation, duration) -> float:
    """Bound on any block's speed relative to the ground (m/s) that no stable run reaches.

    ``SPEED_LIMIT_FACTOR`` times the sum of the free-fall speed from the top of the scene, the largest ground
    velocity change over the run (:func:`~dem_core.inputs.excitation.velocity_range`) and 1 mm/s.
    """
    fall = np.sqrt(2.0 * model.gravity * max(model.top, 0.0))
    return float(SPEED_LIMIT_FACTOR * (fall + velocity_range(excitation, duration) + 1e-3))


def run_settings(model: Model, integrator: int, dt: float, last_step: int, stride: int, speed_limit: float,
                 stop_at_overturn: bool, inertial: bool, substeps: int, theta: float) -> Settings:
    """The :class:`~dem_core.engine.settings.Settings` of a run of ``model`` under ``integrator`` (its code) with
    step ``dt`` (s), ``last_step``, output ``stride`` (steps), the ``speed_limit`` of :func:`_speed_limit` (m/s),
    the explicit integrator's ``substeps`` past an overturn and Moreau-Jean's ``theta``; the base's centre at the
    start, the motion at unit scale and the tolerances of this module."""
    law, bodies, gravity = model.law, model.bodies, model.gravity
    return make_settings(
        dt=dt, speed_limit=speed_limit, energy_tolerance=ENERGY_TOLERANCE,
        energy_scale=float(gravity * np.sum(bodies.radius * bodies.mass)), gravity=gravity, floor=model.floor,
        half_skin=0.5 * law.skin, scale=1.0, start_x=bodies.centroid0[0, 0], start_y=bodies.centroid0[0, 1],
        theta=theta, active_gap=MOREAU_ACTIVE_GAP * gravity * dt**2, slop=MOREAU_SLOP * gravity * dt**2,
        solver_tolerance=MOREAU_SOLVER_TOLERANCE * gravity * dt, solver_failure=MOREAU_SOLVER_FAILURE,
        shortest_substep=MOREAU_SHORTEST_SUBSTEP, restitution=law.restitution, integrator=integrator,
        contact_law=law.law, stride=stride, interface_stride=interface_stride(dt), last_step=last_step,
        stop_at_overturn=stop_at_overturn, inertial=inertial, substeps=substeps, max_sweeps=MOREAU_MAX_SWEEPS,
        rescue_sweeps=MOREAU_RESCUE_SWEEPS, projection_sweeps=MOREAU_PROJECTION_SWEEPS,
        status_passes=MOREAU_STATUS_PASSES, max_substeps=MOREAU_MAX_SUBSTEPS)


#: a run of more steps than this is refused; above WARN_STEPS it is announced with its expected wall time
MAX_STEPS = 1_000_000_000
WARN_STEPS = 10_000_000
#: rough wall time of one block-step of central differences on a laptop core (s; docs/performance.md), for the
#: announcement only
BLOCK_STEP_SECONDS = 1e-7
#: the outputs may take at most this fraction of the machine's memory
MAX_MEMORY_FRACTION = 0.5


class RunTooLarge(ValueError):
    """A run that would take more steps or memory than can be meant; the message names the culprit."""


def _check_run_size(model, names, duration, dt, auto_dt, n_steps, n_out, limit, impact):
    """Refuse before allocating a run of more than ``MAX_STEPS`` steps or whose outputs would not fit in
    memory, naming what made it so; announce one of more than ``WARN_STEPS`` with its expected wall time.
    ``names`` : the blocks' names, in the model's order."""
    n_bodies = len(model.bodies.mass)
    if auto_dt and not math.isfinite(limit):
        step = f"Moreau-Jean's automatic step dt = {dt:.3g} s"
    elif auto_dt:
        lightest = 1 + int(np.argmin(model.bodies.mass[1:]))
        light = f"lightest block '{names[lightest - 1]}' {model.bodies.mass[lightest]:.3g} kg"
        if DEFAULT_SAFETY * limit < impact / DEFAULT_STEPS_PER_IMPACT:
            hint = _damping_hint(model.law)
            why = f"the stability limit {limit:.3g} s" + (f", which {hint}" if hint else
                                                         f" of the stiffest contact (K_n = {model.law.kn:.3g} N/m^2, "
                                                         f"{light})")
        else:
            why = f"the shortest impact {impact:.3g} s (K_n = {model.law.kn:.3g} N/m^2, {light})"
        step = f"the automatic step dt = {dt:.3g} s, set by {why}"
    else:
        step = f"the given dt = {dt:.3g} s"
    if n_steps > MAX_STEPS:
        raise RunTooLarge(f"the run would take {n_steps:.3g} steps (duration {duration:.4g} s at {step}), more than "
                          f"{MAX_STEPS:.0e}: shorten the duration or check the scene's masses and contact parameters")
    memory = n_out * (3 * n_bodies + len(model.interface_keys) + 1) * 8.0
    available = _physical_memory()
    if memory > MAX_MEMORY_FRACTION * available:
        raise RunTooLarge(f"the outputs would take {memory / 2**30:.3g} GiB ({n_out:.3g} outputs of "
                          f"{n_bodies} bodies), more than half of this machine's {available / 2**30:.3g} GiB: "
                          f"raise output_dt or shorten the duration ({duration:.4g} s)")
    if n_steps > WARN_STEPS:
        expected = n_steps * (n_bodies - 1) * BLOCK_STEP_SECONDS
        warn_caller(f"a long run: {n_steps:.3g} steps (duration {duration:.4g} s at {step}); expect about "
                    f"{expected / 60:.3g} minutes")


def _damping_hint(law) -> str:
    """The explicit dashpots of the compiled ``law``, which may set the stability limit rather than its springs
    (or '')."""
    given = {name: getattr(law, name) for name in ("cn", "cr", "ct") if not np.isnan(getattr(law, name))}
    if given:
        return "the explicit dashpots (" + ", ".join(f"{k} = {v:.3g} N s/m" for k, v in given.items()) + ") shrink"
    return ""


def _physical_memory() -> float:
    """This machine's memory, bytes."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return 8.0 * 2**30


def _ensure_compiled(run: Simulation) -> float:
    """Compile the kernel (or load it from numba's cache) with a zero-step call, unless this process has; returns the
    seconds it took (0 where it had been, and where numba compiles nothing: NUMBA_DISABLE_JIT's plain function).
    The driver's arguments, named tuples of C-contiguous arrays of fixed dtypes and ranks, have one type for every
    scene, so one compile serves every run."""
    if getattr(run.kernel, "signatures", True):
        return 0.0
    started = time.perf_counter()
    run.kernel(run.arrays, run.settings, run.state.copy(), run.empty_outputs(1), run.new_scratch(),
               run._samples(0, 0), 0)
    return time.perf_counter() - started

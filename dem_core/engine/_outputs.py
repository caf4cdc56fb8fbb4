"""Compiled: the outputs of a run, its state every ``stride`` steps and at its last.

Private module, the driver's output stage: :func:`write_due` writes a step's state when it is an output not yet
written (a chunk that starts where the last one ended, or a chunk taken again, writes no step twice).
"""

import numba as nb

from ._connector_law import SHEAR_FORCE
from .settings import LAST_STEP, STRIDE
from .state import OUTPUTS, STEP


@nb.njit(cache=True, inline="always")
def write_output(state, outputs):
    """The state's positions, the interfaces' slips and the connectors' forces and deformations into the next output
    row (:class:`~.state.Outputs`)."""
    counters = state.counters
    k = counters[OUTPUTS]
    for b in range(state.pos.shape[0]):
        for d in range(3):
            outputs.pos[k, b, d] = state.pos[b, d]
    for m in range(state.interface_slip.shape[0]):
        outputs.slip[k, m] = state.interface_slip[m]
    for c in range(outputs.connectors.shape[1]):
        for d in range(outputs.connectors.shape[2]):
            outputs.connectors[k, c, d] = state.connectors[c, SHEAR_FORCE + d]
    outputs.step[k] = counters[STEP]
    counters[OUTPUTS] = k + 1


@nb.njit(cache=True, inline="always")
def write_due(settings, state, outputs):
    """The state of this step written if it is an output (every STRIDE steps, and the last) not yet written."""
    step = state.counters[STEP]
    written = state.counters[OUTPUTS]
    due = step % settings.integer[STRIDE] == 0 or step == settings.integer[LAST_STEP]
    if due and (written == 0 or outputs.step[written - 1] != step):
        write_output(state, outputs)

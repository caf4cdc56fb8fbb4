"""The GPU figures the docs quote, read from the device check's committed output (reports/gpu_check/h200: its logs
and tables, as ``bash .ci/gpu-check`` wrote them on a lent H200): docs/performance.md's table and the ratios under
it, the README's sentence, and ``GPU_MEMBERS_PER_THREAD``, where ``device="auto"`` takes the GPU; and the counts made
without a GPU that performance.md sets against them (``kernel-accesses``, run here, and ``step-instructions``, from
its committed log: valgrind counts for minutes)."""

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import dem_core
from comparisons.benchmarks.gpu_check import SCALING
from comparisons.benchmarks.gpu_reference import DURATION, SAMPLE
from comparisons.benchmarks.kernel_accesses import UNCOMPILED
from comparisons.benchmarks.record_members import MIDDLE, SCENES, motions
from dem_core.batch import GPU_MEMBERS_PER_THREAD
from dem_core.engine._members import THREADS_PER_BLOCK
from test_quoted_figures import _words

REPOSITORY = Path(__file__).resolve().parents[1]
CHECK = REPOSITORY / "reports" / "gpu_check" / "h200"
#: what ``python -m comparisons step-instructions`` printed on the development machine
STEP_INSTRUCTIONS = REPOSITORY / "reports" / "step_instructions" / "amd_epyc.log"
#: the H200's multiprocessors (NVIDIA's H200 SXM: 132) and the registers each holds (65,536)
MULTIPROCESSORS, REGISTERS = 132, 65536
#: a step of one member on a core of the development machine (AMD EPYC), s: docs/performance.md's "Measuring the
#: joints" table, the 1 x 6 m block's 20 s by central differences at its automatic step and the 8-drum column's 30 s
#: by Moreau-Jean at 1e-3 s, as that table measured them
CPU_STEP = {("block", "explicit"): 0.073 / (20.0 / 5.96e-5), ("column", "moreau"): 0.136 / (30.0 / 1e-3)}


@pytest.fixture(scope="module")
def logs() -> dict:
    return {name: (CHECK / f"{name}.log").read_text() for name in ("first_call", "second_call")}


@pytest.fixture(scope="module")
def section() -> str:
    text = (REPOSITORY / "docs" / "performance.md").read_text()
    start = text.index("### The device check on an H200: first measurements")
    return _words(text[start:text.index("\n## ", start)])


def _row(log: str, item: str) -> tuple:
    """The item and value of the check's row whose item matches ``item`` (a regular expression) at its start."""
    for line in log.splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if len(cells) >= 3 and re.match(item, cells[1]):
            return cells[1], cells[2]
    raise AssertionError(f"no row {item!r} in the log")


def _value(log: str, item: str) -> str:
    return _row(log, re.escape(item))[1]


def resident_threads() -> int:
    """The threads the H200 holds at once at 255 registers a thread: a multiprocessor holds REGISTERS / (32 r) warps
    at r registers (allocated by the warp, in 256s), in whole blocks of THREADS_PER_BLOCK."""
    warps = REGISTERS // (32 * 256)
    return MULTIPROCESSORS * (warps * 32 // THREADS_PER_BLOCK) * THREADS_PER_BLOCK


def per_thread_step(row) -> float:
    """s a step of one member takes a GPU thread: the kernel's time over the waves of :func:`resident_threads` it
    ran in, over each member's steps."""
    waves = int(np.ceil(row.members / resident_threads()))
    return row.kernel_s / waves / (row.member_steps / row.members)


def ratios() -> dict:
    table = pd.read_csv(CHECK / "throughput.csv")
    return {(row.scene, row.integrator): per_thread_step(row) / CPU_STEP[row.scene, row.integrator]
            for row in table.itertuples()}


def test_the_table_is_the_checks_output(logs, section):
    first, second = logs["first_call"], logs["second_call"]
    for item in ("explicit kernel: first batch", "moreau kernel: first batch"):
        assert f"| {_value(first, item)} s |" in section, item
    for name, words in (("explicit", "explicit"), ("moreau", "Moreau-Jean")):
        registers, memory = re.match(r"(\d+) registers, (\d+) B", _value(first, f"{name} kernel, per thread")).groups()
        assert f"{registers} and {memory} B ({words})" in section, name
    table = pd.read_csv(CHECK / "throughput.csv")
    for row, item in zip(table.itertuples(), ("block, explicit, M=", "column, moreau, M=")):
        rate = _value(first, item)
        assert float(rate) == pytest.approx(row.member_steps / row.kernel_s, rel=5e-3)
        setup, kernel = _value(first, item.split(", M=")[0] + ": set-up").split(";")[0].split(", ")
        assert f"{rate} member-steps/s: kernel {kernel} s, set-up {setup} s" in section, item
    column, block = table[table.scene == "column"].iloc[0], table[table.scene == "block"].iloc[0]
    assert f"{block.set_up_s:.1f} s of the block's {block.set_up_s + block.kernel_s:.1f} s " \
           f"({block.set_up_s / block.members * 1e3:.2f} ms a member) and {column.set_up_s:.1f} s of the column's " \
           f"{column.set_up_s + column.kernel_s:.1f} s" in section
    assert f"{column.set_up_s + column.kernel_s:.1f} s the two" in section
    item, took = _row(second, r"\d+ runs \(gpu")
    assert f"{int(item.split()[0]):,} runs (second call) | {took}; overturning median " \
           f"{_value(second, 'overturning median')}" in section
    scanned = pd.read_csv(CHECK / "fine_scan.csv")
    item, took = _row(second, r"\d+ of \d+ systems")
    done, systems = (int(v) for v in re.match(r"(\d+) of (\d+)", item).groups())
    assert done == len(scanned) and f"{done} of {systems} systems, {scanned.runs.sum():,} runs, in {took}" in section


def test_the_fragility_median_on_the_gpu_is_inside_the_cpu_studys_band(logs, section):
    """The GPU's median against the committed CPU study's 90% band (records drawn again), both quoted."""
    gpu = float(_value(logs["second_call"], "overturning median").split(" =")[0])
    study = (REPOSITORY / "reports" / "studies" / "fragility" / "README.md").read_text()
    median, low, high = (float(v) for v in re.search(r"\| overturning \| ([\d.]+) = [\d.]+ g \(([\d.]+) to ([\d.]+)\)",
                                                      study).groups())
    assert low <= gpu <= high
    assert f"(8.86, {low:g} to {high:g}" in section and median == 8.86


def test_the_fine_scans_first_overturns_lie_between_the_cpu_studys_bounds(section):
    scanned = pd.read_csv(CHECK / "fine_scan.csv")
    study = pd.read_parquet(REPOSITORY / "reports" / "studies" / "record_overturning" / "results.parquet")
    for row in scanned.itertuples():
        cpu = study[(study.kind == row.kind) & (study.n_drums == row.n_drums) & (study.record == row.record)].iloc[0]
        assert cpu.standing_below < row.first_overturn_pga and row.first_overturn_pga - 0.02 < cpu.smallest
        assert f"{row.first_overturn_pga:.4f} m/s^2" in section
        assert f"({cpu.standing_below:.4f} and {cpu.smallest:.4f}" in section


def test_the_per_thread_ratios_and_the_auto_rule_are_the_checks(section):
    table = pd.read_csv(CHECK / "throughput.csv").set_index("scene")
    measured = ratios()
    for (scene, integrator), ratio in measured.items():
        row = table.loc[scene]
        step = per_thread_step(row)
        shown = f"{step * 1e6:.0f} us a step" if step < 1e-3 else f"{step * 1e3:.2f} ms a step"
        assert shown in section, (scene, shown)
        assert f"{ratio:.0f} times" in section, (scene, ratio)
    assert GPU_MEMBERS_PER_THREAD == round(np.mean(list(measured.values())), -1)
    assert f"is {GPU_MEMBERS_PER_THREAD} from these" in section


def test_the_readme_and_cli_quote_the_check_and_the_auto_rule():
    readme = _words((REPOSITORY / "README.md").read_text())
    cli = _words((REPOSITORY / "docs" / "cli.md").read_text())
    assert f"at least {GPU_MEMBERS_PER_THREAD} members per CPU thread" in readme
    assert f"at least {GPU_MEMBERS_PER_THREAD} per CPU thread" in cli
    method = _words((REPOSITORY / "docs" / "method.md").read_text())
    assert f"about {GPU_MEMBERS_PER_THREAD} times slower than a CPU core" in method
    assert f"the GPU from {GPU_MEMBERS_PER_THREAD} members per CPU thread" in method
    assert f"about {GPU_MEMBERS_PER_THREAD} times slower" in readme
    table = pd.read_csv(CHECK / "throughput.csv").set_index("scene")
    block, column = table.loc["block"], table.loc["column"]
    assert f"at {block.member_steps / block.kernel_s:.1e} member-steps".replace("e+0", "e") in readme
    assert f"in {column.set_up_s + column.kernel_s:.0f} s of set-up and kernel ({column.set_up_s:.1f} s the set-up" \
        in readme


def test_the_members_bytes_and_the_shortfalls_are_so(section, logs):
    """The bytes of one member's arrays, from the batch's own packing, the resident members' share of them, and how
    far each mark is from what was measured."""
    from dem_core import scenes
    from dem_core.batch_gpu import _motions, pack
    from dem_core.inputs.excitation import sine_pulse
    from dem_core.simulation import Simulation

    resident = resident_threads()
    table = pd.read_csv(CHECK / "throughput.csv").set_index("scene")
    for name, build, integrator, members in (("block", lambda: scenes.block(1.0, 6.0), "explicit", resident),
                                             ("column", scenes.column, "moreau", table.loc["column"].members)):
        runs = [Simulation(build(), sine_pulse(2.0, 0.5), 0.1, integrator=integrator)]
        packed = pack(runs, _motions(runs))
        size = sum(a[0].nbytes for part in (packed.model, packed.settings, packed.state, packed.outputs,
                                            packed.scratch) for a in part)
        assert f"{size:,} B" in section, (name, size)
        assert re.search(rf"{members:,} (resident members )?hold {members * size / 1e6:.0f} MB", section), name
    block, column = table.loc["block"], table.loc["column"]
    assert f"block needs {1e10 / (block.member_steps / block.kernel_s):.0f} times" in section
    assert f"column {(column.set_up_s + column.kernel_s) / 10.0:.1f} times" in section
    took = float(_row(logs["second_call"], r"\d+ runs \(gpu")[1].split()[0])
    assert f"fragility study {took / 60.0:.1f} times" in section


def _accesses(scene: str, integrator: str, *options: str) -> dict:
    """``python -m comparisons kernel-accesses`` (on its default windows unless ``options`` say): each window's
    reads and writes a step, the last window's bytes touched of the member's, and the elements it touched of each
    array."""
    done = subprocess.run([sys.executable, "-m", "comparisons", "kernel-accesses", "--scene", scene, "--integrator",
                           integrator, *options], capture_output=True, text=True, cwd=REPOSITORY, timeout=600, check=True,
                          env={**os.environ, **UNCOMPILED})  # the command counts in this process, not one of its own
    windows = [tuple(int(v) for v in found) for found in
               re.findall(r"steps \d+ to \d+: (\d+) reads and (\d+) writes a step", done.stdout)]
    solver = [tuple(float(v) for v in found) for found in
              re.findall(r"([\d.]+) passes by statuses and ([\d.]+) sweeps a step", done.stdout)]
    touched, held = (int(v.replace(",", "")) for v in
                     re.search(r"touched ([\d,]+) B of the member's arrays .* of ([\d,]+) B", done.stdout).groups())
    elements = {name: int(n.replace(",", "")) for name, n in
                re.findall(r"^  (\S+) +\d+ +[\d.]+% +([\d,]+) ", done.stdout, re.MULTILINE)}
    dt = float(re.search(r"dt ([\d.e+-]+) s", done.stdout).group(1))
    return {"windows": windows, "solver": solver, "touched": touched, "held": held, "elements": elements, "dt": dt}


@pytest.mark.slow
def test_what_a_threads_step_waits_on_is_the_counts_over_the_h200s_steps():
    """docs/performance.md's table of reads a step against the H200's per-thread steps, and the working sets a
    multiprocessor's members touch, from ``kernel-accesses`` and the check's committed throughput."""
    text = (REPOSITORY / "docs" / "performance.md").read_text()
    start = text.index("### What a thread's step waits on, counted without a GPU")
    section = _words(text[start:text.index("\n### ", start + 1)])
    table = pd.read_csv(CHECK / "throughput.csv").set_index("scene")
    resident = resident_threads()
    counted, per_read = {}, {}
    for scene, integrator, label in (("block", "explicit", "1 x 6 m block, central differences"),
                                     ("column", "moreau", "8-drum column, Moreau-Jean")):
        counted[scene] = found = _accesses(scene, integrator)
        _, (reads, writes) = found["windows"]
        step = per_thread_step(table.loc[scene])
        per_read[scene] = step / reads
        shown = f"{step * 1e6:.0f} us" if step < 1e-3 else f"{step * 1e3:.2f} ms"
        row = (f"| {label} | {reads:,} | {writes:,} | {found['touched']:,} B of {found['held']:,} B | {shown} | "
               f"{per_read[scene] * 1e9:.0f} ns |")
        assert row in section, row
    block, column = counted["block"], counted["column"]
    mean = np.mean(list(per_read.values()))
    assert f"mean, {mean * 1e9:.1f} ns a read" in section
    for scene, integrator, said, windows in (("block", "moreau", "the block by Moreau-Jean reads", ()),
                                             ("column", "explicit", "the column by central differences",
                                              ("--windows", "200", "400"))):
        other = _accesses(scene, integrator, *windows)
        reads, dt = other["windows"][1][0], other["dt"]
        assert f"{said} {reads:,} times" in section, (scene, reads)
        took = round(mean * 1e9, 1) * 1e-9 * reads * round(DURATION / dt)
        assert f"{took:,.{1 if took < 10 else 0}f} s for the {scene}'s {DURATION:g} s" in section, (scene, took)
        if integrator == "explicit":
            assert f"{reads:,} times at steps of {dt:.4g} s" in section
            assert f"`--scene column --integrator explicit {' '.join(windows)}`" in section
    assert f"reads {block['windows'][0][0]} times a step and the column {column['windows'][0][0]:,}" in section
    assert f"{block['touched']:,} B of the block's arrays and {column['touched']:,} B of the column's" in section
    band, elements = column["elements"]["scratch.band"], column_band_elements()
    assert f"of the band, {band} elements of {elements:,}" in section
    assert f"a step touches {band} of its {elements:,} elements" in section
    passes, sweeps = column["solver"][1]
    assert f"{passes:.3g} passes by statuses and no Gauss-Seidel sweep a step in the second window" in section
    assert sweeps == 0.0
    build, tan_alpha = SCENES["column"]
    members = motions(tan_alpha, SAMPLE)
    lowest, highest = (dem_core.simulate(build(), motion, DURATION, integrator="moreau").info
                       for motion in (members[0], members[-1]))
    assert (f"{lowest['status_passes_per_step']:.3f} and {highest['status_passes_per_step']:.3f} passes and "
            f"{lowest['sweeps_per_step']:.3f} and {highest['sweeps_per_step']:.3f} sweeps a step over "
            f"{DURATION:g} s of El Centro") in section
    columns = table.loc["column"].members
    assert f"held {resident:,} threads at once (256 on each multiprocessor) and the column's {columns:,}" in section
    assert f"({THREADS_PER_BLOCK} on each of {columns // THREADS_PER_BLOCK})" in section
    assert table.loc["block"].members > resident and resident == MULTIPROCESSORS * 256
    assert f"{ {8: 'eight'}[round(resident / columns)]} times as many" in section
    assert (f"block's members touch {256 * block['touched']:,} B a step, and at 64 the column's "
            f"{64 * column['touched']:,} B") in section
    assert f"the block's touch {64 * block['touched']:,} B" in section
    loads = {scene: sorted(round(threads * blocks) for threads, blocks in SCALING[scene, integrator] if blocks >= 1)
             for scene, integrator in SCALING}
    assert loads == {"block": [16, 64, 256], "column": [8, 64]}
    said = {scene: [f"{n * counted[scene]['touched']:,} B" for n in loads[scene]] for scene in loads}
    assert (f"block at 16, 64 and 256 threads a multiprocessor (its members touching {said['block'][0]}, "
            f"{said['block'][1]} and {said['block'][2]} a step) and the column at 8 and 64 ({said['column'][0]} and "
            f"{said['column'][1]})") in section


def column_band_elements() -> int:
    """The elements of the device check's 8-drum column's band, a Moreau-Jean member's scratch."""
    from dem_core.batch_gpu import _motions, pack
    from dem_core.inputs.excitation import sine_pulse
    from dem_core.simulation import Simulation

    runs = [Simulation(SCENES["column"][0](), sine_pulse(2.0, 0.5), 0.1, integrator="moreau")]
    return pack(runs, _motions(runs)).scratch.band[0].size


def test_the_device_checks_reference_paragraph_names_the_members_it_runs():
    """docs/performance.md's paragraph on the agreement's CPU side run ahead: the members and record length are
    gpu-reference's own."""
    text = _words((REPOSITORY / "docs" / "performance.md").read_text())
    assert f"each case's batch of {SAMPLE} members, {DURATION:g} s of El Centro on 2 threads" in text


def _step_counts() -> tuple:
    """From the committed log of ``python -m comparisons step-instructions``: ``{(scene, integrator, amplitude):
    (instructions a step, steps, s of the record, the command)}``, and the set of (machine, counted build) it names."""
    counts, machines = {}, set()
    for part in STEP_INSTRUCTIONS.read_text().split("$ ")[1:]:
        command = part.splitlines()[0].strip()
        scene, integrator, seconds, amplitude, steps, machine = re.search(
            r"^(\w+) by (\w+), ([\d.]+) s of \w+ at ([\d.]+) g tan\(alpha\): ([\d,]+) steps, \d+ ns a step on (.+) "
            r"\(the driver built for it\)$", part, re.MULTILINE).groups()
        count, cpu = re.search(r"^([\d,]+) instructions a step \(x86-64, the driver built for (\w+);", part,
                               re.MULTILINE).groups()
        options = dict(re.findall(r"--(\w+) (\S+)", command))
        assert (options["scene"], options["integrator"]) == (scene, integrator), command
        assert float(options.get("amplitude", MIDDLE)) == float(amplitude), command
        assert float(options.get("duration", DURATION)) == float(seconds), command
        counts[scene, integrator, float(amplitude)] = (int(count.replace(",", "")), int(steps.replace(",", "")),
                                                       float(seconds), command)
        machines.add((machine, cpu))
    return counts, machines


def test_a_members_step_in_instructions_is_the_counts_log():
    """docs/performance.md's table of instructions a step and what they allow an H200, from the committed log of
    ``step-instructions``, the check's committed throughput, the reads counted above and the issue's marks."""
    from comparisons.benchmarks.gpu_check import MARKS
    from comparisons.benchmarks.record_members import HIGHEST, LOWEST
    from comparisons.benchmarks.step_instructions import GPUS

    text = _words((REPOSITORY / "docs" / "performance.md").read_text())
    start = text.index("### A member's step in instructions, and what an H200 can make of it")
    section = text[start:text.index(" ### ", start + 1)]
    counts, machines = _step_counts()
    ((machine, cpu),) = machines
    assert machine == "x86_64, 2 cores, AMD EPYC"
    assert "2-vCPU AMD EPYC development machine" in section
    assert f"the counted driver for the CPU valgrind presents, {cpu})" in section
    assert all(command.startswith("python -m comparisons step-instructions --scene ") for *_, command in
               counts.values())
    ((multiprocessors, lanes, clock),) = GPUS.values()
    issue = multiprocessors * lanes * clock
    assert f"{multiprocessors} multiprocessors x {lanes // 32} schedulers x 32 lanes x {clock / 1e9:g} GHz" in section
    assert f"{issue:.4g} instructions a second" in section
    amplitudes = (LOWEST, MIDDLE, HIGHEST)
    assert f"{amplitudes[0]:g}, {amplitudes[1]:g} (the default: the device check's middle member) and " \
           f"{amplitudes[2]:g} times g tan(alpha)" in section
    middle = {}
    for scene, integrator, label in (("block", "explicit", "1 x 6 m block, central differences"),
                                     ("column", "moreau", "8-drum column, Moreau-Jean")):
        runs = [counts[scene, integrator, a] for a in amplitudes]
        middle[scene] = runs[1]
        assert f"| {label} | {', '.join(f'{n:,}' for n, *_ in runs)} | {issue / runs[1][0]:.3g} |" in section, label
        assert {seconds for _, _, seconds, _ in runs} == {DURATION}
        assert runs[2][1] < runs[1][1]  # overturned before the record's end, as the section says
    assert f"{DURATION:g} s of the record" in section and "overturns both members before the record's end" in section
    for scene, integrator, label in (("block", "moreau", "1 x 6 m block, Moreau-Jean"),
                                     ("column", "explicit", "8-drum column, central differences")):
        n, _, seconds, _ = counts[scene, integrator, MIDDLE]
        note = f"at {MIDDLE:g}" + ("" if seconds == DURATION else f" ({seconds:g} s)")
        assert f"| {label} | {n:,} {note} | {issue / n:.3g} |" in section, label
    table = pd.read_csv(CHECK / "throughput.csv").set_index("scene")
    block, column, mark = table.loc["block"], table.loc["column"], MARKS["block explicit member-steps/s"]
    per_step = middle["block"][0]
    assert f"block's mark is {mark * per_step / issue:.0%} of the H200's peak issue" in section
    assert f"{mark:.0e} member-steps a second at {per_step:,} instructions".replace("e+", "e") in section
    warps = REGISTERS // (32 * 256)
    assert f"At 255 registers a multiprocessor holds {warps} warps, {warps // 4} a scheduler" in section
    assert f"every {resident_threads() * clock / (mark * per_step):.1f} cycles" in section
    reads = re.search(r"\| 1 x 6 m block, central differences \| ([\d,]+) \|", text[:start]).group(1)
    assert f"branches that differ between its members and {reads} reads a step" in section
    rate = block.member_steps / block.kernel_s
    assert f"The H200 ran {rate:.1e}: {rate * per_step / issue:.1%} of peak issue".replace("e+0", "e") in section
    step = per_thread_step(block)
    assert (f"a thread's instruction every {step * clock / per_step:.0f} cycles (its {step * 1e6:.0f} us a step "
            f"over {per_step:,})") in section
    prototype = float(re.search(r"The prototype of the issue that asked for the GPU path measured ([\d.]+e\d+) "
                                r"member-steps per second", text).group(1))
    assert f"prototype's {prototype:.1e}".replace("e+", "e") in section
    assert f"at most {issue / prototype:.0f} instructions a step" in section
    per_step, steps, _, _ = middle["column"]
    seconds = MARKS["column moreau batch s"]
    assert (f"A member's {steps:,} steps of {per_step:,} instructions in {seconds:g} s, with nothing else in "
            f"those {seconds:g} s, is an instruction every {seconds * clock / (steps * per_step):.0f} cycles"
            ) in section
    assert (f"the {column.members:,} threads together would issue "
            f"{column.members * steps * per_step / seconds / issue:.1%} of the GPU's peak") in section
    step = per_thread_step(column)
    assert (f"step of {step * 1e3:.2f} ms (by the members' mean steps, as above) took {step * clock / per_step:.0f} "
            f"cycles an instruction ({step / per_step * 1e9:.1f} ns)") in section
    assert (f"its kernel's {column.kernel_s:.1f} s over the longest member's {steps:,} steps, "
            f"{column.kernel_s / steps * clock / per_step:.0f} cycles") in section


def test_step_instructions_without_valgrind_says_what_it_needs(tmp_path):
    """Where valgrind is not installed, the command names what it needs and how to install it, no traceback."""
    done = subprocess.run([sys.executable, "-m", "comparisons", "step-instructions", "--duration", "0.1"],
                          capture_output=True, text=True, cwd=REPOSITORY, timeout=300,
                          env={**os.environ, "PATH": str(tmp_path)})
    assert done.returncode != 0 and "Traceback" not in done.stderr
    assert "valgrind and callgrind_control not found" in done.stderr and "apt-get install valgrind" in done.stderr


def test_the_counted_member_is_the_run_simulate_steps_its_samples_made_ahead():
    """step-instructions' member, sampled for its whole run before it steps, ends where the same run sampled chunk by
    chunk ends, bit for bit; a sequence, whose events a single sampling would not follow, is refused."""
    import argparse

    from comparisons.benchmarks.record_members import motion
    from comparisons.benchmarks.step_instructions import _member, _SampledAhead
    from dem_core.inputs.excitation import sequence, sine_pulse
    from dem_core.simulation import Simulation

    for scene, integrator in (("block", "explicit"), ("column", "moreau")):
        counted = _member(argparse.Namespace(scene=scene, integrator=integrator, amplitude=MIDDLE, duration=0.5))
        build, tan_alpha = SCENES[scene]
        chunked = Simulation(build(), motion(tan_alpha, MIDDLE), 0.5, integrator=integrator)
        counted.advance(100)  # more than one chunk each
        counted.advance()
        chunked.advance()
        assert counted.step == chunked.step == chunked.settings.last_step
        assert np.array_equal(counted.state.pos, chunked.state.pos), scene
        assert np.array_equal(counted.state.vel, chunked.state.vel), scene
    with pytest.raises(TypeError, match="not a sequence"):
        _SampledAhead(SCENES["block"][0](), sequence([sine_pulse(1.0, 0.5)] * 2, rest=0.5))

"""--wait: waiting for the jobs to leave the queue, and the summary after it."""
from __future__ import annotations

import shlex
import sys
import time
from dataclasses import dataclass
from typing import Callable

from lray_farm import slurm
from lray_farm.plan import Plan, ranges

SQUEUE_FAILING_S = 120  # stop waiting when squeue has failed this long
FAST_POLLING_S = 120  # one look a second this long, then less and less often
MAX_TASK_LINES = 50  # the summary names at most this many unfinished tasks


def wait_for(jobs: list[str], wait_timeout: int, poll_max: int,
             queued: Callable[[str], int] = slurm.queued,
             clock: Callable[[], float] = time.monotonic,
             sleep: Callable[[float], None] = time.sleep) -> tuple[bool, list[str]]:
    """Waits while squeue lists a job. (True, []) when they have all left the
    queue (or squeue kept failing); (False, the jobs still queued) after
    wait_timeout seconds."""
    start = clock()
    pause = 1
    errors_since: float | None = None
    while True:
        states = {j: queued(j) for j in jobs}
        left = [j for j, s in states.items() if s == slurm.QUEUED]
        if slurm.FAILED in states.values():
            if errors_since is None:
                errors_since = clock()
            if clock() - errors_since >= SQUEUE_FAILING_S:
                print("farm: squeue has failed for 2 minutes (is slurmctld up?); not waiting any longer",
                      file=sys.stderr)
                return True, []
        else:
            errors_since = None
            if not left:
                return True, []
        if clock() - start >= wait_timeout:
            return False, left
        sleep(pause)
        if clock() - start >= FAST_POLLING_S:
            pause = pause * 2 if pause * 2 <= poll_max else poll_max


@dataclass
class Finished:
    """What the summary needs to know about the run."""
    elapsed_s: int
    outdir: str
    farm_dir: str
    job_name: str
    array_job: str  # "" when no array was submitted
    merge_job: str  # "" when no merge job was submitted
    task_states: dict[int, str]  # array task -> "JobState=... ExitCode=..."
    merge_state: str
    rerun: list[str]  # the command that submits what is missing


def summary(plan: Plan, done: int, still: list[int], f: Finished) -> tuple[list[str], int]:
    """The summary's lines and farm's exit status (0: every frame is there)."""
    n = len(plan.frames)
    lines = [f"farm: done in {f.elapsed_s} s: {done}/{n} frames in {f.outdir}"]
    for t in still[:MAX_TASK_LINES]:
        a, b = plan.task_frames(t)
        tile = f", tile {plan.task_tile(t)}/{plan.tiles}" if plan.tiles else ""
        state = f.task_states.get(t) or "state unknown"
        lines.append(f"farm:   task {t} (frames {a}:{b}:{plan.step}{tile}) did not finish: {state}; "
                     f"log {f.farm_dir}/{f.job_name}-{f.array_job or '?'}_{t}.log")
    if len(still) > MAX_TASK_LINES:
        lines.append(f"farm:   ... and {len(still) - MAX_TASK_LINES} more task(s)")
    if f.merge_job and done < n:
        lines.append(f"farm:   merge job {f.merge_job}: {f.merge_state or 'state unknown'}; "
                     f"log {f.farm_dir}/{f.job_name}-merge-{f.merge_job}.log")
    if done == n:
        lines.append(f"farm: all {n} frames done")
        return lines, 0
    which = f" ({ranges(still)})" if still else ""
    lines.append(f"farm: {len(still)} task(s) to re-run{which}; this command submits only those:")
    lines.append("  " + shlex.join(f.rerun))
    return lines, 1

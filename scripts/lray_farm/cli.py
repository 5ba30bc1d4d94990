"""scripts/farm from start to end: check, plan, write the scripts, submit, wait."""
from __future__ import annotations

import os
import re
import shlex
import shutil
import sys
import tempfile
import time

from lray_farm import jobscripts, probe, slurm, summary
from lray_farm.errors import FarmError
from lray_farm.options import (USAGE, HelpRequested, Options, UsageError, lray_options,
                               parse_args, parse_frames)
from lray_farm.plan import Plan, make_plan, output_dir_exists, ranges

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SELF = os.path.join(ROOT, "scripts", "farm")


def _executable(path: str) -> bool:
    return os.path.isfile(path) and os.access(path, os.X_OK)


def check_array_size(todo: list[int], plan: Plan, max_array: int) -> None:
    """A job array's last index must be below MaxArraySize: say what fits."""
    if not todo or todo[-1] < max_array:
        return
    if plan.ntiles > max_array:
        hint = f"give --tiles {max_array} or fewer"
    else:
        groups_fit = max_array // plan.ntiles
        per_task = -(-len(plan.frames) // groups_fit)
        hint = f"give --frames-per-task {per_task} or more, or split --frames"
    raise FarmError(f"task index {todo[-1]} is past this cluster's MaxArraySize ({max_array}): {hint}")


def rerun_command(o: Options, scene: str, outdir: str, lray: str, lray_merge: str) -> list[str]:
    cmd = [SELF, scene, outdir, *o.passthru]
    if lray != os.path.join(ROOT, "build", "lray"):
        cmd += ["--lray", lray]
    if lray_merge and lray_merge != os.path.join(os.path.dirname(lray), "lray-merge"):
        cmd += ["--lray-merge", lray_merge]
    if o.extra:
        cmd += ["--", *o.extra]
    return cmd


def _write_temp(farm_dir: str, prefix: str, text: str) -> str:
    fd, path = tempfile.mkstemp(prefix=prefix, dir=farm_dir)
    with os.fdopen(fd, "w") as f:
        f.write(text)
    return path


def run(o: Options) -> int:
    if not os.path.isfile(o.scene):
        raise FarmError(f"scene '{o.scene}' does not exist or is not a file")
    scene = os.path.abspath(o.scene)
    try:
        os.makedirs(o.outdir, exist_ok=True)
    except OSError:
        raise FarmError(f"cannot create '{o.outdir}'") from None
    outdir = os.path.abspath(o.outdir)
    stem = os.path.splitext(os.path.basename(scene))[0]
    job_name = o.job_name or f"lray-{stem}"
    if not re.fullmatch(r"[A-Za-z0-9._+-]+", job_name):
        raise FarmError(f"--job-name '{job_name}': use letters, digits and . _ + - only")
    farm_dir = os.path.join(outdir, ".farm")
    slurm.log_pattern_dir(farm_dir)  # a folder Slurm cannot log to fails now

    lray = o.lray or os.path.join(ROOT, "build", "lray")
    if not _executable(lray):
        raise FarmError(f"no lray binary at '{lray}' (build it with scripts/setup, or give --lray PATH)")
    lray = os.path.abspath(lray)
    lray_merge = ""
    if o.tiles:
        lray_merge = o.lray_merge or os.path.join(os.path.dirname(lray), "lray-merge")
        if not _executable(lray_merge):
            raise FarmError(f"no lray-merge binary at '{lray_merge}' (give --lray-merge PATH)")
        lray_merge = os.path.abspath(lray_merge)
    lopts = lray_options(o.extra)
    frames = parse_frames(o.frames)

    info = probe.probe(probe.info_command(lray, scene, outdir, lopts.args,
                                          frames if o.frames else None, o.tiles), scene)
    plan = make_plan(info, frames[2], o.per_task, o.tiles)
    exists = output_dir_exists(outdir)
    todo = plan.todo(exists, o.all_tasks)
    done_before = plan.frames_done(exists)
    n = len(plan.frames)

    what = f"{n} frame(s) {plan.first}:{plan.last}:{plan.step} of {plan.total_frames}"
    if plan.tiles:
        what += f", {plan.tiles} tiles each"
    each = f"{plan.per_task} frame(s)" + (", 1 tile" if plan.tiles else "")
    print(f"farm: {stem}: {what}; {plan.ntasks} task(s) ({each} each), {len(todo)} to submit, "
          f"{done_before}/{n} frame(s) done already")
    need_merge = bool(plan.tiles) and done_before < n
    if not todo and not need_merge:
        print(f"farm: nothing to do: every frame is in {outdir}")
        return 0

    array_spec = ""
    if todo:
        check_array_size(todo, plan, slurm.max_array_size())
        array_spec = ranges(todo) + (f"%{o.max_running}" if o.max_running else "")
    opts = slurm.sbatch_options(farm_dir, job_name, o.partition, o.time_limit, o.cpus,
                                o.sbatch_extra)
    task_text = jobscripts.task_script(plan, lray, scene, outdir, lopts.args, lopts.user_threads)
    merge_text = jobscripts.merge_script(lray_merge, outdir, o.keep_tiles) if need_merge else ""

    if o.dry_run:
        print("--- task script")
        print(task_text, end="")
        if array_spec:
            print(f"--- submit: sbatch {shlex.join(opts.array + ['--array', array_spec])} TASK_SCRIPT")
        if need_merge:
            print("--- merge script")
            print(merge_text, end="")
            dep = "--dependency=afterok:ARRAY_JOB_ID --kill-on-invalid-dep=yes " if array_spec else ""
            print(f"--- submit: sbatch {shlex.join(opts.merge)} {dep}MERGE_SCRIPT")
        return 0

    if shutil.which("sbatch") is None:
        raise FarmError("sbatch not found: is this a Slurm submit host? (Debian: apt-get install slurm-client)")
    os.makedirs(farm_dir, exist_ok=True)
    temps: list[str] = []
    try:
        jobs: list[str] = []
        array_job = merge_job = ""
        if array_spec:
            temps.append(_write_temp(farm_dir, ".task.", task_text))
            array_job = slurm.sbatch(opts.array + ["--array", array_spec, temps[-1]]) or ""
            if not array_job:
                raise FarmError("sbatch refused the job array (see its message above)")
            shutil.copyfile(temps[-1], os.path.join(farm_dir, f"{job_name}-{array_job}.sh"))
            jobs.append(array_job)
            print(f"farm: array job {array_job}: tasks {array_spec}, logs "
                  f"{farm_dir}/{job_name}-{array_job}_<task>.log")
        if need_merge:
            temps.append(_write_temp(farm_dir, ".merge.", merge_text))
            dep = ["--dependency", f"afterok:{array_job}", "--kill-on-invalid-dep=yes"] if array_job else []
            merge_job = slurm.sbatch(opts.merge + dep + [temps[-1]]) or ""
            if not merge_job:
                if array_job:
                    slurm.scancel(array_job)
                cancelled = f"; array job {array_job} cancelled" if array_job else ""
                raise FarmError(f"sbatch refused the merge job (see its message above){cancelled}")
            shutil.copyfile(temps[-1], os.path.join(farm_dir, f"{job_name}-merge-{merge_job}.sh"))
            jobs.append(merge_job)
            after = f" (after array job {array_job} succeeds)" if array_job else ""
            print(f"farm: merge job {merge_job}{after}: log {farm_dir}/{job_name}-merge-{merge_job}.log")
    finally:
        for t in temps:
            try:
                os.remove(t)
            except OSError:
                pass
    if not o.wait:
        return 0

    start = time.monotonic()
    finished, left = summary.wait_for(jobs, o.wait_timeout, o.poll_max)
    if not finished:
        print(f"farm: still queued after --wait-timeout {o.wait_timeout} s: job(s) "
              f"{' '.join(left) or '?'} (they keep running; run the same command later to submit "
              "what is missing)", file=sys.stderr)
        return 3
    exists = output_dir_exists(outdir)
    states = slurm.task_states(slurm.show_job(array_job)) if array_job else {}
    merge_state = slurm.fields(slurm.show_job(merge_job), ("JobState", "Reason", "ExitCode")) \
        if merge_job else ""
    lines, status = summary.summary(
        plan, plan.frames_done(exists), plan.missing_tasks(exists),
        summary.Finished(int(time.monotonic() - start), outdir, farm_dir, job_name, array_job,
                         merge_job, states, merge_state,
                         rerun_command(o, scene, outdir, lray, lray_merge)))
    print("\n".join(lines))
    return status


def main(argv: list[str]) -> int:
    # The job ids must show at once, even when stdout is a pipe or a log file.
    sys.stdout.reconfigure(line_buffering=True)  # type: ignore[attr-defined]
    try:
        return run(parse_args(argv))
    except HelpRequested:
        print(USAGE, end="")
        return 0
    except UsageError:
        sys.stderr.write(USAGE)
        return 2
    except FarmError as e:
        print(f"farm: {e}", file=sys.stderr)
        return e.status
    except KeyboardInterrupt:
        return 130

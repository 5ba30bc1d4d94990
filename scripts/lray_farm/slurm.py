"""The Slurm commands: sbatch's options, the submission, and what squeue and
scontrol say about the jobs. Every command runs from an argument list, never
through a shell."""
from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass

from lray_farm.errors import FarmError

DEFAULT_MAX_ARRAY_SIZE = 1001  # Slurm's default MaxArraySize


def log_pattern_dir(farm_dir: str) -> str:
    """farm_dir as the start of an sbatch --output pattern. '%' is doubled
    (Slurm's '%%'); a backslash cannot be written at all (Slurm reads any
    backslash in the pattern as "no replacements", and %A_%a would stay
    literal), so such a folder is refused."""
    if "\\" in farm_dir:
        raise FarmError(f"OUTDIR {farm_dir!r} has a backslash, which Slurm's --output cannot "
                        "take (it turns off the %A/%a patterns): choose another folder")
    return farm_dir.replace("%", "%%")


@dataclass
class SbatchOptions:
    array: list[str]  # for the job array (without --array)
    merge: list[str]  # for the merge job (without --dependency)


def sbatch_options(farm_dir: str, job_name: str, partition: str, time_limit: str,
                   cpus: int | None, sbatch_extra: list[str]) -> SbatchOptions:
    common = ["--parsable", "--requeue"]
    if partition:
        common += ["--partition", partition]
    if time_limit:
        common += ["--time", time_limit]
    logs = log_pattern_dir(farm_dir)
    array = common + ["--job-name", job_name, "--open-mode=append",
                      "--output", f"{logs}/%x-%A_%a.log"]
    if cpus is not None:
        array += ["--cpus-per-task", str(cpus)]
    array += sbatch_extra
    merge = common + ["--job-name", f"{job_name}-merge", "--output", f"{logs}/%x-%j.log"] + sbatch_extra
    return SbatchOptions(array, merge)


def max_array_size() -> int:
    """This cluster's MaxArraySize (the last array index is one less)."""
    try:
        out = subprocess.run(["scontrol", "show", "config"], capture_output=True, text=True,
                             errors="replace", timeout=60).stdout
    except (OSError, subprocess.TimeoutExpired):
        return DEFAULT_MAX_ARRAY_SIZE
    m = re.search(r"^MaxArraySize\s*=\s*([0-9]+)", out, re.MULTILINE)
    return int(m.group(1)) if m else DEFAULT_MAX_ARRAY_SIZE


def sbatch(args: list[str]) -> str | None:
    """Submits; the job id, or None when sbatch refused (its message went to stderr)."""
    try:
        done = subprocess.run(["sbatch", *args], stdout=subprocess.PIPE, text=True,
                              errors="replace")
    except OSError:
        return None
    if done.returncode != 0 or not done.stdout.strip():
        return None
    return done.stdout.strip().split(";", 1)[0]  # --parsable: "id" or "id;cluster"


def scancel(job: str) -> None:
    try:
        subprocess.run(["scancel", job], check=False)
    except OSError:
        pass


QUEUED, GONE, FAILED = 0, 1, 2


def queued(job: str) -> int:
    """QUEUED while squeue lists the job (pending, running or completing). Each job
    is asked about alone: once a finished job has left the controller's memory
    (MinJobAge), squeue answers "Invalid job id" for it."""
    try:
        done = subprocess.run(["squeue", "-h", "-j", job, "-o", "%i"], capture_output=True,
                              text=True, errors="replace", timeout=120)
    except (OSError, subprocess.TimeoutExpired):
        return FAILED
    if done.returncode == 0:
        return QUEUED if done.stdout.strip() else GONE
    return GONE if "Invalid job id" in done.stdout + done.stderr else FAILED


def show_job(job: str) -> str:
    """`scontrol -o show job JOB`: one line per job (per array task), or ""."""
    try:
        return subprocess.run(["scontrol", "-o", "show", "job", job], capture_output=True,
                              text=True, errors="replace", timeout=120).stdout
    except (OSError, subprocess.TimeoutExpired):
        return ""


def fields(line: str, names: tuple[str, ...]) -> str:
    """'JobState=FAILED ExitCode=1:0': the fields named, in the line's order."""
    pattern = r"(?:^|\s)((?:%s)=\S+)" % "|".join(map(re.escape, names))
    return " ".join(re.findall(pattern, line))


def task_states(show_job_output: str) -> dict[int, str]:
    """Array task id -> "JobState=... ExitCode=..." from scontrol -o show job."""
    states: dict[int, str] = {}
    for line in show_job_output.splitlines():
        m = re.search(r"(?:^|\s)ArrayTaskId=([0-9]+)(?:\s|$)", line)
        if m:
            states[int(m.group(1))] = fields(line, ("JobState", "ExitCode"))
    return states

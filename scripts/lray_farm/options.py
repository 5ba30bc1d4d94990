"""scripts/farm's command line: the options, --help, and the lray options after --."""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from lray_farm.errors import FarmError

USAGE = """\
Usage: scripts/farm SCENE OUTDIR [options] [-- lray options]

Submits SCENE to Slurm as a job array (sbatch --array) that renders its frames
into OUTDIR: one task per frame, or per K frames (--frames-per-task K: the scene
is loaded once per task), or with --tiles N one task per (frame, tile) plus a
merge job (--dependency=afterok on the array) that stitches the tiles with
lray-merge. Every task runs `lray ... --skip-existing`, and tasks whose outputs
all exist already are not submitted: run the same command again to finish a
set after failed, cancelled or timed-out tasks. Prints the job ids at once.

Frames and tasks:
  --frames A:B[:STEP]     0-based frames A..B, every STEP-th (default: all)
  --frames-per-task K     frames per array task (default 1)
  --tiles N               split each frame into N bands of rows (lray --tile I/N),
                          one task each, then one lray-merge job for the set
  --keep-tiles            the merge job keeps the tile files (lray-merge --keep-tiles)
  --all-tasks             submit every task even if its outputs exist (lray's
                          --skip-existing still skips complete images of the right size)
Slurm:
  --partition P           sbatch --partition
  --time T                sbatch --time of each task (e.g. 10:00, 1-00:00:00)
  --cpus-per-task C       sbatch --cpus-per-task; lray renders with C threads
                          (unless -t/--threads is among the lray options)
  --max-running M         run at most M tasks at once (--array=...%M)
  --job-name NAME         job name (default lray-<scene stem>)
  --sbatch OPTION         any other sbatch option, e.g. --sbatch --account=vis
                          or --sbatch --mem=4G (repeatable)
Waiting:
  --wait                  wait for the jobs, then summarise: frames done / expected,
                          tasks that did not finish, the command that re-runs them;
                          exit 0 only if every frame is there
  --wait-timeout SECONDS  give up waiting after this long (default 86400); the
                          jobs keep running
  --poll SECONDS          longest pause between two looks at squeue (default 10)
Programs:
  --lray PATH             the lray binary (default: <repository>/build/lray); it
                          must be reachable under the same path on the compute nodes
  --lray-merge PATH       the merge binary (default: lray-merge next to lray)
  --dry-run               print the task script and the sbatch commands, submit nothing
  -h, --help              this message

Logs: OUTDIR/.farm/<job name>-<array job id>_<task>.log per task (appended to when
a task is requeued), OUTDIR/.farm/<job name>-merge-<job id>.log, and a copy of each
submitted script in OUTDIR/.farm/.

Examples:
  scripts/farm scenes/ring.lua out/ --partition short --time 5:00 -- -w 1280 -H 720
  scripts/farm scenes/csg.lua big/ --tiles 16 --cpus-per-task 8 --wait -- -w 7680 -H 4320
"""


class UsageError(FarmError):
    """Not two positional arguments: the whole usage goes to stderr."""


class HelpRequested(Exception):
    """-h / --help: print USAGE, exit 0."""


@dataclass
class Options:
    scene: str = ""
    outdir: str = ""
    frames: str = ""  # the --frames spec as given ("" = all)
    tiles: int = 0  # 0: whole frames
    per_task: int = 1
    partition: str = ""
    time_limit: str = ""
    cpus: int | None = None
    max_running: int | None = None
    job_name: str = ""
    sbatch_extra: list[str] = field(default_factory=list)
    wait: bool = False
    wait_timeout: int = 86400
    poll_max: int = 10
    lray: str = ""
    lray_merge: str = ""
    keep_tiles: bool = False
    all_tasks: bool = False
    dry_run: bool = False
    extra: list[str] = field(default_factory=list)  # after --, as given
    # The farm options again, in their order, for the re-run command of the
    # summary (--lray, --lray-merge and --dry-run are added or left out there).
    passthru: list[str] = field(default_factory=list)


# option -> (attribute, kind): kind "str", "int" (a whole number >= 1), "flag", "list".
_OPTIONS: dict[str, tuple[str, str]] = {
    "--frames": ("frames", "str"),
    "--tiles": ("tiles", "int"),
    "--frames-per-task": ("per_task", "int"),
    "--partition": ("partition", "str"),
    "--time": ("time_limit", "str"),
    "--cpus-per-task": ("cpus", "int"),
    "--max-running": ("max_running", "int"),
    "--job-name": ("job_name", "str"),
    "--sbatch": ("sbatch_extra", "list"),
    "--wait": ("wait", "flag"),
    "--wait-timeout": ("wait_timeout", "int"),
    "--poll": ("poll_max", "int"),
    "--lray": ("lray", "str"),
    "--lray-merge": ("lray_merge", "str"),
    "--keep-tiles": ("keep_tiles", "flag"),
    "--all-tasks": ("all_tasks", "flag"),
    "--dry-run": ("dry_run", "flag"),
}
# Not repeated in the re-run command (it gives the programs only when not the defaults).
_NOT_PASSED_ON = {"--lray", "--lray-merge", "--dry-run"}


def _whole_number(option: str, value: str) -> int:
    if not re.fullmatch(r"[0-9]+", value) or int(value) < 1:
        raise FarmError(f"{option} '{value}': expected a whole number of 1 or more")
    return int(value)


def parse_args(argv: list[str]) -> Options:
    """The command line as scripts/farm has always read it (see USAGE)."""
    o = Options()
    positional: list[str] = []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("-h", "--help"):
            raise HelpRequested()
        if a == "--":
            o.extra = list(argv[i + 1:])
            break
        if a in _OPTIONS:
            attr, kind = _OPTIONS[a]
            if kind == "flag":
                setattr(o, attr, True)
                if a not in _NOT_PASSED_ON:
                    o.passthru.append(a)
                i += 1
                continue
            if i + 1 >= len(argv):
                raise FarmError(f"{a} needs a value (see scripts/farm --help)")
            value = argv[i + 1]
            if kind == "int":
                setattr(o, attr, _whole_number(a, value))
            elif kind == "list":
                getattr(o, attr).append(value)
            else:
                setattr(o, attr, value)
            if a not in _NOT_PASSED_ON:
                o.passthru += [a, value]
            i += 2
            continue
        if a.startswith("-"):
            raise FarmError(f"unknown option '{a}' (lray options go after --; see scripts/farm --help)")
        positional.append(a)
        i += 1
    if len(positional) != 2:
        raise UsageError("expected SCENE and OUTDIR")
    o.scene, o.outdir = positional
    return o


def parse_frames(spec: str) -> tuple[int, int | None, int]:
    """--frames A[:B[:STEP]] -> (first, last or None for "to the end", step)."""
    if not spec:
        return 0, None, 1
    m = re.fullmatch(r"([0-9]+)(?::([0-9]+)(?::([0-9]+))?)?", spec)
    if not m:
        raise FarmError(f"--frames '{spec}': expected A, A:B or A:B:STEP (0-based frame numbers)")
    first = int(m.group(1))
    last = int(m.group(2)) if m.group(2) is not None else first
    step = int(m.group(3)) if m.group(3) is not None else 1
    if step < 1:
        raise FarmError(f"--frames '{spec}': the step must be 1 or more")
    if last < first:
        raise FarmError(f"--frames '{spec}': the last frame comes before the first")
    return first, last, step


@dataclass
class LrayOptions:
    args: list[str]  # what every task (and lray --info) gets
    user_threads: bool  # -t/--threads given: the tasks do not add -t


def lray_options(extra: list[str]) -> LrayOptions:
    """The lray options after --, less what farm sets itself."""
    args: list[str] = []
    user_threads = False
    for a in extra:
        name = a.split("=", 1)[0]
        if name in ("--frames", "--tile", "--tiles", "--crop", "--info"):
            raise FarmError(f"lray option '{a}': scripts/farm sets the frames and tiles itself "
                            "(use --frames / --tiles)")
        if a in ("--skip-existing", "-q", "--quiet"):
            continue  # every task has them anyway
        if name in ("-t", "--threads"):
            user_threads = True
        args.append(a)
    return LrayOptions(args, user_threads)

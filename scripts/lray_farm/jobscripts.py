"""The batch scripts that Slurm runs: one task of the array, and the merge job.

Every path and argument reaches a script through shlex.quote in an assignment
at its top, whatever bytes it holds (newlines, quotes, $(...), spaces); the
rest of each script is constant text that only reads those variables. So no
name can end a comment or a quoted word and become a command.
"""
from __future__ import annotations

import shlex

from lray_farm.plan import Plan


def _words(args: list[str]) -> str:
    return " ".join(shlex.quote(a) for a in args)


# The task's frames and tile from SLURM_ARRAY_TASK_ID, as in Plan.task_frames.
_TASK_BODY = r'''t=${SLURM_ARRAY_TASK_ID:?this script runs as a task of a Slurm job array}
g=$((t / ntiles)) i=$((t % ntiles))
a=$((first + g * per_task * step))
b=$((a + (per_task - 1) * step))
((b <= last)) || b=$last
((a <= last)) || { echo "farm: task $t is past the last frame" >&2; exit 1; }
opts=(--frames "$a:$b:$step" --skip-existing -q)
((tiles == 0)) || opts+=(--tile "$i/$tiles")
threads=${SLURM_CPUS_PER_TASK:-${SLURM_CPUS_ON_NODE:-}}
if ((user_threads == 0)) && [[ -n "$threads" ]]; then opts+=(-t "$threads"); fi
echo "farm: task $t (job ${SLURM_JOB_ID:-?}) on $(hostname) at $(date -u +%FT%TZ): frames $a:$b:$step$( ((tiles)) && echo ", tile $i/$tiles")"
start=$(date +%s.%N)
status=0
"$lray" "$scene" "$outdir" "${opts[@]}" "${lray_opts[@]}" || status=$?
end=$(date +%s.%N)
echo "farm: task $t finished in $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }') s with exit status $status (start $start end $end)"
exit $status
'''


def task_script(plan: Plan, lray: str, scene: str, outdir: str, lray_args: list[str],
                user_threads: bool) -> str:
    return (
        "#!/usr/bin/env bash\n"
        "# Written by scripts/farm: one task of the job array that renders $scene into\n"
        "# $outdir (the values below are quoted for the shell, whatever they contain).\n"
        "set -euo pipefail\n"
        f"lray={shlex.quote(lray)}\n"
        f"scene={shlex.quote(scene)}\n"
        f"outdir={shlex.quote(outdir)}\n"
        f"lray_opts=({_words(lray_args)})\n"
        f"tiles={plan.tiles} ntiles={plan.ntiles} first={plan.first} last={plan.last} "
        f"step={plan.step} per_task={plan.per_task} user_threads={int(user_threads)}\n"
        + _TASK_BODY
    )


def merge_script(lray_merge: str, outdir: str, keep_tiles: bool) -> str:
    args = [lray_merge, outdir] + (["--keep-tiles"] if keep_tiles else [])
    return (
        "#!/usr/bin/env bash\n"
        "# Written by scripts/farm: stitches the tiles in the folder that lray-merge gets below.\n"
        "set -euo pipefail\n"
        'echo "farm: merge (job ${SLURM_JOB_ID:-?}) on $(hostname) at $(date -u +%FT%TZ)"\n'
        f"exec {_words(args)}\n"
    )

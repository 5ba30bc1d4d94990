"""The task list of a job array, from `lray --info`'s outputs, and what is done.

Task t renders frame group g = t // ntiles (per_task consecutive selected
frames) and, with --tiles N, tile i = t % N of each of them: the generated
task script does the same arithmetic on SLURM_ARRAY_TASK_ID. Nothing here
loops over anything bigger than the outputs lray listed, and nothing shells
out: a plan of 100000 tasks is computed in well under a second.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Callable, Iterable

from lray_farm.errors import FarmError

Exists = Callable[[str], bool]  # output name (relative to OUTDIR) -> is it there


@dataclass(frozen=True)
class Plan:
    total_frames: int  # the scene's frame count
    frames: list[int]  # the selected frames, in order
    step: int
    per_task: int
    tiles: int  # 0: whole frames
    files: list[str]  # the final image of each selected frame (relative to OUTDIR)
    tile_files: list[list[str]]  # each selected frame's tiles ([] without --tiles)

    @property
    def first(self) -> int:
        return self.frames[0]

    @property
    def last(self) -> int:
        return self.frames[-1]

    @property
    def ntiles(self) -> int:
        return self.tiles if self.tiles else 1

    @property
    def groups(self) -> int:
        return (len(self.frames) + self.per_task - 1) // self.per_task

    @property
    def ntasks(self) -> int:
        return self.groups * self.ntiles

    def task_frames(self, task: int) -> tuple[int, int]:
        """(first, last) frame of a task; the task renders first:last:step."""
        g = task // self.ntiles
        chunk = self.frames[g * self.per_task:(g + 1) * self.per_task]
        return chunk[0], chunk[-1]

    def task_tile(self, task: int) -> int:
        return task % self.ntiles

    def frames_done(self, exists: Exists) -> int:
        return sum(1 for f in self.files if exists(f))

    def missing_tasks(self, exists: Exists) -> list[int]:
        """The tasks with an output missing: a frame without its image or, with
        tiles, without its image and without the task's tile of it."""
        out: list[int] = []
        for g in range(self.groups):
            members = range(g * self.per_task, min((g + 1) * self.per_task, len(self.frames)))
            pending = [k for k in members if not exists(self.files[k])]
            if not pending:
                continue
            if not self.tiles:
                out.append(g)
                continue
            for i in range(self.tiles):
                if any(not exists(self.tile_files[k][i]) for k in pending):
                    out.append(g * self.tiles + i)
        return out

    def todo(self, exists: Exists, all_tasks: bool) -> list[int]:
        return list(range(self.ntasks)) if all_tasks else self.missing_tasks(exists)


def make_plan(info: dict[str, Any], step: int, per_task: int, tiles: int) -> Plan:
    """The plan for lray --info's JSON (asked with --frames A:B:step and --tiles
    tiles), after checking the counts: nothing is submitted if this raises."""
    total = info.get("frames")
    outputs = info.get("outputs")
    if not isinstance(total, int) or not isinstance(outputs, list):
        raise FarmError("lray --info gave no frame count or no outputs")
    if not outputs:
        raise FarmError("lray --info lists no frames to render")
    if tiles:
        rows = info.get("tile_rows")
        if not isinstance(rows, int):
            raise FarmError("lray --info gave no tile_rows")
        if tiles > rows:
            raise FarmError(f"--tiles {tiles}: the frame has {rows} tile row(s) of 16 pixels "
                            f"({info.get('height', '?')} pixels high), so at most {rows} tiles; "
                            "nothing submitted")
    frames: list[int] = []
    files: list[str] = []
    tile_files: list[list[str]] = []
    for o in outputs:
        frames.append(o["frame"])
        files.append(o["file"])
        if tiles:
            names = o.get("tiles")
            if not isinstance(names, list) or len(names) != tiles:
                raise FarmError(f"lray --info lists no {tiles} tile names for frame {o['frame']}")
            tile_files.append(names)
    # The task script computes a task's frames as first + k * step: lray must
    # have listed exactly that selection.
    if frames != list(range(frames[0], frames[0] + step * len(frames), step)):
        shown = ", ".join(map(str, frames[:6])) + (", ..." if len(frames) > 6 else "")
        raise FarmError(f"lray --info listed frames {shown}, not every {step}th from {frames[0]}: "
                        "is this lray older or newer than scripts/farm?")
    return Plan(total, frames, step, per_task, tiles, files, tile_files)


def output_dir_exists(outdir: str) -> Exists:
    """Existence in OUTDIR, listed once: 100000 names cost one readdir, not
    100000 stat calls."""
    try:
        listing = set(os.listdir(outdir))
    except OSError:
        listing = set()

    def exists(name: str) -> bool:
        if "/" in name:
            return os.path.exists(os.path.join(outdir, name))
        return name in listing

    return exists


def ranges(numbers: Iterable[int]) -> str:
    """Sorted numbers as Slurm's --array list: [0, 1, 2, 3, 7, 9, 10] -> "0-3,7,9-10"."""
    parts: list[str] = []
    start = prev = None
    for n in numbers:
        if start is not None and n == prev + 1:  # type: ignore[operator]
            prev = n
            continue
        if start is not None:
            parts.append(f"{start}" if start == prev else f"{start}-{prev}")
        start = prev = n
    if start is not None:
        parts.append(f"{start}" if start == prev else f"{start}-{prev}")
    return ",".join(parts)

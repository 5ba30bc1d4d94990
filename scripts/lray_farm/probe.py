"""`lray SCENE OUTDIR --info ...`: the scene's frames and the names of its outputs.

lray loads the script with the options given and prints one line of JSON,
rendering nothing: a broken scene or a bad lray option fails here, before
anything is submitted, and farm never re-implements lray's file naming.
"""
from __future__ import annotations

import json
import subprocess
import sys
from typing import Any

from lray_farm.errors import FarmError

PROBE_TIMEOUT_S = 300


def info_command(lray: str, scene: str, outdir: str, lray_args: list[str],
                 frames: tuple[int, int | None, int] | None, tiles: int) -> list[str]:
    cmd = [lray, scene, outdir, "--info", *lray_args]
    if frames is not None and frames[1] is not None:
        cmd += ["--frames", f"{frames[0]}:{frames[1]}:{frames[2]}"]
    if tiles:
        cmd += ["--tiles", str(tiles)]
    return cmd


def parse_info(stdout: str) -> dict[str, Any] | None:
    """The first line of stdout that is a JSON object with a frame count, or None."""
    for line in stdout.splitlines():
        line = line.strip()
        if not line.startswith("{"):
            continue
        try:
            info = json.loads(line)
        except ValueError:
            continue
        if isinstance(info, dict) and isinstance(info.get("frames"), int):
            return info
    return None


def probe(cmd: list[str], scene: str) -> dict[str, Any]:
    try:
        done = subprocess.run(cmd, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                              errors="replace", timeout=PROBE_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        raise FarmError(f"lray took over {PROBE_TIMEOUT_S} s to load '{scene}'") from None
    except OSError as e:
        raise FarmError(f"cannot run '{cmd[0]}': {e.strerror}") from None
    info = parse_info(done.stdout) if done.returncode == 0 else None
    if info is None:
        sys.stderr.write(done.stderr + done.stdout)
        raise FarmError(f"lray could not load '{scene}' with these options "
                        f"(exit {done.returncode}); nothing submitted")
    if not isinstance(info.get("outputs"), list):
        raise FarmError(f"'{cmd[0]}' --info lists no \"outputs\": this lray is older than "
                        "scripts/farm (rebuild it with scripts/setup)")
    return info

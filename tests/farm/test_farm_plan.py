"""Unit tests of scripts/lray_farm (scripts/farm): task lists, resume, the
generated scripts with hostile paths, the count checks, the summary, and the
whole command with a stand-in lray (speaking `lray --info`'s JSON) and
stand-in Slurm commands. Needs neither lray nor Slurm.

    python3 -m unittest discover -s tests/farm -p 'test_*.py'    (CTest: farm.plan)
"""
from __future__ import annotations

import json
import os
import shlex
import stat
import subprocess
import sys
import tempfile
import time
import unittest
from typing import Any

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "scripts"))

from lray_farm import jobscripts, slurm, summary  # noqa: E402
from lray_farm.cli import check_array_size  # noqa: E402
from lray_farm.errors import FarmError  # noqa: E402
from lray_farm.options import lray_options, parse_args, parse_frames  # noqa: E402
from lray_farm.plan import Plan, make_plan, output_dir_exists, ranges  # noqa: E402

FARM = os.path.join(ROOT, "scripts", "farm")


def name_of(stem: str, frames: int, f: int) -> str:
    """The test's stand-in for lray's naming (farm itself only reads names)."""
    return f"{stem}.png" if frames <= 1 else f"{stem}{f:04d}.png"


def info(frames: int = 20, selected: range | None = None, tiles: int = 0, height: int = 48,
         stem: str = "ring") -> dict[str, Any]:
    """What `lray SCENE OUTDIR --info [--frames] [--tiles N]` prints, as a dict."""
    outputs = []
    for f in selected if selected is not None else range(frames):
        o: dict[str, Any] = {"frame": f, "file": name_of(stem, frames, f)}
        if tiles:
            base = o["file"].rsplit(".", 1)[0]
            o["tiles"] = [f"{base}.tile-{i}-of-{tiles}.exr" for i in range(tiles)]
        outputs.append(o)
    return {"frames": frames, "width": 64, "height": height, "samples": 1, "adaptive": False,
            "tile_rows": (height + 15) // 16, "start_clock": 0, "end_clock": 1, "outputs": outputs}


def read(path: str) -> str:
    with open(path) as f:
        return f.read()


def in_set(names: set[str]):
    return lambda n: n in names


class TaskLists(unittest.TestCase):
    def test_one_task_per_frame(self) -> None:
        p = make_plan(info(), 1, 1, 0)
        self.assertEqual((p.ntasks, p.first, p.last), (20, 0, 19))
        self.assertEqual(p.task_frames(7), (7, 7))

    def test_step_and_frames_per_task(self) -> None:
        p = make_plan(info(selected=range(0, 20, 3)), 3, 3, 0)  # --frames 0:19:3
        self.assertEqual(p.frames, [0, 3, 6, 9, 12, 15, 18])
        self.assertEqual(p.ntasks, 3)
        self.assertEqual([p.task_frames(t) for t in range(3)], [(0, 6), (9, 15), (18, 18)])

    def test_tiles_of_frame_groups(self) -> None:
        p = make_plan(info(selected=range(5), tiles=3), 1, 2, 3)
        self.assertEqual(p.ntasks, 9)  # 3 groups (2, 2, 1 frames) x 3 tiles
        self.assertEqual((p.task_frames(4), p.task_tile(4)), ((2, 3), 1))
        self.assertEqual((p.task_frames(8), p.task_tile(8)), ((4, 4), 2))

    def test_more_tiles_than_tile_rows_is_refused_naming_both(self) -> None:
        with self.assertRaises(FarmError) as e:
            make_plan(info(frames=1, tiles=4, height=48), 1, 1, 4)
        self.assertIn("--tiles 4", str(e.exception))
        self.assertIn("3 tile row", str(e.exception))

    def test_frames_other_than_asked_are_refused(self) -> None:
        with self.assertRaises(FarmError):
            make_plan(info(selected=range(0, 20, 2)), 3, 1, 0)

    def test_frames_spec(self) -> None:
        self.assertEqual(parse_frames("4"), (4, 4, 1))
        self.assertEqual(parse_frames("100:199:2"), (100, 199, 2))
        for bad in ("a", "3:1", "1:5:0", "-1", "1:2:3:4"):
            with self.assertRaises(FarmError, msg=bad):
                parse_frames(bad)

    def test_ranges(self) -> None:
        self.assertEqual(ranges([0, 1, 2, 3, 7, 9, 10]), "0-3,7,9-10")
        self.assertEqual(ranges([5]), "5")
        self.assertEqual(ranges([]), "")

    def test_array_size(self) -> None:
        p = make_plan(info(frames=2000), 1, 1, 0)
        with self.assertRaises(FarmError) as e:
            check_array_size(list(range(2000)), p, 1001)
        self.assertIn("--frames-per-task 2 or more", str(e.exception))
        check_array_size(list(range(1000)), p, 1001)


class Resume(unittest.TestCase):
    def test_tasks_with_all_outputs_are_left_out(self) -> None:
        p = make_plan(info(selected=range(6)), 1, 2, 0)
        done = in_set({"ring0000.png", "ring0001.png", "ring0002.png"})
        self.assertEqual(p.missing_tasks(done), [1, 2])  # group 1 has frame 3 missing
        self.assertEqual(p.frames_done(done), 3)
        self.assertEqual(p.todo(done, all_tasks=True), [0, 1, 2])

    def test_a_tile_is_done_when_its_frame_exists(self) -> None:
        p = make_plan(info(selected=range(2), tiles=3), 1, 1, 3)
        done = in_set({"ring0000.png", "ring0001.tile-0-of-3.exr", "ring0001.tile-2-of-3.exr"})
        self.assertEqual(p.missing_tasks(done), [4])  # frame 1, tile 1

    def test_existence_is_read_from_the_folder(self) -> None:
        with tempfile.TemporaryDirectory() as d:
            open(os.path.join(d, "ring0003.png"), "w").close()
            exists = output_dir_exists(d)
            self.assertTrue(exists("ring0003.png"))
            self.assertFalse(exists("ring0004.png"))


HOSTILE = [
    "new\nline; touch {marker}",
    "$(touch {marker})",
    "`touch {marker}`",
    "quote's \"double\" $HOME ${{x}} * ?",
    " leading space\\back\\slash\ttab",
    "'; touch {marker}; '",
]


class GeneratedScripts(unittest.TestCase):
    """The task and merge scripts take any bytes in a path as data."""

    def setUp(self) -> None:
        self.tmp = tempfile.TemporaryDirectory()
        self.marker = os.path.join(self.tmp.name, "pwned")

    def tearDown(self) -> None:
        self.tmp.cleanup()

    def stub(self, name: str) -> str:
        """A program (under a hostile folder) that writes its arguments, NUL-separated."""
        folder = os.path.join(self.tmp.name, name.replace("/", "_"))
        os.makedirs(folder, exist_ok=True)
        path = os.path.join(folder, "lray")
        with open(path, "w") as f:
            f.write('#!/bin/sh\nfor a in "$@"; do printf "%s\\0" "$a"; done > "$ARGV_OUT"\n')
        os.chmod(path, 0o755)
        return path

    def run_script(self, text: str, env: dict[str, str]) -> list[str]:
        self.assertEqual(subprocess.run(["bash", "-n"], input=text, text=True).returncode, 0)
        path = os.path.join(self.tmp.name, "job.sh")
        with open(path, "w") as f:
            f.write(text)
        argv_out = os.path.join(self.tmp.name, "argv")
        done = subprocess.run(["bash", path], env={**os.environ, **env, "ARGV_OUT": argv_out},
                              capture_output=True, text=True)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertFalse(os.path.exists(self.marker), "a path ran as a command")
        return read(argv_out).split("\0")[:-1]

    def test_task_script_passes_hostile_paths_as_data(self) -> None:
        p = make_plan(info(selected=range(4)), 1, 1, 0)
        for h in HOSTILE:
            h = h.format(marker=self.marker)
            lray = self.stub(h)
            opts = ["-D", h, "--seed=$(touch %s)" % self.marker]
            text = jobscripts.task_script(p, lray, "/s/" + h + ".lua", "/o/" + h, opts, False)
            argv = self.run_script(text, {"SLURM_ARRAY_TASK_ID": "2", "SLURM_CPUS_PER_TASK": "3"})
            self.assertEqual(argv, ["/s/" + h + ".lua", "/o/" + h, "--frames", "2:2:1",
                                    "--skip-existing", "-q", "-t", "3", *opts])

    def test_merge_script_passes_hostile_paths_as_data(self) -> None:
        for h in HOSTILE:
            h = h.format(marker=self.marker)
            argv = self.run_script(jobscripts.merge_script(self.stub(h), "/o/" + h, True), {})
            self.assertEqual(argv, ["/o/" + h, "--keep-tiles"])

    def test_task_script_renders_what_the_plan_says(self) -> None:
        p = make_plan(info(selected=range(1, 20, 3), tiles=2), 3, 2, 2)
        lray = self.stub("plain")
        text = jobscripts.task_script(p, lray, "/s.lua", "/o", [], True)
        for t in range(p.ntasks):
            argv = self.run_script(text, {"SLURM_ARRAY_TASK_ID": str(t)})
            a, b = p.task_frames(t)
            self.assertEqual(argv[2:], ["--frames", f"{a}:{b}:3", "--skip-existing", "-q",
                                        "--tile", f"{p.task_tile(t)}/2"], f"task {t}")

    def test_log_folder_for_slurm(self) -> None:
        self.assertEqual(slurm.log_pattern_dir("/o/50%/.farm"), "/o/50%%/.farm")
        with self.assertRaises(FarmError):
            slurm.log_pattern_dir("/o/a\\b/.farm")
        o = slurm.sbatch_options("/o/.farm", "lray-ring", "", "5:00", 2, ["--mem=1G"])
        self.assertEqual(o.array, ["--parsable", "--requeue", "--time", "5:00", "--job-name", "lray-ring",
                                   "--open-mode=append", "--output", "/o/.farm/%x-%A_%a.log",
                                   "--cpus-per-task", "2", "--mem=1G"])
        self.assertIn("lray-ring-merge", o.merge)


class Options(unittest.TestCase):
    def test_passthru_keeps_farm_options_but_not_programs(self) -> None:
        o = parse_args(["s.lua", "out", "--frames", "0:9", "--lray", "/x/lray", "--wait",
                        "--dry-run", "--", "-w", "64"])
        self.assertEqual(o.passthru, ["--frames", "0:9", "--wait"])
        self.assertEqual(o.extra, ["-w", "64"])

    def test_bad_values(self) -> None:
        for argv in (["s", "o", "--tiles", "0"], ["s", "o", "--poll"], ["s", "o", "--bogus"]):
            with self.assertRaises(FarmError, msg=argv):
                parse_args(argv)

    def test_lray_options(self) -> None:
        lo = lray_options(["-w", "64", "-q", "--skip-existing", "--threads=2"])
        self.assertEqual((lo.args, lo.user_threads), (["-w", "64", "--threads=2"], True))
        for bad in ("--frames=3", "--tile", "--tiles", "--crop=0:0:1:1", "--info"):
            with self.assertRaises(FarmError, msg=bad):
                lray_options([bad])


class Summaries(unittest.TestCase):
    def finished(self, **kw: Any) -> summary.Finished:
        base = dict(elapsed_s=10, outdir="/o", farm_dir="/o/.farm", job_name="lray-ring",
                    array_job="41", merge_job="", task_states={0: "JobState=CANCELLED ExitCode=0:15"},
                    merge_state="", rerun=["/r/scripts/farm", "/s/ring.lua", "/o o", "--wait"])
        base.update(kw)
        return summary.Finished(**base)  # type: ignore[arg-type]

    def test_incomplete(self) -> None:
        p = make_plan(info(selected=range(3)), 1, 1, 0)
        lines, status = summary.summary(p, 1, [0, 2], self.finished())
        self.assertEqual(status, 1)
        self.assertEqual(lines[0], "farm: done in 10 s: 1/3 frames in /o")
        self.assertEqual(lines[1], "farm:   task 0 (frames 0:0:1) did not finish: JobState=CANCELLED "
                                   "ExitCode=0:15; log /o/.farm/lray-ring-41_0.log")
        self.assertIn("task 2 (frames 2:2:1) did not finish: state unknown", lines[2])
        self.assertEqual(lines[3], "farm: 2 task(s) to re-run (0,2); this command submits only those:")
        self.assertEqual(shlex.split(lines[4]), self.finished().rerun)

    def test_complete(self) -> None:
        p = make_plan(info(selected=range(3)), 1, 1, 0)
        lines, status = summary.summary(p, 3, [], self.finished())
        self.assertEqual((status, lines[-1]), (0, "farm: all 3 frames done"))

    def test_tiles_and_merge_state(self) -> None:
        p = make_plan(info(frames=1, tiles=2), 1, 1, 2)
        lines, _ = summary.summary(p, 0, [1], self.finished(merge_job="42",
                                                            merge_state="JobState=PENDING Reason=DependencyNeverSatisfied"))
        self.assertIn("task 1 (frames 0:0:1, tile 1/2) did not finish", lines[1])
        self.assertIn("merge job 42: JobState=PENDING Reason=DependencyNeverSatisfied", lines[2])

    def test_task_states_from_scontrol(self) -> None:
        out = ("JobId=5 ArrayJobId=4 ArrayTaskId=1 JobName=x JobState=FAILED Reason=x ExitCode=1:0\n"
               "JobId=6 ArrayJobId=4 ArrayTaskId=12 JobState=COMPLETED ExitCode=0:0\n")
        self.assertEqual(slurm.task_states(out), {1: "JobState=FAILED ExitCode=1:0",
                                                  12: "JobState=COMPLETED ExitCode=0:0"})

    def test_wait_gives_up_after_the_timeout(self) -> None:
        now = [0.0]
        finished, left = summary.wait_for(["7"], 30, 10, queued=lambda j: slurm.QUEUED,
                                          clock=lambda: now[0],
                                          sleep=lambda s: now.__setitem__(0, now[0] + s))
        self.assertEqual((finished, left), (False, ["7"]))


FAKE_LRAY = r'''#!PYTHON
# Stands in for `lray SCENE OUTDIR --info [...] [--frames A:B:S] [--tiles N]`.
import json, os, sys
a = sys.argv[1:]
assert a[2] == "--info", a
frames, height = int(os.environ["FAKE_FRAMES"]), int(os.environ["FAKE_HEIGHT"])
sel = range(frames)
if "--frames" in a:
    f, l, s = map(int, a[a.index("--frames") + 1].split(":"))
    sel = range(f, l + 1, s)
tiles = int(a[a.index("--tiles") + 1]) if "--tiles" in a else 0
stem = os.path.splitext(os.path.basename(a[0]))[0]
outs = []
for f in sel:
    name = stem + (".png" if frames <= 1 else "%04d.png" % f)
    o = {"frame": f, "file": name}
    if tiles:
        o["tiles"] = ["%s.tile-%d-of-%d.exr" % (name[:-4], i, tiles) for i in range(tiles)]
    outs.append(o)
print(json.dumps({"frames": frames, "width": 64, "height": height, "samples": 1, "adaptive": False,
                  "tile_rows": (height + 15) // 16, "start_clock": 0, "end_clock": 1, "outputs": outs},
                 separators=(",", ":")))
'''

FAKE_SLURM = {
    # sbatch: records its arguments, answers job ids 100, 101, ...
    "sbatch": '#!/bin/sh\necho "$*" | tr "\\n" " " >> "$FAKE_LOG"; echo >> "$FAKE_LOG"\n'
              'n=$(wc -l < "$FAKE_LOG"); echo "$((99 + n));fake"\n',
    "scontrol": '#!/bin/sh\nif [ "$2" = config ]; then echo "MaxArraySize            = $FAKE_MAX_ARRAY"; '
                'else echo "JobId=1 ArrayJobId=100 ArrayTaskId=1 JobState=FAILED ExitCode=1:0"; fi\n',
    "squeue": "#!/bin/sh\nexit 0\n",  # nothing queued any more
}


class WholeCommand(unittest.TestCase):
    """scripts/farm itself, with a stand-in lray and stand-in Slurm commands."""

    def setUp(self) -> None:
        self.tmp = tempfile.TemporaryDirectory()
        t = self.tmp.name
        self.bin = os.path.join(t, "bin")
        os.makedirs(self.bin)
        self.lray = os.path.join(t, "lray")
        self.write(self.lray, FAKE_LRAY.replace("PYTHON", sys.executable))
        self.write(os.path.join(t, "lray-merge"), "#!/bin/sh\n")
        for name, text in FAKE_SLURM.items():
            self.write(os.path.join(self.bin, name), text)
        self.scene = os.path.join(t, "ring.lua")
        open(self.scene, "w").close()
        self.log = os.path.join(t, "sbatch.log")
        self.out = os.path.join(t, "out")

    def tearDown(self) -> None:
        self.tmp.cleanup()

    @staticmethod
    def write(path: str, text: str) -> None:
        with open(path, "w") as f:
            f.write(text)
        os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR)

    def farm(self, *args: str, frames: int = 20, height: int = 48,
             max_array: int = 1001) -> subprocess.CompletedProcess[str]:
        env = {**os.environ, "PATH": self.bin + os.pathsep + os.environ["PATH"],
               "FAKE_FRAMES": str(frames), "FAKE_HEIGHT": str(height), "FAKE_LOG": self.log,
               "FAKE_MAX_ARRAY": str(max_array)}
        return subprocess.run([FARM, self.scene, self.out, "--lray", self.lray, *args], env=env,
                              capture_output=True, text=True, timeout=60)

    def submitted(self) -> list[str]:
        return read(self.log).splitlines() if os.path.exists(self.log) else []

    def test_dry_run_submits_nothing(self) -> None:
        r = self.farm("--frames", "0:19:3", "--frames-per-task", "3", "--dry-run", "--", "-w", "64")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("farm: ring: 7 frame(s) 0:18:3 of 20; 3 task(s) (3 frame(s) each), 3 to submit, "
                      "0/7 frame(s) done already", r.stdout)
        self.assertIn("--array 0-2 TASK_SCRIPT", r.stdout)
        self.assertEqual(self.submitted(), [])

    def test_too_many_tiles_refused_before_submission(self) -> None:
        r = self.farm("--tiles", "4", frames=1, height=48)
        self.assertEqual(r.returncode, 2)
        self.assertIn("farm: --tiles 4: the frame has 3 tile row(s)", r.stderr)
        self.assertEqual(self.submitted(), [])

    def test_100000_tiles_dry_run_is_fast(self) -> None:
        start = time.monotonic()
        r = self.farm("--tiles", "100000", "--dry-run", frames=1, height=16 * 100000,
                      max_array=200000)
        self.assertLess(time.monotonic() - start, 5)  # about 0.3 s; generous for a loaded machine
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("--array 0-99999 TASK_SCRIPT", r.stdout)
        self.assertLess(len(r.stdout.splitlines()), 60)
        # Slurm's default MaxArraySize: refused at once, saying what fits.
        r = self.farm("--tiles", "100000", "--dry-run", frames=1, height=16 * 100000)
        self.assertEqual(r.returncode, 2)
        self.assertIn("give --tiles 1001 or fewer", r.stderr)

    def test_submit_resume_and_summary(self) -> None:
        os.makedirs(self.out)
        for f in (0, 2):
            open(os.path.join(self.out, f"ring{f:04d}.png"), "w").close()
        r = self.farm("--frames", "0:3", "--wait", "--poll", "1", frames=20)
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertEqual(len(self.submitted()), 1)
        self.assertIn("--array 1,3 ", self.submitted()[0])
        self.assertIn("farm: array job 100: tasks 1,3, logs", r.stdout)
        self.assertIn("farm: done in 0 s: 2/4 frames in", r.stdout)
        self.assertIn("farm:   task 1 (frames 1:1:1) did not finish: JobState=FAILED ExitCode=1:0", r.stdout)
        self.assertIn("farm: 2 task(s) to re-run (1,3); this command submits only those:", r.stdout)
        rerun = shlex.split(r.stdout.splitlines()[-1])
        self.assertEqual(rerun[:3], [FARM, self.scene, self.out])
        self.assertEqual(rerun[3:], ["--frames", "0:3", "--wait", "--poll", "1", "--lray", self.lray])
        # The copy of the submitted script is there, the temporary one is not.
        self.assertEqual(sorted(os.listdir(os.path.join(self.out, ".farm"))), ["lray-ring-100.sh"])

    def test_tiles_submit_array_then_merge(self) -> None:
        r = self.farm("--tiles", "3", frames=1, height=48)
        self.assertEqual(r.returncode, 0, r.stderr)
        array, merge = self.submitted()
        self.assertIn("--array 0-2", array)
        self.assertIn("--dependency afterok:100 --kill-on-invalid-dep=yes", merge)
        self.assertIn("farm: merge job 101 (after array job 100 succeeds): log", r.stdout)

    def test_hostile_outdir_through_the_command(self) -> None:
        marker = os.path.join(self.tmp.name, "pwned")
        self.out = os.path.join(self.tmp.name, f"o\ntouch {marker}\n$(touch {marker})'")
        r = self.farm("--frames", "0:1")
        self.assertEqual(r.returncode, 0, r.stderr)
        script = read(os.path.join(self.out, ".farm", "lray-ring-100.sh"))
        self.assertIn("outdir=" + shlex.quote(self.out) + "\n", script)
        self.assertEqual(subprocess.run(["bash", "-n"], input=script, text=True).returncode, 0)
        self.assertFalse(os.path.exists(marker))


if __name__ == "__main__":
    unittest.main()

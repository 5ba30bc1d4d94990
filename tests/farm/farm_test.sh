#!/usr/bin/env bash
# The Slurm path of scripts/farm, for real, on this one machine (CTest label
# "farm"): writes a single-node slurm.conf in a temporary folder (auth/none,
# no munge, no accounting, ports on loopback no other test uses), starts
# slurmctld and slurmd as child processes, and checks through scripts/farm:
#   (a) the ring animation (20 frames, one task each): every frame byte-identical
#       to a local render; the same for every 3rd frame, 3 frames per task;
#   (b) a 4-tile split of the CSG gallery frame, stitched by the merge job that
#       waits for the tiles: byte-identical to a local render; a 3-tile split of
#       one ring frame on the kd-tree backend likewise;
#   (c) a task cancelled mid-render (scancel): the set is incomplete, no final
#       name holds anything but a complete frame, and running scripts/farm again
#       submits only the missing task and completes the set byte-identically.
#   (d) an OUTDIR whose name has a newline, $(...), quotes and a %: the frames
#       and logs land there, and no part of the name runs as a command.
# Prints the ring animation's wall time through Slurm against a local render.
# The daemons (and any job left) are stopped on exit, whatever happens. Every
# wait is bounded. If the daemons cannot start, the test fails saying so.
#
# Usage: tests/farm/farm_test.sh [--lray PATH] [--lray-merge PATH] [--keep]
#   (default: <repository>/build/lray and lray-merge next to it; --keep leaves the
#   temporary folder, with the daemons' logs, in place). Environment:
#   FARM_TEST_BUDGET (seconds, default 330), FARM_TEST_SLURM_CONF_EXTRA (lines added
#   to slurm.conf, e.g. SchedulerParameters=batch_sched_delay=0 to measure without
#   Slurm's default 3 s delay between batch job launches).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
lray="$root/build/lray" lray_merge="" keep=0
while (($#)); do
  case "$1" in
  --lray) lray="$2"; shift 2 ;;
  --lray-merge) lray_merge="$2"; shift 2 ;;
  --keep) keep=1; shift ;;
  *) echo "usage: $0 [--lray PATH] [--lray-merge PATH] [--keep]" >&2; exit 2 ;;
  esac
done
[[ -n "$lray_merge" ]] || lray_merge="$(dirname "$lray")/lray-merge"
farm="$root/scripts/farm"
budget=${FARM_TEST_BUDGET:-330} # seconds for the whole test (CTest's TIMEOUT is above it)
t_start=$SECONDS

fail() {
  echo "farm test: FAIL: $*" >&2
  exit 1
}
step() { echo "== farm test [$((SECONDS - t_start)) s]: $*"; }
left() { echo $((budget - (SECONDS - t_start))); } # seconds left of the budget
now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }

for tool in slurmctld slurmd sbatch squeue sinfo scancel scontrol; do
  command -v "$tool" >/dev/null ||
    fail "'$tool' not found: the Slurm packages are missing (scripts/setup installs slurm-wlm)"
done
[[ -x "$lray" ]] || fail "no lray binary at $lray"
[[ -x "$lray_merge" ]] || fail "no lray-merge binary at $lray_merge"
[[ "$("$lray" --help)" == *--tile* ]] || fail "$lray has no --tile option"

# --- a private cluster ----------------------------------------------------------------
tmp="$(mktemp -d "${TMPDIR:-/tmp}/lray-farm-test.XXXXXX")"
chmod 755 "$tmp"
ctld_pid="" slurmd_pid="" ok=0 user="$(id -un)"
export SLURM_CONF="$tmp/slurm.conf"
# Jobs of an enclosing Slurm job must not leak into this cluster's commands.
while read -r v; do [[ "$v" == SLURM_CONF ]] || unset "$v"; done < <(compgen -e | grep '^SLURM_' || true)

show_logs() {
  local f
  # The daemons' stderr (*.out) has what their log files have, and the errors
  # from before they opened them.
  for f in "$tmp"/log/*.out; do
    [[ -s "$f" ]] || f="${f%.out}.log"
    [[ -s "$f" ]] || continue
    echo "--- last lines of $f" >&2
    tail -n 15 "$f" >&2
  done
}
stop_pid() { # PID NAME: SIGTERM, up to 10 s, then SIGKILL
  local pid="$1" i
  [[ -n "$pid" ]] && kill -0 "$pid" 2>/dev/null || return 0
  kill -TERM "$pid" 2>/dev/null || true
  for ((i = 0; i < 100; i++)); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  if kill -0 "$pid" 2>/dev/null; then
    echo "farm test: $2 (pid $pid) ignored SIGTERM for 10 s: killing it" >&2
    kill -KILL "$pid" 2>/dev/null || true
  fi
  wait "$pid" 2>/dev/null || true
}
cleanup() {
  local status=$? i pids p
  trap - EXIT INT TERM
  if [[ -n "$ctld_pid" ]] && kill -0 "$ctld_pid" 2>/dev/null; then
    # Jobs first, so that no slurmstepd outlives slurmd.
    scancel --quiet --user="$user" 2>/dev/null || true
    for ((i = 0; i < 30; i++)); do
      [[ -z "$(squeue -h -o %A 2>/dev/null)" ]] && break
      sleep 0.5
    done
  fi
  stop_pid "$slurmd_pid" slurmd
  stop_pid "$ctld_pid" slurmctld
  # Anything still running from this test's folder (a job step of a killed slurmd).
  pids=""
  for p in /proc/[0-9]*; do
    [[ -r "$p/cmdline" ]] || continue
    if tr '\0' ' ' <"$p/cmdline" 2>/dev/null | grep -qF "$tmp/"; then pids+=" ${p#/proc/}"; fi
  done
  for p in $pids; do [[ "$p" != $$ ]] && kill -KILL "$p" 2>/dev/null || true; done
  if ((status != 0)); then
    show_logs
    echo "farm test: failed after $((SECONDS - t_start)) s; files in $tmp" >&2
  elif ((keep)); then
    echo "farm test: files in $tmp"
  else
    rm -rf "$tmp"
  fi
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

step "writing $SLURM_CONF"
node_line="$(timeout 20 slurmd -C 2>/dev/null | head -n 1)" || true
node="$(sed -n 's/^NodeName=\([^ ]*\).*/\1/p' <<<"$node_line")"
cpus="$(sed -n 's/.* CPUs=\([0-9]*\).*/\1/p' <<<"$node_line")"
mem="$(sed -n 's/.* RealMemory=\([0-9]*\).*/\1/p' <<<"$node_line")"
[[ -n "$node" && -n "$cpus" && -n "$mem" ]] || fail "cannot read this node from 'slurmd -C': '$node_line'"
mem=$((mem * 9 / 10))
# Two free ports (the pair 16817/16818 unless taken).
port=""
for ((p = 16817; p < 16917; p += 2)); do
  if [[ -z "$(ss -Htln "( sport = :$p or sport = :$((p + 1)) )" 2>/dev/null)" ]]; then port=$p; break; fi
done
[[ -n "$port" ]] || fail "no free pair of TCP ports in 16817..16916 for slurmctld and slurmd"

mkdir -p "$tmp/state" "$tmp/spool" "$tmp/log"
cat >"$SLURM_CONF" <<EOF
ClusterName=lrayfarmtest
SlurmctldHost=localhost
AuthType=auth/none
CredType=cred/none
SlurmUser=$user
SlurmdUser=$user
SlurmctldPort=$port
SlurmdPort=$((port + 1))
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
ReturnToService=2
MinJobAge=600
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=farmtest Nodes=ALL Default=YES MaxTime=INFINITE State=UP
${FARM_TEST_SLURM_CONF_EXTRA:-}
EOF

step "starting slurmctld and slurmd (node $node, $cpus CPUs, ports $port/$((port + 1)))"
slurmctld -D -f "$SLURM_CONF" >"$tmp/log/slurmctld.out" 2>&1 &
ctld_pid=$!
for ((i = 0; i < 100; i++)); do
  scontrol ping >/dev/null 2>&1 && break
  kill -0 "$ctld_pid" 2>/dev/null || fail "slurmctld (as user $user) exited at start: see its log below"
  sleep 0.2
done
scontrol ping >/dev/null 2>&1 || fail "slurmctld did not answer 'scontrol ping' within 20 s"
slurmd -D -f "$SLURM_CONF" -N "$node" >"$tmp/log/slurmd.out" 2>&1 &
slurmd_pid=$!
state=""
for ((i = 0; i < 120; i++)); do
  kill -0 "$slurmd_pid" 2>/dev/null || fail "slurmd (as user $user) exited at start: see its log below"
  kill -0 "$ctld_pid" 2>/dev/null || fail "slurmctld exited: see its log below"
  state="$(sinfo -h -n "$node" -o %T 2>/dev/null || true)"
  [[ "$state" == idle ]] && break
  sleep 0.5
done
[[ "$state" == idle ]] || fail "the node is '${state:-not listed}' in sinfo, not idle, 60 s after slurmd started"
step "node $node is idle"

# --- helpers ------------------------------------------------------------------------
# farm_run LOG SCENE OUTDIR ARGS...: scripts/farm --wait, bounded by what is left of the budget.
farm_run() {
  local log="$1"; shift
  local limit=$(($(left) - 30))
  ((limit > 20)) || fail "out of time before: scripts/farm $*"
  timeout $((limit + 20)) "$farm" "$1" "$2" --lray "$lray" --lray-merge "$lray_merge" \
    --wait --wait-timeout "$limit" --poll 1 "${@:3}" >"$log" 2>&1
}
# same_files LOCAL FARM N [strays-ok]: FARM holds the N images of LOCAL, byte for
# byte, and nothing else but its .farm folder (with strays-ok: and files whose
# names are not final names of LOCAL's kind: temporary files of a killed lray).
same_files() {
  local a="$1" b="$2" n="$3" strays_ok="${4:-}" f count=0 extra
  for f in "$a"/*; do
    [[ -e "$b/$(basename "$f")" ]] || fail "$b/$(basename "$f") is missing"
    cmp -s "$f" "$b/$(basename "$f")" || fail "$b/$(basename "$f") differs from the local render $f"
    count=$((count + 1))
  done
  ((count == n)) || fail "$count images in $a, expected $n"
  extra="$(comm -13 <(cd "$a" && ls -A | sort) <(cd "$b" && ls -A | grep -vx '.farm' | sort) | tr '\n' ' ')"
  if [[ -n "$extra" ]]; then
    [[ -n "$strays_ok" ]] || fail "$b holds files the local render does not: $extra"
    if grep -qE '(^| )[a-z]+[0-9]*\.(png|exr|tga)( |$)' <<<"$extra"; then fail "$b holds extra final images: $extra"; fi
    echo "farm test: note: left in $b by the cancelled lray: $extra"
  fi
}
# task_seconds DIR: the sum of the lray times the task logs report, and the last end.
task_seconds() {
  cat "$1"/.farm/*.log | awk '/^farm: task .* finished in/ {
      s += $6; for (i = 1; i <= NF; i++) if ($i == "end") { e = $(i + 1) + 0; if (e > m) m = e } }
    END { printf "%.2f %.3f\n", s, m }'
}

ring=("$root/scenes/ring.lua")
small=(-w 64 -H 48 -s 1)

# --- (a) the ring animation, one task per frame ------------------------------------------
step "(a) ring animation, 20 frames: local render"
t0="$(now)"
"$lray" "${ring[@]}" "$tmp/local-ring" "${small[@]}" -q
local_wall="$(secs "$t0" "$(now)")"
step "(a) ring animation, 20 frames: through Slurm, one task per frame"
t0="$(now)"
farm_run "$tmp/a.log" "${ring[@]}" "$tmp/farm-ring" --cpus-per-task 1 -- "${small[@]}" ||
  { cat "$tmp/a.log" >&2; fail "(a) scripts/farm --wait did not complete the ring animation"; }
farm_wall="$(secs "$t0" "$(now)")"
cat "$tmp/a.log"
grep -q "^farm: array job [0-9]*: tasks 0-19," "$tmp/a.log" || fail "(a) expected one array job of 20 tasks"
grep -q "^farm: done in .*: 20/20 frames" "$tmp/a.log" || fail "(a) the summary does not say 20/20 frames"
same_files "$tmp/local-ring" "$tmp/farm-ring" 20
read -r lray_sum last_end <<<"$(task_seconds "$tmp/farm-ring")"
slurm_wall="$(secs "$t0" "$last_end")"
step "(a) 20 frames byte-identical to the local render"

step "(a) every 3rd frame (0:19:3), 3 frames per task"
farm_run "$tmp/a2.log" "${ring[@]}" "$tmp/farm-ring3" --frames 0:19:3 --frames-per-task 3 -- "${small[@]}" ||
  { cat "$tmp/a2.log" >&2; fail "(a) scripts/farm --frames 0:19:3 --frames-per-task 3 did not complete"; }
cat "$tmp/a2.log"
grep -q "^farm: array job [0-9]*: tasks 0-2," "$tmp/a2.log" || fail "(a) expected 3 tasks for 7 frames, 3 a task"
mkdir "$tmp/local-ring3"
for f in 0 3 6 9 12 15 18; do cp "$(printf '%s/local-ring/ring%04d.png' "$tmp" $f)" "$tmp/local-ring3/"; done
same_files "$tmp/local-ring3" "$tmp/farm-ring3" 7
grep -q 'frames 0:6:3$' "$tmp"/farm-ring3/.farm/*_0.log || fail "(a) task 0 did not render frames 0:6:3"

# --- (b) tiles ---------------------------------------------------------------------------
step "(b) the CSG gallery frame in 4 tiles"
csg=("$root/scenes/csg.lua") csg_opts=(-w 330 -H 206)
"$lray" "${csg[@]}" "$tmp/local-csg" "${csg_opts[@]}" -q
farm_run "$tmp/b.log" "${csg[@]}" "$tmp/farm-csg" --tiles 4 -- "${csg_opts[@]}" ||
  { cat "$tmp/b.log" >&2; fail "(b) scripts/farm --tiles 4 did not complete the CSG frame"; }
cat "$tmp/b.log"
grep -q "^farm: merge job [0-9]* (after array job [0-9]* succeeds)" "$tmp/b.log" || fail "(b) no merge job after the tiles"
same_files "$tmp/local-csg" "$tmp/farm-csg" 1
step "(b) stitched csg.png byte-identical to the local render; the tiles are gone"

step "(b) ring frame 7 in 3 tiles, kd-tree backend"
kd=(-w 64 -H 48 -s 2 --backend kdtree)
"$lray" "${ring[@]}" "$tmp/local-ring-kd" --frames 7 "${kd[@]}" -q
farm_run "$tmp/b2.log" "${ring[@]}" "$tmp/farm-ring-kd" --frames 7 --tiles 3 -- "${kd[@]}" ||
  { cat "$tmp/b2.log" >&2; fail "(b) scripts/farm --frames 7 --tiles 3 (kd-tree) did not complete"; }
cat "$tmp/b2.log"
same_files "$tmp/local-ring-kd" "$tmp/farm-ring-kd" 1

# --- (c) a task cancelled mid-render, then the set resumed -----------------------------------
# Frames big enough to take seconds each on one CPU; 3 tasks, 2 at a time.
slow=(-w 960 -H 720 -s 8)
step "(c) 3 slow ring frames: local render"
"$lray" "${ring[@]}" "$tmp/local-slow" --frames 0:2 "${slow[@]}" -q
step "(c) through Slurm, cancelling one task while it renders"
out="$tmp/farm-slow"
limit=$(($(left) - 60))
((limit > 30)) || fail "out of time before (c)"
timeout $((limit + 20)) "$farm" "${ring[@]}" "$out" --lray "$lray" --frames 0:2 --cpus-per-task 1 --wait \
  --wait-timeout "$limit" --poll 1 -- "${slow[@]}" >"$tmp/c.log" 2>&1 &
farm_pid=$!
victim=""
for ((i = 0; i < 120; i++)); do
  # A running task whose log says lray has started on its frame.
  while read -r id st; do
    [[ "$st" == RUNNING ]] || continue
    compgen -G "$out/.farm/*-${id}.log" >/dev/null && grep -q '^farm: task .* frames' "$out"/.farm/*-"$id".log &&
      { victim="$id"; break; }
  done < <(squeue -h -r -n lray-ring -o '%i %T' 2>/dev/null || true)
  [[ -n "$victim" ]] && break
  kill -0 "$farm_pid" 2>/dev/null || break
  sleep 0.25
done
[[ -n "$victim" ]] || { cat "$tmp/c.log" >&2; fail "(c) no task of the slow set was seen running within 30 s"; }
sleep 0.5
task="${victim#*_}"
victim_frame=$(printf 'ring%04d.png' "$task")
[[ ! -e "$out/$victim_frame" ]] || fail "(c) task $victim finished before it could be cancelled (frames too fast?)"
step "(c) scancel $victim (frame $task) while it renders"
scancel "$victim"
farm_status=0
wait "$farm_pid" || farm_status=$?
cat "$tmp/c.log"
((farm_status == 1)) || fail "(c) scripts/farm --wait exited with $farm_status after a cancelled task, expected 1"
grep -q "^farm: done in .*: 2/3 frames" "$tmp/c.log" || fail "(c) the summary does not say 2/3 frames"
grep -q "^farm:   task $task .*did not finish: JobState=CANCELLED" "$tmp/c.log" ||
  fail "(c) the summary does not name task $task as cancelled"
[[ ! -e "$out/$victim_frame" ]] || fail "(c) $out/$victim_frame exists although its task was cancelled"
for f in "$out"/ring*.png; do
  cmp -s "$f" "$tmp/local-slow/$(basename "$f")" || fail "(c) $f is not the complete frame (half-written?)"
done
rerun="$(sed -n '/this command submits only those:/{n;s/^  //;p}' "$tmp/c.log")"
[[ -n "$rerun" ]] || fail "(c) the summary does not give the command that re-runs the cancelled task"
step "(c) resubmitting with the command the summary printed: $rerun"
timeout $(($(left) - 10)) bash -c "$rerun" >"$tmp/c2.log" 2>&1 ||
  { cat "$tmp/c2.log" >&2; fail "(c) the resubmitted set did not complete"; }
cat "$tmp/c2.log"
grep -q "^farm: array job [0-9]*: tasks $task," "$tmp/c2.log" || fail "(c) the resubmission did not submit task $task alone"
same_files "$tmp/local-slow" "$out" 3 strays-ok
step "(c) the resumed set is complete and byte-identical"

# --- (d) a hostile output folder ----------------------------------------------------------
# A newline, $(...), quotes and a % in OUTDIR reach the job scripts quoted and
# Slurm's --output as %%: the frames and the logs land in that folder, and no
# part of its name runs as a command.
step "(d) ring frames 0:1 into a folder named with a newline, \$(...), quotes and %"
hostile="$tmp/farm-odd
\$(touch $tmp/pwned) \"q\" 'q' 50%"
farm_run "$tmp/d.log" "${ring[@]}" "$hostile" --frames 0:1 -- "${small[@]}" ||
  { cat "$tmp/d.log" >&2; fail "(d) scripts/farm did not complete into a hostile OUTDIR"; }
cat "$tmp/d.log"
[[ ! -e "$tmp/pwned" ]] || fail "(d) a part of the folder's name ran as a command"
for f in ring0000.png ring0001.png; do
  cmp -s "$tmp/local-ring/$f" "$hostile/$f" || fail "(d) $f is missing or differs in the hostile OUTDIR"
done
compgen -G "$hostile/.farm/lray-ring-*_1.log" >/dev/null || fail "(d) no task log in the hostile OUTDIR's .farm"
step "(d) frames and logs in the hostile folder, nothing ran"

# --- timing ------------------------------------------------------------------------------
slots=$cpus
awk -v l="$local_wall" -v f="$farm_wall" -v w="$slurm_wall" -v s="$lray_sum" -v n=20 -v c="$slots" 'BEGIN {
  printf "farm test: ring animation, 20 frames of 64x48, 1 sample:\n"
  printf "  local render (one lray, %d threads):           %6.2f s\n", c, l
  printf "  through Slurm (20 tasks, 1 CPU each, %d at once): %6.2f s to the last frame (%.2f s to scripts/farm --wait returning)\n", c, w, f
  printf "  lray inside the tasks:                          %6.2f s in all, %.3f s a task\n", s, s / n
  printf "  overhead per task (CPU slots x wall - lray) / tasks: %.2f s\n", (c * w - s) / n
}'
ok=1
step "all checks passed"

#!/usr/bin/env bash
# The render farm on a real Slurm. Starts a private one-node cluster (munged, slurmctld, slurmd on
# free non-default ports; config, state, spool, logs and the munge key in a temporary folder),
# then:
#   1. submits `candela farm slurm --parts 4 --submit` on the Cornell box, waits for the merge job
#      and compares the image with the single-machine render (every pixel within 1e-5);
#   2. submits the same farm again and cancels array task 2 while it renders (scancel: SIGTERM,
#      as at a time limit, then SIGKILL): the merge job is cancelled (afterok); task 2 wrote a
#      part marked partial (what it had, whole, never half-written), which `candela farm status`
#      and `candela merge` report, naming what is missing and the command that renders it;
#      resubmitting task 2 alone, then the merge job, completes the image, bit-identical to the
#      first farm's.
# It stops only the daemons it started, and never touches a Slurm that was already running (it
# talks to its own through SLURM_CONF and the munge socket named there).
# Exit 0 passed, 1 failed, 77 skipped (ctest SKIP_RETURN_CODE) when Slurm cannot be installed.
#
# Usage: slurm_farm.sh CANDELA SOURCE_DIR
set -euo pipefail
candela=$1
source_dir=$2
export PATH="$PATH:/usr/sbin:/sbin"

skip() { echo "SKIPPED: $*"; exit 77; }
fail() { echo "FAILED: $*"; show_logs; exit 1; }
note() { echo "[$(date +%T)] $*"; }

# --- Slurm and munge, installed when missing --------------------------------------------------
have_slurm() { for t in slurmctld slurmd sbatch squeue scontrol scancel sinfo munged; do command -v "$t" >/dev/null || return 1; done; }
if ! have_slurm; then
  note "installing Slurm and munge (scripts/install-deps.sh slurm)"
  "$source_dir/scripts/install-deps.sh" slurm || skip "the Slurm packages (slurmctld slurmd slurm-client munge) are missing and could not be installed"
  have_slurm || skip "Slurm's programs are still missing after installing the packages"
fi
# A Slurm already running is left alone: this test talks only to its own daemons.
running() { local f pids=""; for f in /proc/[0-9]*/comm; do [ "$(cat "$f" 2>/dev/null)" = "$1" ] && pids+=" $(basename "$(dirname "$f")")"; done; echo $pids; }
for d in slurmctld slurmd munged; do
  pids=$(running "$d")
  [ -z "$pids" ] || note "a $d is already running (pids $pids); it is left alone: this test starts and uses its own"
done

# --- A private cluster -------------------------------------------------------------------------
tmp=$(mktemp -d "${TMPDIR:-/tmp}/candela-slurm.XXXXXX")
chmod 755 "$tmp"
mkdir -p "$tmp/munge" "$tmp/state" "$tmp/spool" "$tmp/log" "$tmp/work"
started_pids=()

show_logs() {
  for f in "$tmp"/log/*.log "$tmp"/munge/munged.log "$tmp"/work/*/logs/*.log; do
    [ -f "$f" ] && { echo "--- $f"; tail -n 20 "$f"; }
  done
  return 0
}

stop_cluster() {
  set +e
  if [ -n "${SLURM_CONF:-}" ] && [ -f "$SLURM_CONF" ]; then
    scancel --quiet --user="$(id -un)" 2>/dev/null  # only jobs of this private cluster
    for _ in $(seq 50); do [ -z "$(squeue -h 2>/dev/null)" ] && break; sleep 0.1; done
  fi
  for pid in "${started_pids[@]}"; do kill -TERM "$pid" 2>/dev/null; done
  for pid in "${started_pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null
  done
  rm -rf "$tmp"
}
trap stop_cluster EXIT

# Two free TCP ports above the usual ones (Slurm's defaults are 6817 and 6818).
port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
pick_port() {
  local p
  for _ in $(seq 100); do
    p=$(( 20000 + RANDOM % 20000 ))
    if port_free "$p" && [ "$p" != "${ctld_port:-}" ]; then echo "$p"; return; fi
  done
  fail "no free port found"
}
ctld_port=$(pick_port)
slurmd_port=$(pick_port)

user=$(id -un)
host=$(hostname -s)
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chmod 700 "$tmp/munge"
chmod 400 "$tmp/munge/munge.key"
munged --force --socket="$tmp/munge/munge.sock" --key-file="$tmp/munge/munge.key" --pid-file="$tmp/munge/munged.pid" \
  --log-file="$tmp/munge/munged.log" --seed-file="$tmp/munge/munged.seed" || fail "munged did not start"
for _ in $(seq 50); do [ -s "$tmp/munge/munged.pid" ] && [ -S "$tmp/munge/munge.sock" ] && break; sleep 0.1; done
started_pids+=("$(cat "$tmp/munge/munged.pid")")
chmod 755 "$tmp/munge"  # clients reach the socket; the key stays 0400

cat > "$tmp/slurm.conf" <<EOF
# A one-node cluster for Candela's farm test (tests/farm/slurm_farm.sh).
ClusterName=candelatest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$tmp/munge/munge.sock
CredType=cred/munge
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
SlurmdParameters=config_overrides
ReturnToService=2
KillWait=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$tmp/slurm.conf"

slurmctld -i -f "$SLURM_CONF" || fail "slurmctld did not start"
for _ in $(seq 100); do [ -s "$tmp/slurmctld.pid" ] && break; sleep 0.1; done
started_pids+=("$(cat "$tmp/slurmctld.pid")")
slurmd -f "$SLURM_CONF" -N "$host" || fail "slurmd did not start"
for _ in $(seq 100); do [ -s "$tmp/slurmd.pid" ] && break; sleep 0.1; done
started_pids+=("$(cat "$tmp/slurmd.pid")")
for _ in $(seq 300); do [ "$(sinfo -h -o %T 2>/dev/null)" = idle ] && break; sleep 0.1; done
[ "$(sinfo -h -o %T)" = idle ] || fail "the node did not come up: $(sinfo -h 2>&1)"
note "private Slurm up: slurmctld port $ctld_port, slurmd port $slurmd_port, folder $tmp"

# --- Helpers -------------------------------------------------------------------------------------
job_state() { scontrol show job "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | head -n 1 | cut -d= -f2; }
# Waits until the jobs (ids, comma-separated) have left the queue.
wait_jobs() {
  for _ in $(seq 1500); do [ -z "$(squeue -h -j "$1" 2>/dev/null)" ] && return 0; sleep 0.2; done
  fail "jobs $1 still queued after 5 minutes: $(squeue 2>&1)"
}
field() { awk -v key="$1" '$1 == key && $2 == "job" { print $3 }'; }

cd "$tmp/work"
scene="$source_dir/scenes/cbox.xml"
render=(-D res=64 --spp 1024 --seed 7 --aov variance)
# Four parts of 256 samples per pixel, about two seconds each on one core: long enough to kill one
# while it renders.
note "single-machine render"
"$candela" render "$scene" "${render[@]}" --quiet -o single.exr

# --- 1. A farm run to its end ------------------------------------------------------------------------
note "farm A: candela farm slurm --parts 4 --submit"
out=$("$candela" farm slurm "$scene" "${render[@]}" --parts 4 --workdir "$tmp/work/a" -o "$tmp/work/a.exr" --submit)
echo "$out"
render_job=$(field render <<<"$out")
merge_job=$(field merge <<<"$out")
[ -n "$render_job" ] && [ -n "$merge_job" ] || fail "farm slurm printed no job ids"
wait_jobs "$render_job,$merge_job"
[ "$(job_state "$merge_job")" = COMPLETED ] || fail "farm A's merge job ended $(job_state "$merge_job")"
"$candela" compare a.exr single.exr --pixel-tolerance 1e-5 || fail "farm A's image differs from the single-machine render"
"$candela" farm status a | tee status-a.txt
grep -q "4 of 4 parts done" status-a.txt || fail "farm status does not see four parts"

# --- 2. A task killed on purpose, resubmitted alone -----------------------------------------------------
note "farm B: the same render; array task 2 is killed while it renders"
out=$("$candela" farm slurm "$scene" "${render[@]}" --parts 4 --workdir "$tmp/work/b" -o "$tmp/work/b.exr" --submit)
render_job=$(field render <<<"$out")
merge_job=$(field merge <<<"$out")
for _ in $(seq 1500); do
  [ "$(squeue -h -j "${render_job}_2" -o %T 2>/dev/null)" = RUNNING ] && break
  sleep 0.05
done
[ "$(squeue -h -j "${render_job}_2" -o %T 2>/dev/null)" = RUNNING ] || fail "task 2 never ran"
# The task's renderer (the batch script execs it) has installed its SIGTERM handler (bit 15 of
# SigCgt in /proc/PID/status) and rendered for a moment: cancelled at once, before the program
# has started, it would simply die, which shows nothing about what an interrupted task leaves.
task_pid=""
for _ in $(seq 600); do
  task_pid=$(pgrep -f -- "-o $tmp/work/b/parts/part-00002.exr" | head -n 1 || true)
  if [ -n "$task_pid" ]; then
    mask=$(awk '/^SigCgt/ {print $2}' "/proc/$task_pid/status" 2>/dev/null || true)
    [ -n "$mask" ] && [ $(( 0x$mask >> 14 & 1 )) -ne 0 ] && break
  fi
  sleep 0.05
done
[ -n "$task_pid" ] || fail "task 2's renderer never started"
sleep 0.5
scancel "${render_job}_2"
note "cancelled task ${render_job}_2"
wait_jobs "$render_job,$merge_job"
state=$(job_state "${render_job}_2")
[ "$state" = CANCELLED ] || fail "task 2 ended $state: it finished before it could be killed (the parts are too short for this machine)"
[ "$(job_state "$merge_job")" = CANCELLED ] || fail "farm B's merge job ran although a task failed: $(job_state "$merge_job")"
[ ! -e b.exr ] || fail "farm B wrote an image although a part is missing"
ls -A b/parts
# No temporaries (names starting with a dot) and four parts: task 2's holds what it had rendered.
[ "$(ls -A b/parts | grep -c '^\.')" = 0 ] || fail "a write was left half-done in b/parts: $(ls -A b/parts)"
[ -e b/parts/part-00002.exr ] || fail "the cancelled task wrote no partial part (SIGTERM was not handled)"
"$candela" farm status b | tee status-b.txt
grep -q "3 of 4 parts done" status-b.txt && grep -q "part-00002.exr: was interrupted" status-b.txt && grep -q "missing: task 2" status-b.txt &&
  grep -q "sbatch --array=2 " status-b.txt || fail "farm status does not report the interrupted task and its resubmission"
set +e
"$candela" merge b/parts -o b.exr 2> merge-b.txt
code=$?
set -e
cat merge-b.txt
[ "$code" = 2 ] || fail "merge of an incomplete farm exited $code, not 2"
[ ! -e b.exr ] || fail "merge of an incomplete farm wrote an image"
# What is missing lies in task 2's samples 512:768, named with the command that renders it.
grep -q "missing samples [0-9]*:768" merge-b.txt && grep -q -- "--samples [0-9]*:768" merge-b.txt ||
  fail "merge does not name the missing range and its command"

note "resubmitting task 2 alone, then the merge"
rerun=$(sbatch --parsable --array=2 b/render.sbatch)
merge_job=$(sbatch --parsable --dependency=afterok:"$rerun" b/merge.sbatch)
wait_jobs "$rerun,$merge_job"
[ "$(job_state "$merge_job")" = COMPLETED ] || fail "the resubmitted merge job ended $(job_state "$merge_job")"
"$candela" compare b.exr single.exr --pixel-tolerance 1e-5 || fail "farm B's image differs from the single-machine render"
"$candela" compare b/parts/part-00002.exr a/parts/part-00002.exr --pixel-tolerance 0 || fail "the re-rendered part differs from farm A's"
"$candela" compare b.exr a.exr --pixel-tolerance 0 || fail "farm B's image is not bit-identical to farm A's"
note "passed in $SECONDS s"

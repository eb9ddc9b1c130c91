#!/usr/bin/env bash
# Prove the Slurm scripts on this machine with a real scheduler: start a one-node Slurm cluster
# (slurmctld + slurmd, munge authentication) from a temporary configuration, render
# scenes/cornell-box.toml's 8 passes as 4 array tasks plus a merge job through submit.sh, render
# the same 8 passes in one process, and require the two images to be equal (sppm-gpu diff:
# RMSE < 1e-5). Prints PASS or FAIL with timings; exits non-zero on failure.
#
# Usage (as root, on Debian/Ubuntu; after `cargo build --release`):
#   bash scripts/slurm/check.sh
# Installs slurm-wlm and munge with apt-get where missing, creates /etc/munge/munge.key where
# there is none and starts munged unless one is running. Everything else (configuration, state,
# spool, logs, images) lives in a temporary folder, removed at the end, and the daemons listen on
# their own ports (CHECK_SLURMCTLD_PORT, CHECK_SLURMD_PORT; default 16817 and 16818), so a Slurm
# already installed here is left alone. On exit it stops, by their process ids, the daemons it
# started, and no others.
# CHECK_TIMEOUT (default 600) is how many seconds the jobs may take.
# KEEP_TMP=1 keeps the temporary folder (its path is printed) for a look at the logs.
set -euo pipefail

cd "$(dirname "$0")/../.."
repo="$(pwd)"
# The binary cargo built: under CARGO_TARGET_DIR when that is set, as cargo itself does.
target_dir="${CARGO_TARGET_DIR:-$repo/target}"
[[ "$target_dir" = /* ]] || target_dir="$repo/$target_dir"
bin="$target_dir/release/sppm-gpu"
scene="$repo/scenes/cornell-box.toml"
passes=8
batches=4
render_options=(--width 64 --height 64 --photons 20000)
timeout="${CHECK_TIMEOUT:-600}" # seconds the jobs may take
ctld_port="${CHECK_SLURMCTLD_PORT:-16817}"
slurmd_port="${CHECK_SLURMD_PORT:-16818}"

say() { echo "check: $*"; }
die() {
    echo "check: FAIL: $*" >&2
    exit 1
}
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }

((EUID == 0)) || die "run as root (it installs packages and starts slurmctld, slurmd and munged)"
[[ -x "$bin" ]] || die "$bin is missing: run 'cargo build --release' first"

# --- packages -------------------------------------------------------------------------------
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null ||
    ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
    say "installing slurm-wlm and munge"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq slurm-wlm munge >/dev/null
fi

# --- state and cleanup ------------------------------------------------------------------------
tmp="$(mktemp -d /tmp/sppm-slurm-check.XXXXXX)"
munged_pid="" ctld_pid="" slurmd_pid="" logs_shown=""
export SLURM_CONF="$tmp/slurm.conf"

stop() {
    local pid
    for pid in "$@"; do
        [[ -n "$pid" ]] || continue
        kill "$pid" 2>/dev/null || continue
        # Wait up to 10 s for it to go, then insist.
        for _ in $(seq 50); do
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.2
        done
        kill -9 "$pid" 2>/dev/null || true
    done
}
show_job_logs() {
    local log
    for log in "$tmp"/out/logs/*.out; do
        [[ -f "$log" ]] || continue
        echo "---- $(basename "$log")"
        cat "$log"
    done
    logs_shown=1
}
cleanup() {
    local status=$?
    set +e
    if [[ -n "$ctld_pid" ]] && kill -0 "$ctld_pid" 2>/dev/null; then
        # Cancel this check's jobs left in the queue (after a failure) while the daemons can still
        # end their processes.
        local jobs
        jobs="$(squeue -h -o %A 2>/dev/null | sort -u | tr '\n' ' ')"
        if [[ -n "${jobs// /}" ]]; then
            # shellcheck disable=SC2086 # a list of job ids
            scancel $jobs 2>/dev/null
            for _ in $(seq 30); do
                [[ -z "$(squeue -h 2>/dev/null)" ]] && break
                sleep 0.5
            done
        fi
    fi
    stop "$slurmd_pid" "$ctld_pid" "$munged_pid"
    if ((status != 0)) && [[ -d "$tmp" ]]; then
        local log
        [[ -n "$logs_shown" ]] || show_job_logs >&2
        for log in "$tmp"/slurmctld.log "$tmp"/slurmd.log; do
            [[ -f "$log" ]] || continue
            echo "---- last lines of $log" >&2
            tail -n 15 "$log" >&2
        done
    fi
    if [[ -n "${KEEP_TMP:-}" ]]; then
        echo "check: kept $tmp"
    else
        rm -rf "$tmp"
    fi
    exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# --- munge --------------------------------------------------------------------------------------
if [[ ! -s /etc/munge/munge.key ]]; then
    say "creating /etc/munge/munge.key"
    mkdir -p /etc/munge
    if command -v mungekey >/dev/null; then
        mungekey --create --keyfile=/etc/munge/munge.key
    else
        dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
    fi
    chown munge:munge /etc/munge/munge.key
    chmod 400 /etc/munge/munge.key
fi
if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
    say "using the munged already running"
else
    # munged runs as the munge user (it owns the key); -F keeps it in the foreground, so $! is
    # its pid. Its socket folder is on /run, which may be fresh.
    mkdir -p /run/munge /var/lib/munge /var/log/munge
    chown munge:munge /run/munge /var/lib/munge /var/log/munge
    chmod 755 /run/munge
    setpriv --reuid=munge --regid=munge --init-groups /usr/sbin/munged -F >"$tmp/munged.log" 2>&1 &
    munged_pid=$!
    for _ in $(seq 50); do
        munge -n 2>/dev/null | unmunge >/dev/null 2>&1 && break
        kill -0 "$munged_pid" 2>/dev/null || die "munged stopped: $(cat "$tmp/munged.log")"
        sleep 0.2
    done
    munge -n | unmunge >/dev/null || die "munged doesn't answer"
    say "started munged (pid $munged_pid)"
fi

# --- slurm.conf --------------------------------------------------------------------------------
for port in "$ctld_port" "$slurmd_port"; do
    if (: <"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then
        die "port $port is in use; choose others with CHECK_SLURMCTLD_PORT and CHECK_SLURMD_PORT"
    fi
done
node="$(hostname -s)"
cpus="$(nproc)"
# A bit less than the memory there is: slurmd drains a node that has less than RealMemory.
memory="$(free -m | awk '/^Mem:/ { print int($2 * 0.9) }')"
mkdir -p "$tmp/state" "$tmp/spool" "$tmp/out"
cat >"$SLURM_CONF" <<EOF
# A one-node cluster for scripts/slurm/check.sh.
ClusterName=sppm-check
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
# No cgroups: processes are tracked by their parents, and tasks aren't bound to CPUs.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
# CPUs are the consumable resource: 1-CPU tasks on a $cpus-CPU node run $cpus at a time.
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
# Keep finished jobs' records an hour, for scontrol show job.
MinJobAge=3600
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF

# --- daemons -----------------------------------------------------------------------------------
slurmctld -D -f "$SLURM_CONF" >"$tmp/slurmctld.stderr" 2>&1 &
ctld_pid=$!
slurmd -D -f "$SLURM_CONF" >"$tmp/slurmd.stderr" 2>&1 &
slurmd_pid=$!
say "started slurmctld (pid $ctld_pid) and slurmd (pid $slurmd_pid); SLURM_CONF=$SLURM_CONF"

state=""
for i in $(seq 120); do
    kill -0 "$ctld_pid" 2>/dev/null || die "slurmctld stopped: $(tail -n 5 "$tmp/slurmctld.stderr")"
    kill -0 "$slurmd_pid" 2>/dev/null || die "slurmd stopped: $(tail -n 5 "$tmp/slurmd.stderr")"
    state="$(sinfo -h -n "$node" -o %t 2>/dev/null || true)"
    case "$state" in
    idle | mix | alloc) break ;;
    down* | drain* | drng*)
        # Every 5 tries, in case the node registers in between.
        if ((i % 5 == 0)); then
            scontrol update nodename="$node" state=resume 2>/dev/null || true
        fi
        ;;
    esac
    sleep 0.5
done
[[ "$state" == idle ]] || die "node $node is '${state:-unknown}', not idle"
say "node $node is idle: $cpus CPUs, ${memory} MB"
sinfo

# --- the render as an array and a merge ---------------------------------------------------------
out="$tmp/out"
say "submitting: $passes passes in $batches batches, ${render_options[*]}"
t0="$(now)"
ids="$(SPPM_GPU="$bin" bash scripts/slurm/submit.sh "$scene" "$passes" "$batches" "$out" \
    "$out/merged.exr" "${render_options[@]}")"
echo "$ids"
render_job="$(sed -n 's/^render_job=//p' <<<"$ids")"
merge_job="$(sed -n 's/^merge_job=//p' <<<"$ids")"
[[ -n "$render_job" && -n "$merge_job" ]] || die "submit.sh printed no job ids"

# Wait until neither job is in the queue, showing the queue when it changes. A merge whose
# dependency can never be satisfied is cancelled (--kill-on-invalid-dep), so this ends.
last=""
while true; do
    queue="$(squeue -h -j "$render_job,$merge_job" -o '%i %j %T %R' 2>/dev/null || true)"
    [[ -n "$queue" ]] || break
    if [[ "$queue" != "$last" ]]; then
        echo "[$(elapsed "$t0" "$(now)") s]"
        while read -r line; do echo "    $line"; done <<<"$queue"
        last="$queue"
    fi
    awk -v a="$t0" -v b="$(now)" -v t="$timeout" 'BEGIN { exit !(b - a > t) }' &&
        die "the jobs took more than $timeout s (CHECK_TIMEOUT)"
    sleep 0.5
done
t1="$(now)"
array_time="$(elapsed "$t0" "$t1")"

# Every task's and the merge's state and exit code, from the job records (kept by MinJobAge).
failed=0
lines=()
echo "job records:"
records="$(scontrol -o show job "$render_job"; scontrol -o show job "$merge_job")"
while read -r record; do
    [[ -n "$record" ]] || continue
    # "JOB_TASK" for an array task, "JOB" for the merge.
    id="$(grep -o 'JobId=[0-9]*' <<<"$record" | head -n 1 | cut -d= -f2)"
    array_id="$(grep -o 'ArrayJobId=[0-9]*' <<<"$record" | cut -d= -f2 || true)"
    task="$(grep -o 'ArrayTaskId=[0-9]*' <<<"$record" | cut -d= -f2 || true)"
    [[ -z "$task" ]] || id="${array_id}_$task"
    name="$(grep -o 'JobName=[^ ]*' <<<"$record")"
    job_state="$(grep -o 'JobState=[A-Z_]*' <<<"$record")"
    exit_code="$(grep -o ' ExitCode=[0-9:]*' <<<"$record" | tr -d ' ')"
    run_time="$(grep -o 'RunTime=[0-9:-]*' <<<"$record")"
    lines+=("    $id $name $job_state $exit_code $run_time")
    [[ "$job_state" == JobState=COMPLETED && "$exit_code" == ExitCode=0:0 ]] || failed=1
done <<<"$records"
printf '%s\n' "${lines[@]}" | sort -V
show_job_logs
((failed == 0)) || die "a job didn't complete"
[[ -f "$out/merged.exr" ]] || die "the merge wrote no $out/merged.exr"

# --- the same passes in one process -------------------------------------------------------------
say "rendering the same $passes passes in one process"
t2="$(now)"
"$bin" "$scene" --radius-schedule global --iterations "$passes" "${render_options[@]}" \
    -o "$out/whole.exr"
t3="$(now)"
whole_time="$(elapsed "$t2" "$t3")"

diff_line="$("$bin" diff "$out/merged.exr" "$out/whole.exr")"
echo "diff merged whole: $diff_line"
rel_mse="$(awk '{ for (i = 1; i < NF; i++) if ($i == "relMSE") print $(i + 1) }' <<<"$diff_line")"
rmse="$(awk '{ for (i = 1; i < NF; i++) if ($i == "RMSE") print $(i + 1) }' <<<"$diff_line")"
[[ -n "$rel_mse" && -n "$rmse" ]] || die "can't read relMSE and RMSE from sppm-gpu diff"

echo
echo "array ($batches tasks, 1 CPU each) + merge, submission to merged image: $array_time s"
echo "one process ($cpus CPUs):                                               $whole_time s"
if awk -v r="$rmse" -v m="$rel_mse" 'BEGIN { exit !(r < 1e-5 && m < 1e-9) }'; then
    echo "PASS: the Slurm array's merged image equals the one-process render (relMSE $rel_mse, RMSE $rmse)"
else
    die "the merged image differs from the one-process render (relMSE $rel_mse, RMSE $rmse)"
fi

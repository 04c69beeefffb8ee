#!/usr/bin/env bash
# flapwing on a real (single-node) Slurm cluster: starts one with cluster.sh, then
#  1. a 4-task array sweep via `flapwing submit` merges to exactly the unsharded table;
#  2. with one task cancelled (scancel of a pending array element), `merge` and `status` report
#     that shard missing, the resubmit command merge prints is run, and the merge then equals
#     the unsharded table byte for byte;
#  3. throughput: one shard run directly and as a Slurm task, interleaved, a few repeats;
#  4. a study with a failed case (the RoboBee sweep of issue #40): every task completes and
#     its log lists its failed cases, `status` counts the shards done and lists the failed
#     cases, and the merge keeps the failed row and equals the unsharded table.
# Outputs are checked, not exit codes (a job can end COMPLETED without having run). The
# daemons are stopped at the end, also on failure. Needs root (installs slurm-wlm and munge
# when missing). FLAPWING_BIN names the binary (default target/release/flapwing).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${FLAPWING_BIN:-$root/target/release/flapwing}
[[ -x $bin ]] || {
    echo "test_cluster: no flapwing binary at $bin (build it, or set FLAPWING_BIN)" >&2
    exit 1
}
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
work=$(mktemp -d /tmp/flapwing-slurm-test.XXXXXX)
export FLAPWING_SLURM_DIR=$work/cluster
export SLURM_CONF=$FLAPWING_SLURM_DIR/slurm.conf
jobs=()
ok=0

cleanup() {
    if ((${#jobs[@]})); then scancel "${jobs[@]}" 2>/dev/null || true; fi
    "$root/scripts/slurm/cluster.sh" stop || true
    if ((ok)); then
        rm -rf "$work"
    else
        echo "test_cluster: FAILED; files kept in $work" >&2
    fi
}
trap cleanup EXIT

fail() {
    echo "test_cluster: FAIL: $*" >&2
    exit 1
}
step() { printf '\n== %s\n' "$*"; }

# The job id of the latest submission recorded in a manifest.
last_job() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["submissions"][-1]["job_id"])' "$1"; }

# Waits until job $1 has left the queue (at most $2 s).
wait_job() {
    local deadline=$((SECONDS + ${2:-120}))
    while [[ -n $(squeue -h -j "$1" 2>/dev/null) ]]; do
        ((SECONDS < deadline)) || fail "job $1 still queued after ${2:-120} s: $(squeue -h -r -j "$1")"
        sleep 0.2
    done
}

"$root/scripts/slurm/cluster.sh" start

study=$work/study.toml
cp "$root/examples/studies/drosophila_amplitude_aoa.toml" "$study"
name=drosophila_amplitude_aoa
"$bin" sweep "$study" --out "$work/whole" >/dev/null
whole=$work/whole/$name.csv
[[ $(wc -l <"$whole") == 21 ]] || fail "unsharded table: $(wc -l <"$whole") lines, expected 21"

step "1. a 4-task job array merges to the unsharded table"
"$bin" submit "$study" --out "$work/a" --shards 4 --time 00:05:00
job=$(last_job "$work/a/$name.slurm.json")
jobs+=("$job")
wait_job "$job"
for k in 1 2 3 4; do
    [[ -s $work/a/$name-shard-$k-of-4.csv ]] || fail "job $job: shard $k was not written ($(cat "$work"/a/slurm/*_$k.out 2>/dev/null))"
done
"$bin" status "$work/a"
"$bin" sweep merge "$work/a"
cmp "$work/a/$name.csv" "$whole" || fail "the merged table differs from the unsharded one"
echo "merged table equals the unsharded one (cmp)"

step "2. a cancelled task is reported missing, resubmitted, and the merge completes"
# With --throttle 1 only task 1 runs at first; task 3 is still pending when cancelled.
"$bin" submit "$study" --out "$work/b" --shards 4 --throttle 1
job=$(last_job "$work/b/$name.slurm.json")
jobs+=("$job")
# Before the cancel, squeue has every shard: task 1 pending or running, the others pending.
"$bin" status "$work/b" --json >"$work/status0.json"
python3 - "$work/status0.json" <<'EOF' || fail "status right after submit does not show the queued tasks"
import json, sys
s = json.load(open(sys.argv[1]))["studies"][0]
assert sorted(s["done"] + s["running"] + s["pending"]) == [1, 2, 3, 4], s
assert 3 in s["pending"] and 4 in s["pending"] and s["missing"] == [], s
EOF
scancel "${job}_3"
wait_job "$job"
[[ ! -e $work/b/$name-shard-3-of-4.csv ]] || fail "shard 3 exists although its task was cancelled"
if "$bin" sweep merge "$work/b" >"$work/merge.out" 2>"$work/merge.err"; then
    fail "merge succeeded with shard 3 missing"
fi
cat "$work/merge.err"
grep -q "missing shard(s) 3$" "$work/merge.err" || fail "merge does not list shard 3 as missing"
resubmit=$(grep -A1 "resubmit just those with:" "$work/merge.err" | tail -n 1 | sed 's/^ *//')
[[ $resubmit == "flapwing submit $study --out $work/b --shards 4 --only 3" ]] ||
    fail "unexpected resubmit command: $resubmit"
"$bin" status "$work/b" | tee "$work/status.txt"
"$bin" status "$work/b" --json >"$work/status.json"
python3 - "$work/status.json" <<'EOF' || fail "status --json does not report shard 3 missing"
import json, sys
s = json.load(open(sys.argv[1]))["studies"][0]
assert s["done"] == [1, 2, 4] and s["missing"] == [3], s
assert s["running"] == [] and s["pending"] == [], s
assert "squeue" in s["sources"], s
EOF
grep -Eq '^  missing +1  3$' "$work/status.txt" || fail "status text does not list shard 3 as missing"
echo "running the printed command: $resubmit"
eval "\"\$bin\" ${resubmit#flapwing }"
job=$(last_job "$work/b/$name.slurm.json")
jobs+=("$job")
wait_job "$job"
"$bin" sweep merge "$work/b"
cmp "$work/b/$name.csv" "$whole" || fail "the merged table after the resubmission differs from the unsharded one"
"$bin" status "$work/b" --json | python3 -c 'import json,sys; s=json.load(sys.stdin)["studies"][0]; assert s["done"]==[1,2,3,4], s' ||
    fail "status after the resubmission is not all done"
echo "merged table after the resubmission equals the unsharded one (cmp)"

step "3. throughput of one shard: direct vs as a Slurm task (--jobs 1, interleaved)"
big=$work/throughput.toml
cat >"$big" <<'EOF'
name = "throughput"
base_model = "drosophila"
design = "full_factorial"
responses = ["lift_over_weight", "aero_power_w", "lift_per_power_n_per_w", "trim_feasible"]
[[factor]]
path = "kinematics.amplitude_deg"
range = [120.0, 160.0]
count = 60
[[factor]]
path = "kinematics.mid_stroke_aoa_deg"
range = [30.0, 60.0]
count = 30
EOF
cases=600 # shard 1 of 3 of 1800 cases
repeats=${FLAPWING_SLURM_REPEATS:-4}
# "in X s" of a sweep's report: the time spent on the cases.
secs_of() { sed -nE 's/.* cases \(.*\) in ([0-9.]+) s$/\1/p' "$1" | head -n 1; }
now() { date +%s.%N; }
# Rows: repeat, mode, seconds on the cases (the sweep's own report), start and end times.
: >"$work/throughput.txt"
for i in $(seq "$repeats"); do
    t0=$(now)
    "$bin" sweep "$big" --out "$work/direct-$i" --shard 1/3 --jobs 1 >"$work/direct-$i.out"
    t1=$(now)
    s=$(secs_of "$work/direct-$i.out")
    [[ -n $s ]] || fail "no timing in $(cat "$work/direct-$i.out")"
    echo "$i direct $s $t0 $t1" >>"$work/throughput.txt"

    t0=$(now)
    "$bin" submit "$big" --out "$work/slurm-$i" --shards 3 --only 1 >/dev/null
    job=$(last_job "$work/slurm-$i/throughput.slurm.json")
    jobs+=("$job")
    shard=$work/slurm-$i/throughput-shard-1-of-3.csv
    deadline=$((SECONDS + 120))
    until [[ -e $shard ]]; do
        ((SECONDS < deadline)) || fail "task ${job}_1 wrote no shard in 120 s"
        sleep 0.05
    done
    t1=$(now)
    wait_job "$job"
    log=$work/slurm-$i/slurm/throughput-${job}_1.out
    s=$(secs_of "$log")
    [[ -n $s ]] || fail "no timing in the task's log $log: $(cat "$log")"
    cmp <(tail -n +2 "$shard") <(tail -n +2 "$work/direct-$i/throughput-shard-1-of-3.csv") ||
        fail "the Slurm task's shard differs from the direct run's"
    echo "$i slurm $s $t0 $t1" >>"$work/throughput.txt"
done
python3 - "$work/throughput.txt" "$cases" <<'EOF'
import statistics, sys
cases = int(sys.argv[2])
rows = [l.split() for l in open(sys.argv[1]).read().splitlines()]
print(f"{'repeat':<7} {'mode':<7} {'cases/s':>9} {'cases/s incl. start-up':>23}")
for r in rows:
    print(f"{r[0]:<7} {r[1]:<7} {cases / float(r[2]):9.1f} {cases / (float(r[4]) - float(r[3])):23.1f}")
def med(mode, f):
    return statistics.median(f(r) for r in rows if r[1] == mode)
run = lambda r: cases / float(r[2])
wall = lambda r: cases / (float(r[4]) - float(r[3]))
d, s = med("direct", run), med("slurm", run)
dw, sw = med("direct", wall), med("slurm", wall)
print(f"median cases/s of a task: direct {d:.1f}, as a Slurm task {s:.1f} (ratio {s / d:.3f})")
print(f"median cases/s with start-up (direct: process start to exit; Slurm: sbatch to the shard file): direct {dw:.1f}, Slurm {sw:.1f} (ratio {sw / dw:.3f})")
print("per-task throughput " + ("within" if s >= 0.9 * d else "NOT within") + " 10% of direct")
EOF

step "4. a study with a failed case: tasks complete, status and merge list it, the row is kept"
rb=$work/robobee_hinge_drive.toml
rbname=robobee_hinge_drive
cp "$root/examples/studies/$rbname.toml" "$rb"
"$bin" sweep "$rb" --out "$work/rb-whole" | tee "$work/rb-whole.out"
grep -q "^2 of 9 case(s) failed" "$work/rb-whole.out" || fail "the unsharded RoboBee sweep does not report its 2 failed cases"
"$bin" submit "$rb" --out "$work/rb" --shards 3 >/dev/null
job=$(last_job "$work/rb/$rbname.slurm.json")
jobs+=("$job")
wait_job "$job"
for k in 1 2 3; do
    [[ -s $work/rb/$rbname-shard-$k-of-3.csv ]] || fail "job $job: shard $k was not written ($(cat "$work"/rb/slurm/*_$k.out 2>/dev/null))"
done
# Cases 1 and 2 are in shard 1 (cases 0..2): that task's log lists them.
grep -q "^2 of 3 case(s) failed" "$work/rb/slurm/$rbname-${job}_1.out" ||
    fail "task ${job}_1's log does not list its failed cases: $(cat "$work/rb/slurm/$rbname-${job}_1.out")"
"$bin" status "$work/rb" | tee "$work/rb-status.txt"
grep -Eq '^  done +3  1,2,3$' "$work/rb-status.txt" || fail "status does not count the 3 shards done"
grep -q '^  failed cases in done shards: 2 (1,2;' "$work/rb-status.txt" || fail "status does not list failed cases 1 and 2"
"$bin" sweep merge "$work/rb" | tee "$work/rb-merge.out"
grep -q "^  case 1 (.*no periodic motion" "$work/rb-merge.out" || fail "merge does not list failed case 1"
grep -q "^  case 2 (.*did not settle" "$work/rb-merge.out" || fail "merge does not list failed case 2"
cmp "$work/rb/$rbname.csv" "$work/rb-whole/$rbname.csv" || fail "the merged RoboBee table differs from the unsharded one"
echo "tasks completed with the failed case in their table; the merge equals the unsharded table (cmp)"

ok=1
printf '\ntest_cluster: 4 passed, 0 failed\n'

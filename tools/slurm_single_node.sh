#!/usr/bin/env bash
# The split bake's Slurm recipe (README) on a single-node Slurm on this machine (issue 29):
# munged, slurmctld and slurmd from Debian (apt-get install slurm-wlm munge) started with a
# private configuration in a scratch folder, then a solve job, a job array of N gather shards
# after it and a merge job after them, and the merged folder compared with one bake's.
#
#   sudo tools/slurm_single_node.sh SCENE [N] [radbake options...]    (as root; default N = 3)
#
# Prints each job's id and state and whether the bytes match; exit 1 when they do not. Stops the
# Slurm daemons it started; munged, a system service, is left running (stopped and started again
# between runs, slurmd's registration was refused). RADBAKE names the program (default build/src/radbake).
set -euo pipefail
scene="$(realpath "$1")"; shift
shards="${1:-3}"; [[ $# -gt 0 ]] && shift
radbake="$(realpath "${RADBAKE:-build/src/radbake}")"
opts=("$@")
work="$(mktemp -d)"
node="$(hostname -s)"
pids=()
cleanup() {
    for pid in "${pids[@]}"; do kill "$pid" 2> /dev/null || true; done
    wait 2> /dev/null || true
    rm -rf "$work"
}
trap cleanup EXIT
mkdir -p "$work/state" "$work/spool" "$work/out"
cat > "$work/slurm.conf" << CONF
ClusterName=radbake
SlurmctldHost=$node
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=$node CPUs=$(nproc) State=UNKNOWN
PartitionName=bake Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
if ! pgrep -x munged > /dev/null; then
    mkdir -p /run/munge && chown munge:munge /run/munge
    runuser -u munge -- /usr/sbin/munged --force
fi
for _ in $(seq 30); do  # munged answers once its socket is up
    munge -n 2> /dev/null | unmunge > /dev/null 2>&1 && break
    sleep 0.5
done
/usr/sbin/slurmctld -D -f "$SLURM_CONF" > /dev/null 2>&1 & pids+=($!)
# slurmd's first registration is sometimes refused (a munge authentication error right after
# the daemons start): it is started again, up to three times, until the node is idle.
idle=no
for _ in 1 2 3; do
    /usr/sbin/slurmd -D -f "$SLURM_CONF" -N "$node" > /dev/null 2>&1 & slurmd=$!
    for _ in $(seq 20); do
        sinfo -h -o %T 2> /dev/null | grep -q idle && { idle=yes; break; }
        sleep 1
    done
    [[ $idle == yes ]] && { pids+=($slurmd); break; }
    kill "$slurmd" 2> /dev/null || true
    wait "$slurmd" 2> /dev/null || true
done
[[ $idle == yes ]] || { cat "$work/slurmctld.log" "$work/slurmd.log" >&2; exit 1; }
sinfo -h -o "%P %D %T"

# The recipe, as README gives it: each step a job, each waiting for the ones it reads.
cd "$work/out"
cp "$scene" .
name="$(basename "$scene")"
q="$(printf ' %q' "${opts[@]}")"
solve=$(sbatch --parsable -c 1 --wrap "$radbake solve $name --solution level.sol -q$q")
gather=$(sbatch --parsable -c 1 --dependency=afterok:$solve --array=1-$shards \
    --wrap "$radbake gather $name --solution level.sol --shard \${SLURM_ARRAY_TASK_ID}/$shards -o part\${SLURM_ARRAY_TASK_ID} --threads 1 -q$q")
merge=$(sbatch --parsable -c 1 --dependency=afterok:$gather --wait \
    --wrap "$radbake merge part* -q -o merged")
echo "jobs: solve $solve, gather $gather (array 1-$shards), merge $merge"
squeue -h || true
"$radbake" bake "$name" -q -o whole "${opts[@]}" > /dev/null 2>&1
same=yes
while IFS= read -r f; do
    cmp -s "whole/$f" "merged/$f" || { echo "differs: $f"; same=no; }
done < <(cd whole && find . -type f ! -name timings.json | sort)
echo "merged outputs: $([[ $same == yes ]] && echo "the same bytes as one bake (timings.json aside)" || echo DIFFER)"
[[ $same == yes ]]

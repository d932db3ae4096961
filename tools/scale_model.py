#!/usr/bin/env python3
"""A model of one bake on many nodes (issue 29): the predicted wall time of a bake on MPI ranks,
from the lead's timings.json of a bake on ranks of this machine.

    python3 tools/scale_model.py TIMINGS.json [--one T1] [--work-scale K] [--serial-scale KS]
                                 [--exchange-scale KX] [--nodes 1,8,32,128] [--ranks-per-node 2]
                                 [--latency-us A] [--bandwidth-gb-s B]

TIMINGS.json: the lead's, from `mpirun -np R radbake bake ... --threads 1` (its seconds, shared_s:
the lead's time computing its share, exchange_s: its time in exchanges, waits for slower ranks
included, exchanged_mb and exchanges). T1: the same bake's wall time in one process of one
thread, to check the model against (tools/bench_ranks.sh prints both). The scales carry the
measured scene to the one predicted, each a ratio predicted / measured: K its shared work (the
solve's loops and the read-out), KS its serial work, KX its exchanges and their bytes.

The model: the lead's serial part S = seconds - shared_s - exchange_s (what every rank does
alike: import, parts, ray caster, the solver's decisions and vector updates, assembly, writing);
the shared work W = R x shared_s; a wait for slower ranks in proportion to the share (the
measured exchange_s / shared_s, taken as constant: optimistic, as imbalance grows with ranks);
and the exchanges over a network: a latency A per round of a log2(P)-round allgather, and the
bytes a rank receives (half of the lead's sent and received) over bandwidth B. Then
T(P) = KS S + (K W / P)(1 + wait) + KX E A ceil(log2 P) + KX X / B.
"""
import argparse
import json
import math


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("timings", help="the lead's timings.json of a bake on ranks")
    p.add_argument("--one", type=float, help="the same bake in one process of one thread: wall s")
    p.add_argument("--work-scale", type=float, default=1.0)
    p.add_argument("--serial-scale", type=float, default=1.0)
    p.add_argument("--exchange-scale", type=float, default=1.0)
    p.add_argument("--nodes", default="1,8,32,128")
    p.add_argument("--ranks-per-node", type=int, default=2)
    p.add_argument("--latency-us", type=float, default=30.0, help="per allgather round (10 GbE: ~30 us)")
    p.add_argument("--bandwidth-gb-s", type=float, default=1.1, help="into a node (10 GbE: ~1.1 GB/s)")
    a = p.parse_args()

    t = json.load(open(a.timings))
    ranks = t.get("ranks", 1)
    if ranks < 2:
        raise SystemExit("%s: not a bake on ranks (no \"ranks\" above 1)" % a.timings)
    wall, shared_s, exchange_s = t["seconds"], t["shared_s"], t["exchange_s"]
    serial = wall - shared_s - exchange_s
    work = ranks * shared_s
    wait = exchange_s / shared_s if shared_s > 0 else 0.0
    print("measured on %d ranks: wall %.1f s = serial %.2f + shared %.1f + exchanges %.2f (%.1f MiB in %d)"
          % (ranks, wall, serial, shared_s, exchange_s, t["exchanged_mb"], t["exchanges"]))
    one = serial + work
    print("one process by the model: %.1f s%s" % (one, "; measured %.1f s (%+.1f %%)" % (a.one, 100 * (one / a.one - 1))
                                                   if a.one else ""))
    s, w = a.serial_scale * serial, a.work_scale * work
    received = a.exchange_scale * t["exchanged_mb"] * 1024 * 1024 / 2
    exchanges = a.exchange_scale * t["exchanges"]
    print("predicted scene: serial %.0f s, shared work %.0f s (one process %.0f s = %.1f h), %.0f exchanges, "
          "%.1f GB received per rank" % (s, w, s + w, (s + w) / 3600, exchanges, received / 1e9))
    print("| nodes | ranks | serial s | shared s (waits included) | exchange latency s | exchange bytes s | wall s | speed-up |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for nodes in (int(n) for n in a.nodes.split(",")):
        p_ranks = nodes * a.ranks_per_node
        share = w / p_ranks * (1 + wait) if p_ranks > 1 else w
        rounds = math.ceil(math.log2(p_ranks)) if p_ranks > 1 else 0
        latency = exchanges * a.latency_us * 1e-6 * rounds if nodes > 1 else 0.0
        volume = received / (a.bandwidth_gb_s * 1e9) if nodes > 1 else 0.0
        total = s + share + latency + volume
        print("| %d | %d | %.0f | %.0f | %.1f | %.1f | %.0f | %.1f |"
              % (nodes, p_ranks, s, share, latency, volume, total, (s + w) / total))


if __name__ == "__main__":
    main()

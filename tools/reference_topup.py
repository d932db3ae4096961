#!/usr/bin/env python3
"""Tops up a per-vertex Monte Carlo reference where it is noisier than asked (issue 13's yardstick).

    python3 tools/reference_topup.py SCENE PROBES REFERENCE.csv --samples N [--max-se 0.005]
                                     [--lit max|median] [--threads 0] [--seed 11]
                                     [--reference-mc build/tools/reference_mc] -o OUT.csv

REFERENCE.csv is `reference_mc SCENE PROBES --samples N` (tools/vertex_reference.sh writes one).
Issue 13 asks for "at least enough paths for 0.5 % per-vertex noise", but one path count for every
probe leaves the dim ones far noisier: at 65,536 paths the tessellated Cornell box's RMS noise is
0.55 %, yet the ceiling right above its lamp, lit only through a 1 cm gap, is at 4-10 % per vertex.
Every lit probe (vertex_error.py's rule) whose relative standard error of the grey (the mean of the
channels' errors over the grey) is above --max-se gets more paths, as many as the 1/sqrt(paths) law
says it needs, rounded up to a power of two times 4096 (one reference_mc run per such count, each
with its own seed, so no path is drawn twice); the estimates are pooled by their path counts:
mean = (n1 m1 + n2 m2) / (n1 + n2), standard error = sqrt(n1^2 se1^2 + n2^2 se2^2) / (n1 + n2).
Rows are written in REFERENCE.csv's order and format. Python standard library only.
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import read_csv_rows  # noqa: E402
import vertex_error  # noqa: E402

CHANNELS = ("r", "g", "b")
ERRORS = ("se_r", "se_g", "se_b")


def relative_se(row):
    grey = vertex_error.grey(row)
    return sum(float(row[k]) for k in ERRORS) / 3.0 / grey if grey > 0.0 else 0.0


def probe_lines(path):
    """The probe lines of a probe file (comments and blank lines dropped), in order."""
    with open(path) as f:
        return [line for line in f if line.partition("#")[0].strip()]


def pooled(row, n0, extra_row, n1):
    out = dict(row)
    for c, e in zip(CHANNELS, ERRORS):
        out[c] = "%.9g" % ((n0 * float(row[c]) + n1 * float(extra_row[c])) / (n0 + n1))
        out[e] = "%.3g" % (math.sqrt((n0 * float(row[e])) ** 2 + (n1 * float(extra_row[e])) ** 2) / (n0 + n1))
    return out


def main(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene")
    p.add_argument("probes", help="the probe file REFERENCE.csv was made from")
    p.add_argument("reference", help="reference_mc's CSV for it")
    p.add_argument("--samples", type=int, required=True, help="the paths per probe REFERENCE.csv was made with")
    p.add_argument("--max-se", type=float, default=0.005, help="relative standard error to reach on lit probes")
    p.add_argument("--lit", choices=("max", "median"), default="median")
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--seed", type=int, default=11, help="seed of the first top-up run (then +1 per run)")
    p.add_argument("--reference-mc", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build",
                                                           "tools", "reference_mc"))
    p.add_argument("-o", "--out", required=True)
    args = p.parse_args(argv[1:])

    rows = read_csv_rows(args.reference)
    lines = probe_lines(args.probes)
    if len(lines) != len(rows):
        sys.stderr.write("reference_topup: error: %s has %d probes, %s %d rows\n" % (
            args.probes, len(lines), args.reference, len(rows)))
        return 1
    mask, _ = vertex_error.lit_mask(rows, args.lit)
    # Probes by the paths they still need, rounded up to 4096 x a power of two.
    runs = {}
    for i, (row, lit) in enumerate(zip(rows, mask)):
        rel = relative_se(row)
        if not lit or rel <= args.max_se:
            continue
        extra = args.samples * ((rel / args.max_se) ** 2 - 1.0)
        runs.setdefault(4096 * 2 ** max(0, math.ceil(math.log2(extra / 4096.0))), []).append(i)
    out = list(rows)
    with tempfile.TemporaryDirectory() as work:
        for k, (extra, indices) in enumerate(sorted(runs.items())):
            probe_file, csv_file = os.path.join(work, "p%d.probes" % k), os.path.join(work, "r%d.csv" % k)
            with open(probe_file, "w") as f:
                f.writelines(lines[i] if lines[i].endswith("\n") else lines[i] + "\n" for i in indices)
            sys.stderr.write("reference_topup: %d probes, %d more paths each\n" % (len(indices), extra))
            subprocess.run([args.reference_mc, args.scene, probe_file, "--samples", str(extra), "--threads",
                            str(args.threads), "--seed", str(args.seed + k), "-o", csv_file], check=True)
            for i, extra_row in zip(indices, read_csv_rows(csv_file)):
                if not vertex_error.same_position(extra_row, rows[i]):
                    sys.stderr.write("reference_topup: error: probe %d moved between the runs\n" % i)
                    return 1
                out[i] = pooled(rows[i], args.samples, extra_row, extra)
    columns = list(rows[0].keys())
    tmp = args.out + ".tmp"
    with open(tmp, "w", newline="\n") as f:
        f.write(",".join(columns) + "\n")
        for row in out:
            f.write(",".join(str(row[c]) for c in columns) + "\n")
    os.replace(tmp, args.out)
    noisy = sum(1 for row, lit in zip(out, mask) if lit and relative_se(row) > args.max_se * 1.05)
    sys.stderr.write("reference_topup: %s: %d probes topped up in %d runs; RMS relative standard error %.3f %%, "
                     "%d lit probes still above %.2f %% (+5 %%)\n" % (
                         args.out, sum(len(v) for v in runs.values()), len(runs),
                         100 * vertex_error.reference_noise(out, mask), noisy, 100 * args.max_se))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

#!/usr/bin/env python3
"""How far the solve's progress lines were from the truth.

Reads the stderr of `radbake solve|bake SCENE ... 2> LOG` (progress as lines: stderr not a
terminal, no --quiet) and, for each line that gives the solve's fraction and time left
("; the solve N %, about T left"), compares them with what the run then did: the solve runs
from the end of `import` to the end of its last phase. Prints the lines nearest to 25 % and
50 % of the solve's wall time (issue 28: the time left within 2 x at 25 %, within 30 % at 50 %)
and, with --all, every line.

    radbake solve b1m.wrl --solution b1m.sol --threads 2 2> b1m.log
    python3 tools/progress_check.py b1m.log
"""
import argparse
import re
import sys

LINE = re.compile(r"^radbake: (?P<phase>.+?) (?:\d+ %|done in).*\(total (?P<total>[^)]+)\)")
STAGE = re.compile(r"; the solve (?P<percent>\d+) %, about (?P<left>.+?) left")


def seconds(text):
    text = text.strip()
    m = re.fullmatch(r"(\d+) min (\d+) s", text)
    if m:
        return 60.0 * int(m.group(1)) + int(m.group(2))
    m = re.fullmatch(r"([\d.]+) s", text)
    if m:
        return float(m.group(1))
    raise ValueError(f"not a duration: {text!r}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("log")
    parser.add_argument("--all", action="store_true", help="every line with the solve's estimate")
    args = parser.parse_args()

    start = None
    end = None
    said = []  # (total seconds, fraction, seconds left, phase)
    with open(args.log, encoding="utf-8", errors="replace") as f:
        for raw in f:
            m = LINE.match(raw.strip())
            if not m:
                continue
            total = seconds(m.group("total"))
            if m.group("phase") == "import" and "done in" in raw:
                start = total
            s = STAGE.search(raw)
            if s:
                said.append((total, int(s.group("percent")) / 100.0, seconds(s.group("left")), m.group("phase")))
                if "done in" in raw:
                    end = total
    if start is None or end is None or not said:
        sys.exit(f"{args.log}: no import line or no line with the solve's estimate")
    wall = end - start
    print(f"solve: {wall:.1f} s wall (from {start:.1f} s to {end:.1f} s)")

    def row(t, fraction, left, phase):
        true_left = end - t
        true_fraction = (t - start) / wall
        ratio = left / true_left if true_left > 0 else float("nan")
        return (f"  at {t:8.1f} s ({100 * true_fraction:5.1f} % of the solve, in {phase}): said {100 * fraction:3.0f} %, "
                f"{left:7.1f} s left; truly {true_left:7.1f} s left: {ratio:5.2f} x")

    for target in (0.25, 0.5):
        t = start + target * wall
        before = [x for x in said if x[0] <= t]
        after = [x for x in said if x[0] > t]
        print(f"nearest lines to {100 * target:.0f} % of the solve ({t:.1f} s):")
        for x in (before[-1:] + after[:1]):
            print(row(*x))
    if args.all:
        print("every line:")
        for x in said:
            print(row(*x))


if __name__ == "__main__":
    main()

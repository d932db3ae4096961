#!/usr/bin/env python3
"""ctest `targets_script`: tools/targets.py reads what the programs write and judges its table
right, on fabricated timings.json / stats.json and fabricated program output (no benchmark runs,
nothing is timed; under a second).

    python3 tools/test_targets.py

- a cost per point is the phase's wall time over stats.json's covered_texels / vertices, and the
  solve is every phase up to the last `solve*` one (issue 12's "phases up to the last solve");
- bench_solver's, bench_scale.sh's, bench_reconstruct's and doctest's printed tables parse, and
  the ladder's growth is 200k over 20k;
- every comparison judges as it says, a missing figure is "not measured" and never "met", and
  medians over runs are taken per figure (element-wise for lists);
- the targets table is well formed: every row names a measurement that exists, open rows come
  from the open issues 27, 28 and 29, and a measurement used by several rows runs once, N times;
- the printed table holds each row's figure, target, verdict and command.
Python standard library only.
"""
import io
import json
import os
import sys
import tempfile
import unittest
from contextlib import redirect_stdout

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import targets  # noqa: E402

TIMINGS = {
    "generator": "radbake 0.1.0", "scene": "x.wrl", "seconds": 10.0,
    "phases": {"import": 0.5, "parts": 0.1, "elements": 0.1, "direct light": 0.0, "links": 2.0, "solve": 0.5,
               "links (deferred)": 0.3, "solve (deferred)": 0.5, "links 2": 1.0, "solve 2": 1.0,
               "vertices": 0.8, "lightmaps": 2.4, "write": 0.3},
    "peak_rss_mb": 120.5, "threads": 2}
STATS = {"elements": 100, "links": 1000, "vertices": 4000, "covered_texels": 80000, "lightmaps": True}

BENCH_SOLVER = """\
mode   thr  median_s elements   leaves     links   shafts  occluded   rays iters   rss_mb
aabb     2     2.512    21234    15000    242000   100000         0 1234567    26    250.5  (runs: 2.512; cluster links 1, element links 2, clusters 3, cluster rays 4)
exact    2     2.901    21000    14900    230000   120000       500 1200000    26    260.0  (runs: 2.901; cluster links 1, element links 2, clusters 3, cluster rays 4)
"""

BENCH_SCALE = """\
| scene | triangles | median_s | links | rays | rss_mb | status |
|---|---:|---:|---:|---:|---:|---|
| building_20k | 19808 | 10.0 | 568000 | 1000 | 100.0 | ok |
| building_200k | 192710 | 150.0 | 5860000 | 9000 | 800.0 | ok |
| building_1m | 969156 | - | - | - | 4000.0 | timeout (1800 s) after 1800.2 s |
"""

DOCTEST = """\
===============================================================================
[doctest] test cases: 5 | 4 passed | 1 failed | 40 skipped
[doctest] assertions: 30 | 29 passed | 1 failed |
"""

RECONSTRUCT = """\
links adaptive: 530.7 us per covered texel (cpu 172.2; tolerance 0.02, 6696 evaluated)
error links all:      rms 0.0066 worst 0.2911
error links adaptive: rms 0.0073 worst 0.2911
"""


def write_bake(folder, timings=TIMINGS, stats=STATS):
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "timings.json"), "w") as f:
        json.dump(timings, f)
    with open(os.path.join(folder, "stats.json"), "w") as f:
        json.dump(stats, f)


class Parsing(unittest.TestCase):
    def test_bake_figures(self):
        with tempfile.TemporaryDirectory() as tmp:
            write_bake(tmp)
            fig = targets.bake_figures(tmp)
        solve = 0.5 + 0.1 + 0.1 + 0.0 + 2.0 + 0.5 + 0.3 + 0.5 + 1.0 + 1.0  # up to "solve 2"
        self.assertAlmostEqual(fig["solve_s"], solve)
        self.assertAlmostEqual(fig["us_per_texel"], 1e6 * 2.4 / 80000)  # 30 us
        self.assertAlmostEqual(fig["us_per_vertex"], 1e6 * 0.8 / 4000)  # 200 us
        self.assertAlmostEqual(fig["vertices_over_solve"], 0.8 / solve)
        self.assertAlmostEqual(fig["lightmaps_over_solve"], 2.4 / solve)
        self.assertEqual(fig["seconds"], 10.0)
        self.assertEqual(fig["peak_mb"], 120.5)

    def test_bake_without_lightmaps_has_no_texel_cost(self):
        timings = json.loads(json.dumps(TIMINGS))
        del timings["phases"]["lightmaps"]
        with tempfile.TemporaryDirectory() as tmp:
            write_bake(tmp, timings, dict(STATS, covered_texels=0, lightmaps=False))
            fig = targets.bake_figures(tmp)
        self.assertNotIn("us_per_texel", fig)
        self.assertIn("us_per_vertex", fig)

    def test_solve_needs_a_solve_phase(self):
        with self.assertRaises(ValueError):
            targets.solve_seconds({"import": 1.0, "vertices": 2.0})
        self.assertAlmostEqual(targets.solve_seconds({"import": 1.0, "solve": 2.0, "vertices": 5.0}), 3.0)

    def test_bench_solver(self):
        table = targets.parse_bench_solver(BENCH_SOLVER)
        self.assertEqual(sorted(table), ["aabb", "exact"])
        self.assertEqual(table["aabb"]["median_s"], 2.512)
        self.assertEqual(table["exact"]["links"], 230000)
        self.assertEqual(table["exact"]["rss_mb"], 260.0)
        with self.assertRaises(ValueError):
            targets.parse_bench_solver("unknown option --x\n")

    def test_bench_scale_and_growth(self):
        rows = targets.parse_bench_scale(BENCH_SCALE)
        self.assertEqual(rows["building_200k"]["median_s"], 150.0)
        self.assertIsNone(rows["building_1m"]["median_s"])
        self.assertTrue(rows["building_1m"]["status"].startswith("timeout"))
        fig = targets.ladder_figures(rows)
        self.assertAlmostEqual(fig["time_growth"], 15.0)
        self.assertAlmostEqual(fig["memory_growth"], 8.0)
        self.assertEqual(fig["b200k_s"], 150.0)
        self.assertNotIn("b1m_s", fig)  # a timed-out 1M building has no figure: "not measured"

    def test_doctest_and_reconstruct(self):
        self.assertEqual(targets.parse_doctest(DOCTEST), (5, 1))
        with self.assertRaises(ValueError):
            targets.parse_doctest("Segmentation fault")
        fig = targets.parse_bench_reconstruct(RECONSTRUCT)
        self.assertAlmostEqual(fig["rms"], 0.73)
        self.assertAlmostEqual(fig["worst"], 29.11)


class Judging(unittest.TestCase):
    def test_comparisons(self):
        j = targets.judge
        self.assertTrue(j(50.0, "<=", 50.0))
        self.assertFalse(j(50.1, "<=", 50.0))
        self.assertTrue(j(31.0, ">=", 30.0))
        self.assertTrue(j(0, "==", 0))
        self.assertFalse(j(1, "==", 0))
        self.assertTrue(j(-0.33, "|x|<=", 0.43))
        self.assertFalse(j(-0.5, "|x|<=", 0.43))
        self.assertTrue(j([3.0, 0.8, 0.65], "nonincreasing", None))
        self.assertTrue(j([3.0, 3.0, 0.65], "nonincreasing", None))
        self.assertFalse(j([3.0, 0.8, 0.9], "nonincreasing", None))
        self.assertTrue(j([1.0, 2.0, 5.0], "nondecreasing", None))
        self.assertFalse(j([1.0, 0.9, 5.0], "nondecreasing", None))
        self.assertIsNone(j(None, "<=", 1.0))

    def test_medians(self):
        runs = [{"s": 3.0, "l": [1.0, 5.0], "n": "a"}, {"s": 1.0, "l": [3.0, 1.0], "n": "b"},
                {"s": 2.0, "l": [2.0, 3.0], "n": "c"}]
        m = targets.median_figures(runs)
        self.assertEqual(m["s"], 2.0)
        self.assertEqual(m["l"], [2.0, 3.0])
        self.assertEqual(m["n"], "c")

    def test_rows_and_table(self):
        rows_in = [("texel cost", 27, "open", "quick", "m1", "us", "<=", 30.0),
                   ("vertex cost", 12, "met", "quick", "m1", "uv", "<=", 50.0),
                   ("solve", 28, "open", "quick", "m2", "s", "<=", 3.0)]
        results = {"m1": {"figures": {"us": 25.0, "uv": 80.0}, "commands": ["radbake bake a|b"],
                          "cpu": [{"command": "radbake", "wall_s": 2.0, "cpu_s": 3.0}]},
                   "m2": {"error": "house.wrl missing", "commands": [], "cpu": []}}
        rows = targets.table_rows(rows_in, results)
        self.assertEqual([r["met"] for r in rows], [True, False, None])
        text = targets.format_table(rows)
        lines = text.splitlines()
        self.assertEqual(len(lines), 2 + 3)
        self.assertIn("| texel cost | 27 (open) | 25.0 | <= 30.0 | yes | 1.50 |", lines[2])
        self.assertIn("| 80.0 | <= 50.0 | **no** |", lines[3])
        self.assertIn("radbake bake a\\|b", lines[3])  # a | in a command does not break the table
        self.assertIn("house.wrl missing", lines[4])
        self.assertIn("not measured", lines[4])

    def test_number_format(self):
        self.assertEqual(targets.fmt_number(300000), "300,000")
        self.assertEqual(targets.fmt_number(2.28e-05), "2.28e-05")
        self.assertEqual(targets.fmt_number([3.0, 0.8]), "3.00 / 0.8")
        self.assertEqual(targets.fmt_target("|x|<=", 0.5), "|x| <= 0.5")


class Table(unittest.TestCase):
    def test_targets_are_well_formed(self):
        issues = {2, 3, 4, 6, 11, 12, 13, 27, 28, 29, 30, 33}
        seen = set()
        for row in targets.TARGETS:
            self.assertEqual(len(row), 8, row)
            name, issue, state, mode, measurement, figure, comparison, threshold = row
            self.assertIn(issue, issues, name)
            self.assertIn(state, ("met", "open"), name)
            self.assertEqual(state == "open", issue in (27, 28, 29), name)
            self.assertIn(mode, ("quick", "long"), name)
            self.assertIn(measurement, targets.MEASUREMENTS, name)
            self.assertIn(comparison, ("<=", ">=", "==", "|x|<=", "nonincreasing", "nondecreasing"), name)
            self.assertEqual(threshold is None, comparison in ("nonincreasing", "nondecreasing"), name)
            self.assertNotIn((name, issue), seen, "duplicate row")
            seen.add((name, issue))
        quick = targets.selected_targets(False)
        self.assertTrue(quick and all(t[3] == "quick" for t in quick))
        self.assertGreater(len(targets.selected_targets(True)), len(quick))
        for measurement in targets.needed_measurements(quick):
            for need in targets.MEASUREMENTS[measurement][2]:
                self.assertNotIn("graz", need)  # quick mode never bakes the long scenes

    def test_a_measurement_runs_once_per_run_and_derived_ones_after(self):
        calls = []

        def fake(r):
            calls.append(1)
            return {"x": float(len(calls))}

        saved = dict(targets.MEASUREMENTS)
        try:
            targets.MEASUREMENTS["fake"] = (fake, False, [])
            targets.MEASUREMENTS["fake_derived"] = (lambda r, res: {"y": res["fake"]["figures"]["x"] * 2}, True,
                                                    ["fake"])
            rows = [("a", 27, "open", "quick", "fake", "x", "<=", 5.0),
                    ("b", 27, "open", "quick", "fake", "x", "<=", 1.0),
                    ("c", 28, "open", "quick", "fake_derived", "y", "<=", 5.0)]
            names = targets.needed_measurements(rows)
            self.assertEqual(names, ["fake", "fake_derived"])

            class R:
                commands, cpu = [], []
            err = io.StringIO()
            old, sys.stderr = sys.stderr, err
            try:
                results = targets.measure_all(R(), names, 3)
            finally:
                sys.stderr = old
            self.assertEqual(len(calls), 3)  # 3 runs of one measurement, though two rows use it
            self.assertEqual(results["fake"]["figures"]["x"], 2.0)  # the median of 1, 2, 3
            self.assertEqual(results["fake_derived"]["figures"]["y"], 4.0)
            self.assertEqual([r["met"] for r in targets.table_rows(rows, results)], [True, False, True])
        finally:
            targets.MEASUREMENTS.clear()
            targets.MEASUREMENTS.update(saved)

    def test_a_cached_reference_is_reused(self):
        # The generator's OBJ names its MTL: the check must not see a rename as a new box (it once
        # did, and deleted an hour's reference).
        import argparse
        import subprocess
        with tempfile.TemporaryDirectory() as tmp:
            box = os.path.join(tmp, "cache", "box")
            os.makedirs(box)
            subprocess.run([sys.executable, os.path.join(HERE, "gen_cornell_tessellated.py"),
                            os.path.join(box, "box.obj")], stdout=subprocess.DEVNULL, check=True)
            for name, text in (("vertices.probes", "0 0 0 0 1 0\n"), ("reference.csv", "x\n"),
                               ("reference.samples", "65536\n")):
                with open(os.path.join(box, name), "w") as f:
                    f.write(text)
            args = argparse.Namespace(build=tmp, scenes=tmp, cache=os.path.join(tmp, "cache"), work=None,
                                      ref_samples=65536, ref_max_se=0.0, no_reference_build=False)
            runner = targets.Runner(args)

            def no_run(*a, **k):
                raise AssertionError("the cached reference was rebuilt")
            runner.run = no_run
            runner.python_tool = no_run
            self.assertEqual(runner.box_reference()[2], os.path.join(box, "reference.csv"))
            args.ref_max_se = 0.005  # no topped-up reference cached: without building, none
            args.no_reference_build = True
            self.assertIsNone(runner.box_reference()[2])
            self.assertTrue(os.path.isfile(os.path.join(box, "reference.csv")))

    def test_list(self):
        out = io.StringIO()
        with redirect_stdout(out):
            self.assertEqual(targets.main(["targets.py", "--list"]), 0)
        self.assertEqual(len(out.getvalue().strip().splitlines()), 2 + len(targets.TARGETS))


if __name__ == "__main__":
    unittest.main()

#!/usr/bin/env python3
"""Targets that stay met (issue 27): re-runs the benchmark behind every numeric target still in
force and prints each figure beside its target.

    python3 tools/targets.py --quick|--long [--build DIR] [--scenes DIR] [--runs N] [--json OUT]
                             [--cache DIR] [--work DIR] [--only SUBSTRING] [--list]

--quick  about ten minutes on a 2-core machine once the tessellated box's reference is cached:
         the tessellated Cornell box (vertex accuracy at draft / medium / high and the lightmap at
         its vertices against a path-traced reference, its vertex cost, its solve), the shipped
         cornell_box.wrl's cost per texel, house.wrl's cost per vertex and solve,
         CornellBox-Water's and CornellBox-Sphere's, Duplex, the paper scenes' probe errors, the
         analytic scenes and the closed-form tests.
--long   adds graz.wrl, office.wrl, the classroom, the scale ladder's buildings (20k, 200k, 1M:
         tools/bench_scale.sh), the VRML reader's speed and the occlusion property benchmark:
         a few hours.
--build DIR    a build of radbake with its tools and tests (default build/).
--scenes DIR   the shared real scenes (default ../shared/scenes, beside the repository).
--cache DIR    where the tessellated box's reference (and long mode's generated scenes) are
               kept between runs (default BUILD/targets-cache). The reference
               (tools/vertex_reference.sh's probes, reference_mc with --ref-samples paths, then
               tools/reference_topup.py to --ref-max-se on every lit vertex: issue 13's
               definition) is built on the first run: about half an hour on 2 quiet cores.
--runs N       runs per benchmark (default 1 in quick mode, 3 in long); a timed figure is the
               median of its runs. Counts and errors do not vary between runs; benchmarks whose
               figures are all errors or counts, and the scale ladder, run once (ONE_RUN).
--json OUT     saves every row (figures, targets, commands) as JSON.
--only S       only the targets whose name contains S (the benchmarks they need run once).
--list         prints the targets table (docs/targets.md) and exits.
--no-reference-build   never builds the box's reference: without a cached one, the box's
               accuracy rows are "not measured" and its cost rows still run.

A cost per point is a phase's wall time from the bake's timings.json ("phases") divided by
stats.json's `covered_texels` (texels) or `vertices` (output vertices). A solve time is
bench_solver's `median_s`. Wall times on a shared machine move by up to 25 % between identical
runs: each command's CPU time (user + system of the child, from getrusage) is printed with its
CPU/wall ratio, which falls below the thread count when other work competes for the cores.
Exit status 0 when every measured target is met, 1 when one is not, 2 on a usage error; a
target that could not be measured is listed as such and does not fail the run.
Python standard library only.
"""
import argparse
import json
import math
import os
import re
import resource
import shlex
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import harness  # noqa: E402  (harness.compare: the paper and analytic scenes' probe errors)

# --- The targets ------------------------------------------------------------------------------
# One row per target: (name, issue, state, mode, measurement, figure, comparison, threshold).
#   state:       "met" targets of resolved issues that must stay met; "open" for issues 27 and 28.
#   mode:        "quick" or "long" (--long runs both).
#   measurement: a key of MEASUREMENTS below (what is run; each runs once however many rows use it).
#   figure:      a key of the dict that measurement returns.
#   comparison:  "<=", ">=", "==", "|x|<=" (absolute value at most), "nonincreasing" or
#                "nondecreasing" (a list of figures, in the order named).
# Percentages are in percent; times in seconds; costs in microseconds; memory in MB.
# Where a figure is "no worse than docs/results.md by more than 0.1 point", the threshold is the
# documented figure plus that margin, and the row's name says so.
TARGETS = [
    # Tessellated Cornell box (tools/gen_cornell_tessellated.py) against the topped-up reference.
    ("box: medium output vertices, RMS %", 13, "met", "quick", "box_medium", "rms", "<=", 1.5),
    ("box: medium output vertices, p95 %", 13, "met", "quick", "box_medium", "p95", "<=", 3.0),
    ("box: medium output vertices, max %", 13, "met", "quick", "box_medium", "max", "<=", 8.0),
    ("box: medium output vertices, |bias| %", 13, "met", "quick", "box_medium", "bias", "|x|<=", 0.5),
    ("box: high RMS % at most medium's", 13, "met", "quick", "box_presets", "rms_high_minus_medium", "<=", 0.0),
    ("box: lightmap at vertices (64/m), RMS %", 13, "met", "quick", "box_lightmap", "rms", "<=", 2.0),
    ("box: lightmap at vertices (64/m), p95 %", 13, "met", "quick", "box_lightmap", "p95", "<=", 4.0),
    ("box: medium vertices RMS % (0.78 + 0.1)", 27, "open", "quick", "box_medium", "rms", "<=", 0.88),
    ("box: medium vertices p95 % (1.40 + 0.1)", 27, "open", "quick", "box_medium", "p95", "<=", 1.50),
    ("box: medium vertices |bias| % (0.33 + 0.1)", 27, "open", "quick", "box_medium", "bias", "|x|<=", 0.43),
    ("box: lightmap at vertices RMS % (1.49 + 0.1)", 27, "open", "quick", "box_lightmap", "rms", "<=", 1.59),
    ("box: lightmap at vertices p95 % (1.55 + 0.1)", 27, "open", "quick", "box_lightmap", "p95", "<=", 1.65),
    ("box: draft vertices RMS %", 27, "open", "quick", "box_draft", "rms", "<=", 3.0),
    ("box: draft vertices |bias| %", 27, "open", "quick", "box_draft", "bias", "|x|<=", 1.0),
    ("box: draft CPU / medium CPU", 27, "open", "quick", "box_presets", "cpu_draft_over_medium", "<=", 0.6),
    ("box: RMS % draft >= medium >= high", 27, "open", "quick", "box_presets", "rms_dmh", "nonincreasing", None),
    ("box: CPU s draft <= medium <= high", 27, "open", "quick", "box_presets", "cpu_dmh", "nondecreasing", None),
    ("box: vertices phase, us per vertex", 27, "open", "quick", "box_medium", "us_per_vertex", "<=", 50.0),
    ("box: whole bake --no-lightmaps, CPU s", 12, "met", "quick", "box_medium", "cpu_s", "<=", 10.7),
    ("box: solve (aabb) s", 11, "met", "quick", "box_solve", "aabb_s", "<=", 3.0),
    ("box: links (aabb)", 11, "met", "quick", "box_solve", "aabb_links", "<=", 300000),
    ("box: solve (aabb) s", 28, "open", "quick", "box_solve", "aabb_s", "<=", 1.2),
    ("box: solve (exact) s", 28, "open", "quick", "box_solve", "exact_s", "<=", 1.2),
    # Duplex, draft -> medium -> high (issue 27's monotone presets; issue 12's whole bake).
    ("duplex: probes RMS % draft >= medium >= high", 27, "open", "quick", "duplex_presets", "rms_dmh",
     "nonincreasing", None),
    ("duplex: CPU s draft <= medium <= high", 27, "open", "quick", "duplex_presets", "cpu_dmh", "nondecreasing",
     None),
    ("duplex: whole bake (default settings) s", 12, "met", "quick", "duplex_bake", "seconds", "<=", 10.0),
    # The shipped Cornell box.
    ("cornell_box.wrl 64/m: lightmaps, us per covered texel", 12, "met", "quick", "cornell64", "us_per_texel",
     "<=", 50.0),
    ("cornell_box.wrl 64/m: lightmaps, us per covered texel", 27, "open", "quick", "cornell64", "us_per_texel",
     "<=", 30.0),
    ("cornell_box.wrl: lightmap phase / solve (density 16)", 12, "met", "quick", "cornell16", "lightmaps_over_solve",
     "<=", 1.5),
    ("cornell_box.wrl, 1 thread: whole bake s", 4, "met", "quick", "cornell1t", "seconds", "<=", 2.0),
    ("cornell_box.wrl, 1 thread: peak MB", 4, "met", "quick", "cornell1t", "peak_mb", "<=", 200.0),
    # house.wrl, CornellBox-Water, CornellBox-Sphere (../shared/scenes).
    ("house.wrl: vertices phase, us per vertex", 12, "met", "quick", "house_bake", "us_per_vertex", "<=", 50.0),
    ("house.wrl: vertices phase, us per vertex", 27, "open", "quick", "house_bake", "us_per_vertex", "<=", 50.0),
    ("house.wrl: vertices phase / solve", 12, "met", "quick", "house_bake", "vertices_over_solve", "<=", 1.0),
    ("house.wrl: solve (aabb) s", 11, "met", "quick", "house_solve", "aabb_s", "<=", 15.0),
    ("house.wrl: solve peak MB", 11, "met", "quick", "house_solve", "rss_mb", "<=", 1024.0),
    ("house.wrl: solve (aabb) s", 28, "open", "quick", "house_solve", "aabb_s", "<=", 3.0),
    ("house.wrl: solve (exact) s", 28, "open", "quick", "house_solve", "exact_s", "<=", 3.0),
    ("CornellBox-Water: solve (aabb) s", 11, "met", "quick", "water_solve", "aabb_s", "<=", 15.0),
    ("CornellBox-Water: solve peak MB", 11, "met", "quick", "water_solve", "rss_mb", "<=", 1024.0),
    ("CornellBox-Water: solve (aabb) s", 28, "open", "quick", "water_solve", "aabb_s", "<=", 3.0),
    ("CornellBox-Water: solve (exact) s", 28, "open", "quick", "water_solve", "exact_s", "<=", 3.0),
    ("CornellBox-Sphere: vertices phase / solve", 12, "met", "quick", "sphere_bake", "vertices_over_solve",
     "<=", 1.0),
    # The paper scenes' probe errors (docs/results.md's table, aabb rows, + 0.05 point).
    ("paper Cornell Box: probes L2 % (0.45 + 0.05)", 28, "open", "quick", "paper_cornell_box", "l2", "<=", 0.50),
    ("paper Duplex: probes L2 % (0.71 + 0.05)", 28, "open", "quick", "paper_duplex", "l2", "<=", 0.76),
    ("paper Geometry: probes L2 % (0.65 + 0.05)", 28, "open", "quick", "paper_geometry", "l2", "<=", 0.70),
    ("paper Shadow: probes L2 % (1.03 + 0.05)", 28, "open", "quick", "paper_shadow", "l2", "<=", 1.08),
    ("paper Secondary: probes L2 % (0.69 + 0.05)", 28, "open", "quick", "paper_secondary", "l2", "<=", 0.74),
    ("paper Shadow: probes L2 % (about 1-2 %)", 13, "met", "quick", "paper_shadow", "l2", "<=", 2.0),
    # Closed forms.
    ("analytic scenes: probes outside rel_tol (medium)", 6, "met", "quick", "analytic", "outside", "==", 0),
    ("closed-form tests failing (doctest)", 13, "met", "quick", "closed_form_tests", "failed", "==", 0),
    ("closed closet at draft: light / room's", 28, "open", "quick", "closet", "ratio", "<=", 1e-4),
    # Lightmaps in the browser (issue 33): tests/web/lightmap_check.mjs on house.wrl's default
    # bake, three.js and Babylon.js; surfaces brighter than 1 % of the brightest.
    ("house.wrl in the browser: worst surface median vs the EXR %", 33, "met", "quick", "web_house", "encoding_worst", "<=", 3.0),
    ("house.wrl in the browser: worst material vs albedo x H/pi %", 33, "met", "quick", "web_house", "material_worst", "<=", 3.0),
    ("house.wrl in the browser: largest decoded step %", 33, "met", "quick", "web_house", "step_max", "<=", 2.0),
    # A read-out split into shards (issue 29): tools/bench_shards.sh on house.wrl, 7 shards.
    ("house.wrl, 7 shards merged: one bake's bytes (1 = yes)", 29, "open", "long", "shards_house", "identical", "==", 1),
    ("house.wrl, 7 shards: CPU summed / one read-out's", 29, "open", "long", "shards_house", "cpu_ratio", "<=", 1.25),
    ("house.wrl, 7 shards: merge wall / whole bake's", 29, "open", "long", "shards_house", "merge_ratio", "<=", 0.05),
    # One bake on MPI ranks (issue 29): tools/bench_ranks.sh, 2 ranks of 1 thread against 1 process.
    ("graz.wrl, 2 ranks: whole bake speed-up over one process", 29, "open", "long", "ranks_graz", "speedup", ">=", 1.7),
    ("graz.wrl, 2 ranks: largest rank's peak memory / one process's", 29, "open", "long", "ranks_graz",
     "memory_ratio", "<=", 1.3),
    ("graz.wrl, 2 ranks: one bake's bytes (1 = yes)", 29, "open", "long", "ranks_graz", "identical", "==", 1),
    ("20k building, 2 ranks: whole bake speed-up over one process", 29, "open", "long", "ranks_building",
     "speedup", ">=", 1.7),
    ("20k building, 2 ranks: largest rank's peak memory / one process's", 29, "open", "long", "ranks_building",
     "memory_ratio", "<=", 1.3),
    ("20k building, 2 ranks: one bake's bytes (1 = yes)", 29, "open", "long", "ranks_building", "identical", "==", 1),
    # graz.wrl (long).
    ("graz.wrl: solve (aabb) s", 11, "met", "long", "graz_solve", "aabb_s", "<=", 30.0),
    ("graz.wrl: solve peak MB", 11, "met", "long", "graz_solve", "rss_mb", "<=", 2048.0),
    ("graz.wrl: solve (aabb) s", 28, "open", "long", "graz_solve", "aabb_s", "<=", 15.0),
    ("graz.wrl: solve (exact) s", 28, "open", "long", "graz_solve", "exact_s", "<=", 15.0),
    ("graz.wrl: lightmaps, us per covered texel", 27, "open", "long", "graz_bake", "us_per_texel", "<=", 60.0),
    ("graz.wrl: vertices phase, us per vertex", 27, "open", "long", "graz_bake", "us_per_vertex", "<=", 60.0),
    ("graz.wrl: vertices phase / solve", 12, "met", "long", "graz_bake", "vertices_over_solve", "<=", 1.0),
    ("graz.wrl: bake with lightmaps / --no-lightmaps", 12, "met", "long", "graz_ratio", "ratio", "<=", 2.0),
    ("graz.wrl 44/m: lightmap phase s (about 1M texels)", 27, "open", "long", "graz44", "lightmaps_s", "<=", 60.0),
    # Issue 30 (daylight): whole bakes with lightmaps (16 texels/m) under an overcast sky and a sun.
    ("house.wrl, overcast sky and sun: bake with lightmaps s", 30, "met", "long", "daylight_house", "seconds", "<=", 120.0),
    ("16-room building with windows, sky and sun, lamps off: bake s", 30, "met", "long", "daylight_building",
     "seconds", "<=", 120.0),
    ("graz.wrl: lightmap vs reference_mc at texels, |bias| %", 27, "open", "long", "graz_texels", "bias", "|x|<=", 1.0),
    ("graz.wrl: lightmap vs reference_mc at texels, median |error| %", 27, "open", "long", "graz_texels", "median",
     "<=", 3.0),
    ("graz.wrl: lightmap vs reference_mc at texels, p95 |error| %", 27, "open", "long", "graz_texels", "p95", "<=",
     12.0),
    ("graz.wrl: edge texels' p95 / inside texels'", 27, "open", "long", "graz_texels", "edge_over_inside", "<=", 1.5),
    # The classroom and office.wrl (long).
    ("classroom: solve (aabb) s", 11, "met", "long", "classroom_solve", "aabb_s", "<=", 40.0),
    ("classroom: solve peak MB", 11, "met", "long", "classroom_solve", "rss_mb", "<=", 2048.0),
    ("classroom: solve (aabb) s", 28, "open", "long", "classroom_solve", "aabb_s", "<=", 15.0),
    ("classroom: solve (exact) s", 28, "open", "long", "classroom_solve", "exact_s", "<=", 15.0),
    ("office.wrl: solve (aabb) s", 11, "met", "long", "office_solve", "aabb_s", "<=", 60.0),
    ("office.wrl: solve peak MB", 11, "met", "long", "office_solve", "rss_mb", "<=", 4096.0),
    ("office.wrl: solve (aabb) s", 28, "open", "long", "office_solve", "aabb_s", "<=", 15.0),
    ("office.wrl: solve (exact) s", 28, "open", "long", "office_solve", "exact_s", "<=", 15.0),
    # The scale ladder's buildings (tools/bench_scale.sh, aabb).
    ("building 20k -> 200k: solve time growth x", 11, "met", "long", "ladder", "time_growth", "<=", 20.0),
    ("building 20k -> 200k: memory growth x", 11, "met", "long", "ladder", "memory_growth", "<=", 15.0),
    ("building 200k: solve s", 11, "met", "long", "ladder", "b200k_s", "<=", 300.0),
    ("building 20k -> 200k: solve time growth x (n^1.08)", 28, "open", "long", "ladder", "time_growth", "<=", 12.0),
    ("building 20k -> 200k: memory growth x", 28, "open", "long", "ladder", "memory_growth", "<=", 10.0),
    ("building 200k: solve s", 28, "open", "long", "ladder", "b200k_s", "<=", 60.0),
    ("building 1M: solve s", 11, "met", "long", "ladder", "b1m_s", "<=", 600.0),
    ("building 1M: peak MB", 11, "met", "long", "ladder", "b1m_mb", "<=", 8192.0),
    ("building 1M: solve s", 28, "open", "long", "ladder", "b1m_s", "<=", 180.0),
    ("building 1M: peak MB", 28, "open", "long", "ladder", "b1m_mb", "<=", 4096.0),
    # The oldest benchmarks (long: the generated VRML file is 100 MB; 10^6 configurations).
    ("VRML97 read, MB/s on one core", 2, "met", "long", "vrml_read", "mb_per_s", ">=", 30.0),
    ("VRML97 read, peak memory / file size", 2, "met", "long", "vrml_read", "memory_over_file", "<=", 10.0),
    ("occlusion: exact's false occlusions in 10^6", 3, "met", "long", "occlusion", "exact_false", "==", 0),
    # The fast read-out against the exhaustive gather (long: the exhaustive gather takes minutes).
    ("cornell_box.wrl 64/m: texels vs exhaustive gather, RMS %", 12, "met", "long", "recon_cornell", "rms",
     "<=", 2.0),
]

# Targets in force that this script cannot measure yet (docs/targets.md says why).
NOT_MEASURED = [
    ("a real-scene accuracy benchmark of issue 27's own beside graz.wrl's (\"graz.wrl and one more real scene\")",
     27, "to be chosen by issue 27's work"),
    ("a scene with no light source solves in under 1 s; a building with a lamp in one room only in at most "
     "0.1 x the time with a lamp in every room", 28, "tools/gen_building.py puts a lamp in every room"),
    ("the 1M building's progress estimate within 2 x at 25 % and 30 % at 50 % of the solve", 28,
     "the solve prints no fraction to read yet"),
    ("graz.wrl at least 4 x faster and the 1M building at least 4.8 x faster than at the start of issue 28",
     28, "a ratio to a start-of-work binary: run this script with --build on both builds"),
    ("shards N = 1, 3, 7 merged: one bake's bytes on the Cornell box, Duplex, graz.wrl and the 20k building", 29,
     "the first two are ctest's (tests/cli/test_split_bake.cpp); the others by hand: tools/bench_shards.sh SCENE N "
     "(session 23: N = 3 on both; session 24: N = 1 and 7 on the building, 7 on graz.wrl)"),
    ("mpirun -np 1, 2, 3: one bake's bytes on the Cornell box, Duplex, graz.wrl and the 20k building", 29,
     "the first two are ctest's (tests/cli/test_mpi_bake.cpp); 2 ranks on the others above (long); 3 ranks by "
     "hand: tools/bench_ranks.sh SCENE 3"),
    ("each rank holds about 1 / N of the links (within 25 %)", 29,
     "not so: every rank holds every link (docs/distributed.md says why)"),
]

QUALITIES = ("draft", "medium", "high")
PAPER = {"cornell_box": "scenes/cornell_box", "duplex": "scenes/paper/duplex",
         "geometry": "scenes/paper/geometry", "shadow": "scenes/paper/shadow",
         "secondary": "scenes/paper/secondary"}
SHARED = {"house": "vrml-threejs-house-vrml97/house.wrl",
          "water": "cornell-mcguire/CornellBox-Water.obj",
          "sphere": "cornell-mcguire/CornellBox-Sphere.obj",
          "graz": "vrml-castle-demo-models/lights_materials/raytracer/graz.wrl",
          "office": "vrml-castle-demo-models/lights_materials/raytracer/office.wrl",
          "classroom": "vrml-student-classroom/room.wrl"}
CLOSED_FORM_TESTS = {
    "tests_pipeline": ["a 90-degree hinge*", "a black block standing on an emitting floor*",
                       "a furnace's edges and corners*", "two-sided furnace*", "hard edges*"],
    "tests_radiosity": ["closed emitting box*", "irradiance below an emitting unit square*",
                        "probe under a half-hidden emitting square*", "probe in a luminaire's penumbra*",
                        "polygon form factor*", "point-to-polygon form factor*",
                        "tessellated closed furnace with clusters*",
                        "a closed dark room beside a bright one stays exactly black*"],
    "tests_readout": ["closed emitting box*"],  # the vertex bake's closed form
    "tests_harness": ["analytic*"],
}


class Unmeasured(Exception):
    """A benchmark that could not run here (a missing scene or program): its rows say why."""


# --- Reading what the programs write ------------------------------------------------------------
def read_json(path):
    with open(path) as f:
        return json.load(f)


def solve_seconds(phases):
    """The solve's wall time from timings.json's phases: every phase up to the last solve phase
    (import, parts, elements, links, solve, deferred links, later rounds), as issue 12 counts it."""
    names = list(phases)
    last = max((i for i, n in enumerate(names) if n.startswith("solve")), default=-1)
    if last < 0:
        raise ValueError("timings.json has no solve phase: %s" % ", ".join(names))
    return sum(float(phases[n]) for n in names[:last + 1])


def bake_figures(out_dir):
    """The figures of one bake folder: whole wall time, solve, vertex and texel costs, peak MB."""
    timings = read_json(os.path.join(out_dir, "timings.json"))
    stats = read_json(os.path.join(out_dir, "stats.json"))
    phases = timings["phases"]
    solve = solve_seconds(phases)
    fig = {"seconds": float(timings["seconds"]), "solve_s": solve, "peak_mb": float(timings["peak_rss_mb"])}
    vertices = int(stats.get("vertices", 0))
    if "vertices" in phases and vertices > 0:
        fig["vertices_s"] = float(phases["vertices"])
        fig["us_per_vertex"] = 1e6 * fig["vertices_s"] / vertices
        fig["vertices_over_solve"] = fig["vertices_s"] / solve if solve > 0 else float("inf")
    texels = int(stats.get("covered_texels", 0) or 0)
    if "lightmaps" in phases:
        fig["lightmaps_s"] = float(phases["lightmaps"])
        fig["lightmaps_over_solve"] = fig["lightmaps_s"] / solve if solve > 0 else float("inf")
        if texels > 0:
            fig["us_per_texel"] = 1e6 * fig["lightmaps_s"] / texels
    fig["vertices"] = vertices
    fig["covered_texels"] = texels
    return fig


def parse_bench_solver(text):
    """bench_solver's table: {mode: {median_s, links, rays, rss_mb, ...}} (its printed columns)."""
    columns = None
    out = {}
    for line in text.splitlines():
        words = line.split()
        if words[:3] == ["mode", "thr", "median_s"]:
            columns = words
            continue
        if columns and len(words) >= len(columns) and words[0] in ("rays", "aabb", "obb", "exact"):
            row = {}
            for k, w in zip(columns[1:], words[1:len(columns)]):
                row[k] = float(w)
            out[words[0]] = row
    if not out:
        raise ValueError("no bench_solver table in its output")
    return out


def parse_doctest(text):
    """(test cases run, failed) from a doctest summary line."""
    m = re.search(r"test cases:\s*(\d+)\s*\|\s*(\d+) passed\s*\|\s*(\d+) failed", text)
    if not m:
        raise ValueError("no doctest summary")
    return int(m.group(1)), int(m.group(3))


def parse_bench_scale(text):
    """tools/bench_scale.sh's markdown table: {scene: {triangles, median_s, links, rays, rss_mb, status}}."""
    out = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 7 or cells[0] in ("scene", "") or cells[0].startswith("---"):
            continue
        row = {"status": cells[6]}
        for k, v in zip(("triangles", "median_s", "links", "rays", "rss_mb"), cells[1:6]):
            try:
                row[k] = float(v)
            except ValueError:
                row[k] = None
        out[cells[0]] = row
    return out


def ladder_figures(rows):
    """Growth from building_20k to building_200k, and the 200k and 1M buildings' figures."""
    fig = {}
    a, b, c = rows.get("building_20k"), rows.get("building_200k"), rows.get("building_1m")
    if a and b and a.get("median_s") and b.get("median_s"):
        fig["time_growth"] = b["median_s"] / a["median_s"]
        fig["memory_growth"] = b["rss_mb"] / a["rss_mb"]
        fig["triangle_growth"] = b["triangles"] / a["triangles"] if a.get("triangles") and b.get("triangles") else None
    if b and b.get("median_s"):
        fig["b200k_s"] = b["median_s"]
    if c and c.get("median_s"):
        fig["b1m_s"] = c["median_s"]
        fig["b1m_mb"] = c["rss_mb"]
    return fig


def median_figures(runs):
    """Per key, the median over runs of the numbers (lists element-wise); other values from the last."""
    out = {}
    for key in runs[-1]:
        values = [r.get(key) for r in runs if key in r]
        if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            out[key] = statistics.median(values)
        elif all(isinstance(v, list) for v in values) and len({len(v) for v in values}) == 1:
            out[key] = [statistics.median(col) for col in zip(*values)]
        else:
            out[key] = values[-1]
    return out


def judge(value, comparison, threshold):
    """True / False, or None when there is no figure."""
    if value is None:
        return None
    if comparison == "<=":
        return value <= threshold
    if comparison == ">=":
        return value >= threshold
    if comparison == "==":
        return value == threshold
    if comparison == "|x|<=":
        return abs(value) <= threshold
    if comparison == "nonincreasing":
        return all(a >= b for a, b in zip(value, value[1:]))
    if comparison == "nondecreasing":
        return all(a <= b for a, b in zip(value, value[1:]))
    raise ValueError("unknown comparison %s" % comparison)


def fmt_number(v):
    if v is None:
        return "-"
    if isinstance(v, list):
        return " / ".join(fmt_number(x) for x in v)
    if isinstance(v, int) or (isinstance(v, float) and v.is_integer() and abs(v) >= 100):
        return "{:,}".format(int(v))
    a = abs(v)
    if a != 0 and (a < 1e-3 or a >= 1e7):
        return "%.3g" % v
    if a >= 100:
        return "%.0f" % v
    if a >= 10:
        return "%.1f" % v
    return "%.3g" % v if a < 1 else "%.2f" % v


def fmt_target(comparison, threshold):
    if comparison == "nonincreasing":
        return "not rising"
    if comparison == "nondecreasing":
        return "not falling"
    if comparison == "|x|<=":
        return "|x| <= " + fmt_number(threshold)
    return "%s %s" % (comparison, fmt_number(threshold))


def table_rows(targets, results):
    """The printed rows: one per target, with its figure (or why there is none) and verdict."""
    rows = []
    for name, issue, state, mode, measurement, figure, comparison, threshold in targets:
        result = results.get(measurement, {})
        value = result.get("figures", {}).get(figure) if "figures" in result else None
        met = judge(value, comparison, threshold)
        rows.append({"target": name, "issue": issue, "state": state, "mode": mode, "measurement": measurement,
                     "figure": figure, "measured": value, "comparison": comparison, "threshold": threshold,
                     "met": met, "error": result.get("error"), "commands": result.get("commands", []),
                     "cpu": result.get("cpu", [])})
    return rows


def cpu_wall(cpu):
    """CPU time over wall time of a benchmark's commands (None without timed commands)."""
    wall = sum(c["wall_s"] for c in cpu)
    return sum(c["cpu_s"] for c in cpu) / wall if wall > 0 else None


def format_table(rows, abbreviate=lambda s: s):
    lines = ["| target | issue | measured | target | met | CPU/wall | command |", "|---|---|---:|---|---|---:|---|"]
    for r in rows:
        met = {True: "yes", False: "**no**", None: "not measured"}[r["met"]]
        measured = fmt_number(r["measured"]) if r["met"] is not None else (r["error"] or "no figure")
        command = " ; ".join(abbreviate(c) for c in r["commands"])
        ratio = cpu_wall(r["cpu"])
        lines.append("| %s | %d (%s) | %s | %s | %s | %s | `%s` |" % (
            r["target"], r["issue"], r["state"], measured, fmt_target(r["comparison"], r["threshold"]), met,
            "%.2f" % ratio if ratio is not None else "-", command.replace("|", "\\|")))
    return "\n".join(lines)


# --- Running ------------------------------------------------------------------------------------
class Runner:
    def __init__(self, args):
        self.args = args
        self.build = os.path.abspath(args.build)
        self.scenes = os.path.abspath(args.scenes)
        self.cache = os.path.abspath(args.cache or os.path.join(self.build, "targets-cache"))
        self.work = os.path.abspath(args.work or os.path.join(self.cache, "work"))
        self.commands = []
        self.cpu = []

    def program(self, rel):
        path = os.path.join(self.build, rel)
        if not os.access(path, os.X_OK):
            raise Unmeasured("%s not built" % rel)
        return path

    def shared(self, key):
        path = os.path.join(self.scenes, SHARED[key])
        if not os.path.isfile(path):
            raise Unmeasured("%s missing" % SHARED[key])
        return path

    def run(self, argv, timeout=None, check=True, record=True):
        """Runs argv; returns (stdout, stderr). Records the command and its CPU time."""
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.monotonic()
        p = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)
        wall = time.monotonic() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        if record:
            self.commands.append(" ".join(shlex.quote(a) for a in argv))
            self.cpu.append({"command": os.path.basename(argv[0]) if not argv[0].endswith("python3") else
                             os.path.basename(argv[1]), "wall_s": wall, "cpu_s": cpu})
        self.last_cpu = cpu
        if check and p.returncode != 0:
            tail = (p.stderr.strip().splitlines() or ["(no output)"])[-1][:200]
            raise RuntimeError("%s exited %d: %s" % (os.path.basename(argv[0]), p.returncode, tail))
        return p.stdout, p.stderr

    def out_dir(self, name):
        path = os.path.join(self.work, name)
        shutil.rmtree(path, ignore_errors=True)
        return path

    def bake(self, scene, name, *options):
        out = self.out_dir(name)
        self.run([self.program("src/radbake"), "bake", scene, "-q", "-o", out] + list(options))
        fig = bake_figures(out)
        fig["cpu_s"] = self.last_cpu
        return out, fig

    def python_tool(self, tool, *args):
        return self.run([sys.executable, os.path.join(HERE, tool)] + list(args))

    # The tessellated box and its reference, cached.
    def box_reference(self):
        """(scene, probe file, reference CSV) of the tessellated box, from the cache or built into it:
        CACHE/box/box.obj (tools/gen_cornell_tessellated.py, rebuilt when the generator's bytes
        change), vertices.probes (vertex_probes), reference.csv (reference_mc, --ref-samples paths;
        reference.samples holds the count) and reference_topped_seF.csv (tools/reference_topup.py
        to --ref-max-se F)."""
        box = os.path.join(self.cache, "box")
        scene, probes = os.path.join(box, "box.obj"), os.path.join(box, "vertices.probes")
        base, samples_file = os.path.join(box, "reference.csv"), os.path.join(box, "reference.samples")
        max_se = self.args.ref_max_se
        reference = base if max_se <= 0 else os.path.join(box, "reference_topped_se%g.csv" % max_se)
        os.makedirs(box, exist_ok=True)
        os.makedirs(self.work, exist_ok=True)
        # Generated under the same file name: the OBJ names its MTL (mtllib box.mtl).
        os.makedirs(os.path.join(self.work, "box_check"), exist_ok=True)
        fresh = os.path.join(self.work, "box_check", "box.obj")
        subprocess.run([sys.executable, os.path.join(HERE, "gen_cornell_tessellated.py"), fresh],
                       stdout=subprocess.DEVNULL, check=True)
        with open(fresh, "rb") as a:
            fresh_bytes = a.read()
        same = False
        if os.path.isfile(scene) and os.path.isfile(probes):
            with open(scene, "rb") as b:
                same = b.read() == fresh_bytes
        have_base = same and os.path.isfile(base) and os.path.isfile(samples_file)
        if have_base:
            with open(samples_file) as f:
                have_base = f.read().strip() == str(self.args.ref_samples)
        if have_base and os.path.isfile(reference):
            return scene, probes, reference
        if self.args.no_reference_build:
            if not same:
                self.python_tool("gen_cornell_tessellated.py", scene)
                self.run([self.program("tools/vertex_probes"), scene, probes])
            return scene, probes, None
        sys.stderr.write("targets: building the tessellated box's reference in %s (%d paths%s): slow (session 11: "
                         "15 min for the paths and 10 for the top-up on 2 quiet cores), once\n" % (
                             box, self.args.ref_samples,
                             ", topped up to %.2f %% per lit vertex" % (100 * max_se) if max_se > 0 else ""))
        if not have_base:
            for f in os.listdir(box):
                if f.startswith("reference"):
                    os.remove(os.path.join(box, f))
            self.python_tool("gen_cornell_tessellated.py", scene)
            self.run([self.program("tools/vertex_probes"), scene, probes])
            self.run([self.program("tools/reference_mc"), scene, probes, "--samples", str(self.args.ref_samples),
                      "--threads", "0", "--seed", "1", "-o", base])
            with open(samples_file, "w") as f:
                f.write("%d\n" % self.args.ref_samples)
        if reference != base:
            self.python_tool("reference_topup.py", scene, probes, base, "--samples", str(self.args.ref_samples),
                             "--max-se", str(max_se), "--lit", "median", "--threads", "0",
                             "--reference-mc", self.program("tools/reference_mc"), "-o", reference)
        return scene, probes, reference

    def vertex_error(self, bake_or_csv, reference, vertices):
        argv = [bake_or_csv, reference, "--lit", "median", "--json"] + (["--vertices"] if vertices else [])
        out, _ = self.python_tool("vertex_error.py", *argv)
        r = json.loads(out.strip().splitlines()[-1])
        return {k: 100.0 * r[k] for k in ("rms", "p95", "max", "bias")}

    def bench_solver(self, scene, modes="aabb,exact", *options):
        out, _ = self.run([self.program("tools/bench_solver"), scene, "--modes", modes, "--threads", "2",
                           "--runs", "1"] + list(options))
        table = parse_bench_solver(out)
        fig = {}
        for mode, row in table.items():
            fig[mode + "_s"] = row["median_s"]
            fig[mode + "_links"] = row["links"]
        fig["rss_mb"] = max(row["rss_mb"] for row in table.values())
        return fig


def m_box_quality(quality):
    def measure(r):
        scene, _, reference = r.box_reference()
        out, fig = r.bake(scene, "box_" + quality, "--no-lightmaps", "--quality", quality, "--threads", "2")
        if reference:
            fig.update(r.vertex_error(out, reference, vertices=True))
        return fig
    return measure


def m_box_presets(r, results):
    figs = [results["box_" + q]["figures"] for q in QUALITIES]
    out = {"cpu_dmh": [f["cpu_s"] for f in figs], "cpu_draft_over_medium": figs[0]["cpu_s"] / figs[1]["cpu_s"]}
    if all("rms" in f for f in figs):
        out.update({"rms_dmh": [f["rms"] for f in figs], "rms_high_minus_medium": figs[2]["rms"] - figs[1]["rms"]})
    return out


def m_box_lightmap(r):
    scene, probes, reference = r.box_reference()
    if not reference:
        raise Unmeasured("no cached reference (--no-reference-build)")
    out, fig = r.bake(scene, "box_lm64", "--texel-density", "64", "--threads", "2")
    csv_path = os.path.join(r.work, "box_lm64.csv")
    r.run([r.program("tools/lightmap_at_vertices"), out, probes, csv_path])
    fig.update(r.vertex_error(csv_path, reference, vertices=False))
    return fig


def m_box_solve(r):
    scene, _, _ = r.box_reference()
    return r.bench_solver(scene)


def m_duplex_quality(quality):
    def measure(r):
        scene = os.path.join(REPO, "scenes/paper/duplex.wrl")
        out, fig = r.bake(scene, "duplex_" + quality, "--probes", os.path.join(REPO, "scenes/paper/duplex.probes"),
                          "--no-lightmaps", "--quality", quality, "--threads", "2")
        fig.update(r.vertex_error(os.path.join(out, "probes.csv"), os.path.join(REPO, "docs/reference/duplex.csv"),
                                  vertices=False))
        return fig
    return measure


def m_duplex_presets(r, results):
    figs = [results["duplex_" + q]["figures"] for q in QUALITIES]
    return {"rms_dmh": [f["rms"] for f in figs], "cpu_dmh": [f["cpu_s"] for f in figs]}


def m_duplex_bake(r):
    return r.bake(os.path.join(REPO, "scenes/paper/duplex.wrl"), "duplex_default", "--threads", "2")[1]


def m_cornell(density, threads):
    def measure(r):
        return r.bake(os.path.join(REPO, "scenes/cornell_box.wrl"), "cornell_%s_%s" % (density, threads),
                      "--texel-density", density, "--threads", threads)[1]
    return measure


def m_shared_bake(key, *options):
    def measure(r):
        return r.bake(r.shared(key), key + "_bake", "--threads", "2", "--read-root", r.scenes, *options)[1]
    return measure


def m_shared_solve(key):
    def measure(r):
        return r.bench_solver(r.shared(key), "aabb,exact", "--read-root", r.scenes)
    return measure


def m_web(key):
    """tests/web/lightmap_check.mjs on a default bake of a shared scene: per engine and judged
    surface (median H/pi above 1 % of the brightest surface's), the worst relative error of its
    median against the EXR and of its material against albedo x H/pi, and the largest step."""
    def measure(r):
        out, fig = r.bake(r.shared(key), key + "_web", "--threads", "2", "--read-root", r.scenes)
        if not shutil.which("node"):
            raise Unmeasured("node missing (tools/setup_web.sh)")
        report = os.path.join(out, "web.json")
        r.run(["node", os.path.join(REPO, "tests/web/lightmap_check.mjs"), "--bake", out, "--json", report], check=False)
        if not os.path.isfile(report):
            raise Unmeasured("the browser check did not run (tools/setup_web.sh)")
        with open(report) as f:
            engines = json.load(f)
        encoding, material, steps, judged = [], [], [], 0
        for engine in engines:
            drawn = [s for s in engine["surfaces"] if s["texels"] > 0]
            brightest = max(s["lightmap_median"] for s in drawn)
            for s in drawn:
                if not s["lightmap_median"] > 0.01 * brightest:
                    continue
                judged += 1
                encoding.append(abs(s["shown_median"] / s["expected_median"] - 1.0))
                if s.get("physical_median"):
                    material.append(abs(s["material_median"] / s["physical_median"] - 1.0))
                steps.append(s["largest_step"])
        fig.update({"encoding_worst": 100.0 * max(encoding), "material_worst": 100.0 * max(material or [0.0]),
                    "step_max": 100.0 * max(steps), "judged": judged})
        return fig
    return measure


def m_paper(name):
    def measure(r):
        base = os.path.join(REPO, PAPER[name])
        out, fig = r.bake(base + ".wrl", "paper_" + name, "--probes", base + ".probes", "--visibility", "aabb",
                          "--no-lightmaps", "--threads", "2")
        reference = harness.read_csv_rows(os.path.join(REPO, "docs/reference/%s.csv" % name))
        errors = harness.compare(os.path.join(out, "probes.csv"), reference)
        r.commands.append("harness.compare(%s/probes.csv, docs/reference/%s.csv)" % (out, name))
        fig.update({"l2": 100.0 * errors["l2_rel"], "max_rel": 100.0 * errors["max_rel"]})
        return fig
    return measure


def m_analytic(r):
    folder = os.path.join(REPO, "scenes/analytic")
    outside = probes = 0
    worst = 0.0
    for name in sorted(f[:-len(".expected.csv")] for f in os.listdir(folder) if f.endswith(".expected.csv")):
        out = r.out_dir("analytic_" + name)
        r.run([r.program("src/radbake"), "bake", os.path.join(folder, name + ".wrl"), "--probes",
               os.path.join(folder, name + ".probes"), "--no-lightmaps", "--threads", "2", "-q", "-o", out],
              record=False)
        reference = harness.read_csv_rows(os.path.join(folder, name + ".expected.csv"))
        errors = harness.compare(os.path.join(out, "probes.csv"), reference)
        outside += len(reference) - errors["within_tol"]
        probes += len(reference)
        worst = max(worst, errors["max_rel"])
    r.commands.append("for S in scenes/analytic/*.expected.csv: radbake bake S.wrl --probes S.probes "
                      "--no-lightmaps -o OUT; harness.compare(OUT/probes.csv, S.expected.csv)")
    return {"outside": outside, "probes": probes, "max_rel": 100.0 * worst}


def m_closed_form_tests(r):
    failed = cases = 0
    for binary, patterns in CLOSED_FORM_TESTS.items():
        out, _ = r.run([r.program(os.path.join("tests", binary)), "-tc=" + ",".join(patterns)], check=False)
        n, f = parse_doctest(out)
        if n == 0:
            raise ValueError("%s ran no test case for %s" % (binary, patterns))
        cases += n
        failed += f
    return {"failed": failed, "cases": cases}


def m_closet(r):
    out, _ = r.run([r.program("tests/tests_radiosity"), "-tc=at draft*", "-s"], check=False)
    m = re.search(r"closet ([0-9.eE+-]+), room B ([0-9.eE+-]+)", out)
    if not m:
        raise ValueError("the closet test printed no figure")
    closet, room = float(m.group(1)), float(m.group(2))
    return {"closet": closet, "room": room, "ratio": closet / room if room > 0 else float("inf")}


def m_graz_texels(r, results):
    """graz.wrl's default lightmap (graz_bake's) at 400 texel centres (tools/texel_probes, every
    brightness decile alike) against reference_mc, scored on lit texels by tools/texel_error.py."""
    scene, bake_dir = r.shared("graz"), os.path.join(r.work, "graz_bake")
    probes, reference = os.path.join(r.work, "graz_texels.probes"), os.path.join(r.work, "graz_texels_ref.csv")
    r.run([r.program("tools/texel_probes"), scene, bake_dir, probes, "--read-root", r.scenes, "--threads", "2"])
    r.run([r.program("tools/reference_mc"), scene, probes, "--samples", "16384", "--threads", "2", "-o", reference])
    out, _ = r.python_tool("texel_error.py", probes, reference, "--json")
    scores = json.loads(out)
    edge, inside = scores["by_edge"]["edge"]["p95"], scores["by_edge"]["inside"]["p95"]
    return {"bias": 100.0 * scores["all"]["bias"], "median": 100.0 * scores["all"]["median"],
            "p95": 100.0 * scores["all"]["p95"], "lit": scores["lit"],
            "edge_over_inside": edge / inside if inside > 0 else float("inf")}


def m_graz_ratio(r, results):
    return {"ratio": results["graz_bake"]["figures"]["seconds"] / results["graz_nolm"]["figures"]["seconds"]}


def m_daylight_building(r):
    """tools/gen_building.py's 16 rooms with a glazed window in every outside wall, lamps off."""
    scene = os.path.join(r.cache, "daylight", "building_windows.wrl")
    os.makedirs(os.path.dirname(scene), exist_ok=True)
    r.python_tool("gen_building.py", scene, "--rooms", "4", "4", "--panels", "9", "--windows", "--lamps", "none")
    return r.bake(scene, "daylight_building", "--threads", "2", "--sky", "overcast", "--sun", "135,35")[1]


def m_ladder(r):
    work = os.path.join(r.cache, "scale_scenes")
    out, _ = r.run(["bash", os.path.join(HERE, "bench_scale.sh"), r.build, "--scenes",
                    "building_20k,building_200k,building_1m", "--timeout", "1800", "--work", work])
    return ladder_figures(parse_bench_scale(out))


def parse_bench_reconstruct(text):
    """bench_reconstruct's "error links adaptive" line (the read-out bakes use against the exhaustive gather)."""
    m = re.search(r"^error links adaptive:\s+rms ([0-9.eE+-]+) worst ([0-9.eE+-]+)", text, re.M)
    if not m:
        raise ValueError("bench_reconstruct printed no 'error links adaptive' line")
    return {"rms": 100.0 * float(m.group(1)), "worst": 100.0 * float(m.group(2))}


def m_recon_cornell(r):
    out, _ = r.run([r.program("tools/bench_reconstruct"), os.path.join(REPO, "scenes/cornell_box.wrl"),
                    "--texel-density", "64", "--threads", "2"])
    return parse_bench_reconstruct(out)


def m_vrml_read(r):
    path = os.path.join(r.cache, "vrml_bench.wrl")
    if not os.path.isfile(path):
        r.python_tool("gen_vrml_bench.py", path)
    out, _ = r.run(["taskset", "-c", "0", r.program("tools/bench_vrml_read"), path, "3"]
                   if shutil.which("taskset") else [r.program("tools/bench_vrml_read"), path, "3"])
    m = re.search(r"median ([0-9.]+) MB/s over \d+ runs; peak RSS [0-9.]+ MB = ([0-9.]+) x file size", out)
    if not m:
        raise ValueError("bench_vrml_read printed no median")
    return {"mb_per_s": float(m.group(1)), "memory_over_file": float(m.group(2))}


def m_occlusion(r):
    out, _ = r.run([r.program("tools/bench_occlusion"), "1000000"])
    m = re.search(r"^exact\s+(\d+)\s+(\d+)\s+(\d+)", out, re.M)
    if not m:
        raise ValueError("bench_occlusion printed no exact row")
    return {"exact_claims": int(m.group(1)), "exact_false": int(m.group(2))}


def parse_bench_shards(text):
    """bench_shards.sh's ratio lines: the shards' CPU over one read-out's, the merge over a bake."""
    cpu = re.search(r"CPU summed [0-9.]+ s = ([0-9.]+) x the one-process read-out", text)
    merge = re.search(r"merge: wall [0-9.]+ s = ([0-9.]+) x a whole bake", text)
    if not cpu or not merge:
        raise ValueError("bench_shards.sh printed no ratios")
    return {"cpu_ratio": float(cpu.group(1)), "merge_ratio": float(merge.group(1)),
            "identical": 1 if "the same bytes as one bake" in text else 0}


def bench_script(r, script, *args):
    """The output of tools/SCRIPT ARGS run with this build's radbake."""
    out, _ = r.run(["env", "RADBAKE=" + r.program("src/radbake"), "bash", os.path.join(HERE, script), *args],
                   check=False)
    return out


def m_shards_house(r):
    return parse_bench_shards(bench_script(r, "bench_shards.sh", r.shared("house"), "7", "--read-root", r.scenes))


def parse_bench_ranks(text):
    """bench_ranks.sh's lines: the speed-up, the largest rank's memory over one process's, same bytes."""
    speedup = re.search(r"speed-up ([0-9.]+) x", text)
    memory = re.search(r"largest rank [0-9.]+ MiB: ([0-9.]+) x", text)
    if not speedup or not memory:
        raise ValueError("bench_ranks.sh printed no ratios")
    return {"speedup": float(speedup.group(1)), "memory_ratio": float(memory.group(1)),
            "identical": 1 if "same bytes: yes" in text else 0}


def m_ranks(scene_of):
    def measure(r):
        return parse_bench_ranks(bench_script(r, "bench_ranks.sh", scene_of(r), "2", str(r.args.runs or 3)))
    return measure


def ranks_building(r):
    scene = os.path.join(r.cache, "ranks", "building_20k.wrl")
    os.makedirs(os.path.dirname(scene), exist_ok=True)
    r.python_tool("gen_building.py", scene, "--rooms", "4", "4", "--panels", "9")
    return scene


# measurement -> (function, derived from other measurements?, the measurements it needs)
MEASUREMENTS = {
    "box_draft": (m_box_quality("draft"), False, []),
    "box_medium": (m_box_quality("medium"), False, []),
    "box_high": (m_box_quality("high"), False, []),
    "box_presets": (m_box_presets, True, ["box_draft", "box_medium", "box_high"]),
    "box_lightmap": (m_box_lightmap, False, []),
    "box_solve": (m_box_solve, False, []),
    "duplex_draft": (m_duplex_quality("draft"), False, []),
    "duplex_medium": (m_duplex_quality("medium"), False, []),
    "duplex_high": (m_duplex_quality("high"), False, []),
    "duplex_presets": (m_duplex_presets, True, ["duplex_draft", "duplex_medium", "duplex_high"]),
    "duplex_bake": (m_duplex_bake, False, []),
    "cornell64": (m_cornell("64", "2"), False, []),
    "cornell16": (m_cornell("16", "2"), False, []),
    "cornell1t": (m_cornell("16", "1"), False, []),
    "house_bake": (m_shared_bake("house", "--no-lightmaps"), False, []),
    "house_solve": (m_shared_solve("house"), False, []),
    "web_house": (m_web("house"), False, []),
    "shards_house": (m_shards_house, False, []),
    "ranks_graz": (m_ranks(lambda r: r.shared("graz")), False, []),
    "ranks_building": (m_ranks(ranks_building), False, []),
    "water_solve": (m_shared_solve("water"), False, []),
    "sphere_bake": (m_shared_bake("sphere", "--no-lightmaps"), False, []),
    "paper_cornell_box": (m_paper("cornell_box"), False, []),
    "paper_duplex": (m_paper("duplex"), False, []),
    "paper_geometry": (m_paper("geometry"), False, []),
    "paper_shadow": (m_paper("shadow"), False, []),
    "paper_secondary": (m_paper("secondary"), False, []),
    "analytic": (m_analytic, False, []),
    "closed_form_tests": (m_closed_form_tests, False, []),
    "closet": (m_closet, False, []),
    "graz_solve": (m_shared_solve("graz"), False, []),
    "graz_bake": (m_shared_bake("graz"), False, []),
    "graz_nolm": (m_shared_bake("graz", "--no-lightmaps"), False, []),
    "graz_ratio": (m_graz_ratio, True, ["graz_bake", "graz_nolm"]),
    "graz_texels": (m_graz_texels, True, ["graz_bake"]),
    "graz44": (lambda r: r.bake(r.shared("graz"), "graz_44", "--threads", "2", "--read-root", r.scenes,
                                "--texel-density", "44")[1],
               False, []),
    "daylight_house": (m_shared_bake("house", "--sky", "overcast", "--sun", "135,35"), False, []),
    "daylight_building": (m_daylight_building, False, []),
    "classroom_solve": (m_shared_solve("classroom"), False, []),
    "office_solve": (m_shared_solve("office"), False, []),
    "ladder": (m_ladder, False, []),
    "vrml_read": (m_vrml_read, False, []),
    "occlusion": (m_occlusion, False, []),
    "recon_cornell": (m_recon_cornell, False, []),
}


# Measured once whatever --runs says: deterministic figures, or a benchmark that takes hours or
# repeats itself (bench_vrml_read reads its file 3 times).
ONE_RUN = {"box_lightmap", "analytic", "closed_form_tests", "closet", "paper_cornell_box", "paper_duplex",
           "paper_geometry", "paper_shadow", "paper_secondary", "ladder", "vrml_read", "occlusion",
           "recon_cornell", "graz_texels", "ranks_graz", "ranks_building"}  # bench_ranks.sh takes medians itself


def selected_targets(long_mode, only=None):
    return [t for t in TARGETS if (long_mode or t[3] == "quick") and (not only or only in t[0])]


def needed_measurements(targets):
    order = []
    for t in targets:
        for m in MEASUREMENTS[t[4]][2] + [t[4]]:
            if m not in order:
                order.append(m)
    return order


def measure_all(runner, names, runs):
    results = {}
    for name in names:
        fn, derived, needs = MEASUREMENTS[name]
        runner.commands, runner.cpu = [], []
        started = time.monotonic()
        sys.stderr.write("targets: %s ...\n" % name)
        try:
            if derived:
                missing = [n for n in needs if "figures" not in results.get(n, {})]
                if missing:
                    raise Unmeasured("needs %s" % ", ".join(missing))
                figs = fn(runner, results)
                commands = list(dict.fromkeys(c for n in needs for c in results[n]["commands"]))
                cpu = [c for n in needs for c in results[n]["cpu"]]
            else:
                figs = median_figures([fn(runner) for _ in range(1 if name in ONE_RUN else runs)])
                commands, cpu = list(dict.fromkeys(runner.commands)), runner.cpu
            results[name] = {"figures": figs, "commands": commands, "cpu": cpu}
        except (Unmeasured, RuntimeError, ValueError, OSError, KeyError, subprocess.SubprocessError) as e:
            results[name] = {"error": "%s: %s" % (type(e).__name__, e) if not isinstance(e, Unmeasured) else str(e),
                             "commands": list(dict.fromkeys(runner.commands)), "cpu": runner.cpu}
        sys.stderr.write("targets: %s done in %.1f s%s\n" % (name, time.monotonic() - started,
                                                              " (%s)" % results[name]["error"]
                                                              if "error" in results[name] else ""))
    return results


def targets_markdown():
    lines = ["| target | issue | state | mode | measurement | figure | target |", "|---|---:|---|---|---|---|---|"]
    for name, issue, state, mode, measurement, figure, comparison, threshold in TARGETS:
        lines.append("| %s | %d | %s | %s | %s | %s | %s |" % (name, issue, state, mode, measurement, figure,
                                                               fmt_target(comparison, threshold)))
    return "\n".join(lines)


def main(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    g = p.add_mutually_exclusive_group()
    g.add_argument("--quick", action="store_true", help="the quick targets (the default)")
    g.add_argument("--long", action="store_true", help="every target: a few hours")
    p.add_argument("--build", default=os.path.join(REPO, "build"))
    p.add_argument("--scenes", default=os.path.join(REPO, "..", "shared", "scenes"))
    p.add_argument("--cache", help="default BUILD/targets-cache")
    p.add_argument("--work", help="bake folders (default CACHE/work; emptied per benchmark)")
    p.add_argument("--runs", type=int, help="runs per benchmark (default 1 quick, 3 long)")
    p.add_argument("--json", help="save the rows as JSON here")
    p.add_argument("--only", help="only targets whose name contains this")
    p.add_argument("--list", action="store_true", help="print the targets table and exit")
    p.add_argument("--no-reference-build", action="store_true",
                   help="never build the box's reference: without a cached one its accuracy rows are not measured")
    p.add_argument("--ref-samples", type=int, default=65536, help="the box reference's paths per vertex")
    p.add_argument("--ref-max-se", type=float, default=0.005,
                   help="top the reference up to this noise per lit vertex (0: no top-up)")
    args = p.parse_args(argv[1:])
    if args.list:
        print(targets_markdown())
        return 0
    runs = args.runs or (3 if args.long else 1)
    if runs < 1:
        p.error("--runs must be at least 1")
    runner = Runner(args)
    targets = selected_targets(args.long, args.only)
    if not targets:
        p.error("no target matches --only %r" % args.only)
    started = time.monotonic()
    load = os.getloadavg()[0]
    results = measure_all(runner, needed_measurements(targets), runs)
    rows = table_rows(targets, results)

    def abbreviate(command):
        for path, name in ((runner.work, "$WORK"), (runner.cache, "$CACHE"), (runner.build, "$BUILD"),
                           (runner.scenes, "$SCENES"), (REPO, "."), (sys.executable, "python3")):
            command = command.replace(path, name)
        return command

    print("targets.py --%s: %d targets, %d runs each, load %.1f at start, %.0f s; BUILD=%s SCENES=%s CACHE=%s "
          "WORK=%s" % ("long" if args.long else "quick", len(rows), runs, load, time.monotonic() - started,
                       runner.build, runner.scenes, runner.cache, runner.work))
    print()
    print(format_table(rows, abbreviate))
    met = sum(1 for r in rows if r["met"] is True)
    missed = [r for r in rows if r["met"] is False]
    unmeasured = [r for r in rows if r["met"] is None]
    print()
    print("met %d, not met %d, not measured %d" % (met, len(missed), len(unmeasured)))
    print()
    print("CPU time per command (user + system of the child; CPU/wall below the threads used means the cores "
          "were shared):")
    for name, result in results.items():
        for c in result.get("cpu", []):
            if c["wall_s"] >= 0.5:
                print("  %-18s %-26s wall %7.2f s  CPU %7.2f s  CPU/wall %.2f" % (
                    name, c["command"], c["wall_s"], c["cpu_s"], c["cpu_s"] / c["wall_s"]))
    print()
    print("Not measured by this script (docs/targets.md):")
    for text, issue, why in NOT_MEASURED:
        print("  - issue %d: %s (%s)" % (issue, text, why))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"mode": "long" if args.long else "quick", "runs": runs, "load_at_start": load,
                       "rows": rows, "results": results}, f, indent=1, sort_keys=True, default=str)
    return 1 if missed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

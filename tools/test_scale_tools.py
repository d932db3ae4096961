#!/usr/bin/env python3
"""ctest `scale_tools`: the scale and accuracy yardsticks' generators and scorer hold what they
promise (a few seconds in all).

    python3 tools/test_scale_tools.py RADBAKE VERTEX_PROBES REFERENCE_MC LIGHTMAP_AT_VERTICES

- gen_cornell_tessellated.py: radbake reads 17 meshes, 2,448 polygons, 4,896 triangles, 16
  emitting polygons, bounds [0,0,0]..[1,1,1]; vertex_probes finds 2,857 vertices (no importer
  welds across an edge), every probe strictly inside its own face (the nudge), its normal the
  face's (walls: into the room);
- gen_building.py: the triangle count it prints is the one radbake reads; two runs give the same
  bytes; a different seed gives others; in a room without boxes the floor's irradiance under
  the lamp (reference_mc) is well above the lamp's direct light alone, which it would not be if
  walls faced outward (one-sided surfaces: a wall seen from behind is black);
- vertex_error.py: exact figures on a literal bake and reference;
- reference_topup.py: noisy probes get paths to the asked noise, the others keep their bytes,
  estimates pool by path count;
- lightmap_at_vertices: on a room lit by its ceiling, baked with lightmaps, the lightmap looked
  up at every vertex gives the bake's own vertex value (the .ply) within 2 % inside the walls
  (a lookup half a texel off, or with v up, does not), its rows are the probe file's positions,
  and a bake without lightmaps is refused naming a mesh.
Python standard library only.
"""
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import vertex_error  # noqa: E402

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL: " + message)


def run(command):
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError("%s failed (%d): %s" % (" ".join(command), result.returncode, result.stderr))
    return result.stdout


def info(radbake, path):
    return json.loads(run([radbake, "info", path, "--json"]))


def read_probes(path):
    probes = []
    with open(path) as f:
        for line in f:
            body = line.partition("#")[0].split()
            if body:
                probes.append([float(v) for v in body])
    return probes


def test_cornell(radbake, vertex_probes, tmp):
    obj = os.path.join(tmp, "cornell.obj")
    run([sys.executable, os.path.join(HERE, "gen_cornell_tessellated.py"), obj])
    check(os.path.exists(os.path.join(tmp, "cornell.mtl")), "the .mtl is written beside the .obj")
    got = info(radbake, obj)
    for key, want in (("meshes", 17), ("polygons", 2448), ("triangles", 4896), ("emitters", 16), ("warnings", 0)):
        check(got[key] == want, "cornell: %s %s, want %s" % (key, got[key], want))
    check(got["bounds"] == {"min": [0, 0, 0], "max": [1, 1, 1]}, "cornell: bounds %s" % got["bounds"])
    check(abs(got["area"] - 7.3) < 1e-5, "cornell: area %s, want 7.3" % got["area"])
    probes_path = os.path.join(tmp, "cornell.probes")
    run([vertex_probes, obj, probes_path])
    probes = read_probes(probes_path)
    check(len(probes) == 2857, "cornell: %d vertex probes, want 2857" % len(probes))
    nudge = 1e-4 * math.sqrt(3.0)
    for x, y, z, nx, ny, nz in probes:
        p, n = (x, y, z), (nx, ny, nz)
        axis = max(range(3), key=lambda a: abs(n[a]))
        if abs(abs(n[axis]) - 1.0) < 1e-9:  # a wall, the light or a box top: axis-aligned
            others = [p[a] for a in range(3) if a != axis]
            # Strictly inside the room's walls: no probe left on an edge of its face.
            if not all(nudge * 0.5 < c < 1.0 - nudge * 0.5 for c in others):
                check(False, "cornell: probe %s (normal %s) not inside its face" % (p, n))
                break
            if p[axis] in (0.0, 1.0):  # a wall: its normal points into the room
                check((0.5 - p[axis]) * n[axis] > 0, "cornell: wall probe %s faces out (%s)" % (p, n))
    corner = [pr for pr in probes if pr[1] == 0.0 and pr[0] < 1e-3 and pr[2] < 1e-3]
    check(len(corner) == 1 and abs(corner[0][0] - nudge / math.sqrt(2)) < 1e-9 and
          abs(corner[0][2] - nudge / math.sqrt(2)) < 1e-9,
          "cornell: the floor's corner vertex is nudged along the diagonal: %s" % corner)


def test_building(radbake, reference_mc, tmp):
    a, b, c = (os.path.join(tmp, n + ".wrl") for n in ("a", "b", "c"))
    gen = [sys.executable, os.path.join(HERE, "gen_building.py")]
    printed = run(gen + [a, "--rooms", "2", "1", "--panels", "3"])
    run(gen + [b, "--rooms", "2", "1", "--panels", "3"])
    run(gen + [c, "--rooms", "2", "1", "--panels", "3", "--seed", "2"])
    with open(a, "rb") as fa, open(b, "rb") as fb, open(c, "rb") as fc:
        da, db, dc = fa.read(), fb.read(), fc.read()
    check(da == db, "building: two runs differ")
    check(da != dc, "building: --seed changes nothing")
    triangles = int(printed.split(" triangles")[0].split()[-1])
    got = info(radbake, a)
    check(got["triangles"] == triangles, "building: radbake reads %d triangles, the generator says %d" % (
        got["triangles"], triangles))
    check(got["emitters"] == 2 and got["warnings"] == 0, "building: %s" % got)
    check(got["bounds"] == {"min": [0, 0, 0], "max": [8.19999981, 3, 4]}, "building: bounds %s" % got["bounds"])
    # A room without boxes: the floor under the lamp.
    empty = os.path.join(tmp, "empty.wrl")
    run(gen + [empty, "--rooms", "2", "1", "--panels", "2", "--boxes", "0"])
    probes = os.path.join(tmp, "floor.probes")
    with open(probes, "w") as f:
        f.write("2 0 2 0 1 0\n")
    out = run([reference_mc, empty, probes, "--samples", "4096", "--threads", "1"])
    h = float(out.splitlines()[1].split(",")[6])
    # Direct light of the 0.5 m square lamp (radiance 1) 2.98 m above, by the midpoint rule.
    direct, n = 0.0, 50
    for i in range(n):
        for j in range(n):
            dx, dz, dy = -0.25 + (i + 0.5) * 0.5 / n, -0.25 + (j + 0.5) * 0.5 / n, 2.98
            r2 = dx * dx + dy * dy + dz * dz
            direct += (dy * dy / (r2 * r2)) * (0.5 / n) ** 2
    print("building: floor H %.5g, the lamp alone %.5g" % (h, direct))
    check(h > 1.3 * direct, "building: floor H %.5g against the lamp's direct %.5g: walls face out?" % (h, direct))


def test_vertex_error():
    def rows(values, se=None):
        out = []
        for i, v in enumerate(values):
            row = {"x": str(i), "y": "0", "z": "0", "nx": "0", "ny": "1", "nz": "0", "r": str(v), "g": str(v), "b": str(v)}
            if se is not None:
                row.update({"se_r": str(se * v), "se_g": str(se * v), "se_b": str(se * v)})
            out.append(row)
        return out
    reference = rows([1.5, 2.0, 4.0, 100.0, 0.5], se=0.01)  # 0.5 is below 1 % of 100: not lit
    bake = rows([1.65, 1.8, 4.0, 100.0, 5.0])
    result, errors = vertex_error.score(bake, reference)
    check(result["lit"] == 4, "vertex_error: lit %d, want 4" % result["lit"])
    check(abs(result["rms"] - math.sqrt((0.01 + 0.01) / 4)) < 1e-12, "vertex_error: rms %r" % result["rms"])
    check(abs(result["bias"] - 0.0) < 1e-12, "vertex_error: bias %r" % result["bias"])
    check(abs(result["max"] - 0.1) < 1e-12 and abs(result["p95"] - 0.1) < 1e-12, "vertex_error: max/p95 %r" % result)
    check(abs(result["ref_noise_rms"] - 0.01) < 1e-12, "vertex_error: noise %r" % result["ref_noise_rms"])
    median_rule, _ = vertex_error.score(bake, reference, "median")
    check(median_rule["lit"] == 5, "vertex_error: lit by the median %d, want 5" % median_rule["lit"])
    moved = rows([1.5, 2.0, 4.0, 100.0, 0.5])
    moved[2]["x"] = "2.001"
    try:
        vertex_error.score(moved, reference)
        check(False, "vertex_error: a moved probe is not noticed")
    except ValueError:
        pass


def write_room(path, n=4):
    """A closed 1 m room facing inward, its ceiling emitting (so the light inside is smooth),
    every wall its own object cut into n x n quads: vertices inside the walls' charts."""
    walls = [  # (name, origin, u, v): the front (u x v) faces into the room
        ("floor", (0, 0, 0), (0, 0, 1), (1, 0, 0)), ("ceiling", (0, 1, 0), (1, 0, 0), (0, 0, 1)),
        ("back", (0, 0, 0), (1, 0, 0), (0, 1, 0)), ("front", (0, 0, 1), (0, 1, 0), (1, 0, 0)),
        ("left", (0, 0, 0), (0, 1, 0), (0, 0, 1)), ("right", (1, 0, 0), (0, 0, 1), (0, 1, 0))]
    mtl = os.path.splitext(path)[0] + ".mtl"
    with open(mtl, "w") as f:
        f.write("newmtl wall\nKd 0.6 0.5 0.4\nKe 0 0 0\n\nnewmtl lamp\nKd 0.3 0.3 0.3\nKe 1 1 1\n")
    lines, base = ["mtllib " + os.path.basename(mtl)], 1
    for name, o, u, v in walls:
        lines += ["o " + name, "usemtl " + ("lamp" if name == "ceiling" else "wall")]
        for j in range(n + 1):
            for i in range(n + 1):
                lines.append("v %g %g %g" % tuple(o[k] + u[k] * i / n + v[k] * j / n for k in range(3)))
        for j in range(n):
            for i in range(n):
                a = base + j * (n + 1) + i
                lines.append("f %d %d %d %d" % (a, a + 1, a + n + 2, a + n + 1))
        base += (n + 1) ** 2
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def test_lightmap_at_vertices(radbake, vertex_probes, lightmap_at_vertices, tmp):
    room = os.path.join(tmp, "room.obj")
    write_room(room)
    probes_path, bake, flat = (os.path.join(tmp, n) for n in ("room.probes", "room_bake", "room_flat"))
    run([vertex_probes, room, probes_path])
    # Every texel evaluated (no interpolation), 16 per metre: the correct lookup is within 1 %
    # of the vertex bake inside the walls, one half a texel off in u alone 3.7 %, in u and v 6 %.
    run([radbake, "bake", room, "--quality", "draft", "--texel-density", "16", "--texel-tolerance", "0",
         "--threads", "2", "--quiet", "-o", bake])
    out = os.path.join(tmp, "room_lookup.csv")
    run([lightmap_at_vertices, bake, probes_path, out])
    rows = vertex_error.read_csv_rows(out)
    probes = read_probes(probes_path)
    check(len(rows) == len(probes) == 6 * 25, "lightmap: %d rows for %d probes" % (len(rows), len(probes)))
    check(all([float(r[k]) for k in ("x", "y", "z", "nx", "ny", "nz")] == p for r, p in zip(rows, probes)),
          "lightmap: the rows are not the probe file's positions and normals")
    vertex = vertex_error.vertex_rows(bake, rows)  # pi x the .ply value of the same vertex
    inside, worst = 0, (0.0, None)
    for r, v in zip(rows, vertex):
        p = [float(r[k]) for k in ("x", "y", "z")]
        if all(0.1 < c < 0.9 or abs(float(r[n])) == 1.0 for c, n in zip(p, ("nx", "ny", "nz"))):
            inside += 1  # not on the border of its wall
            e = abs(vertex_error.grey(r) - vertex_error.grey(v)) / vertex_error.grey(v)
            worst = max(worst, (e, p))
    print("lightmap: %d vertices inside the walls, worst lookup against the vertex bake %.2f %% at %s" % (
        inside, 100 * worst[0], worst[1]))
    check(inside == 6 * 9, "lightmap: %d vertices inside the walls, want 54" % inside)
    check(worst[0] < 0.02, "lightmap: lookup %.2f %% from the vertex bake at %s" % (100 * worst[0], worst[1]))
    # A bake without lightmaps: refused, naming the mesh.
    run([radbake, "bake", room, "--quality", "draft", "--no-lightmaps", "--quiet", "-o", flat])
    result = subprocess.run([lightmap_at_vertices, flat, probes_path, out], capture_output=True, text=True)
    check(result.returncode == 1 and "has no lightmap chart" in result.stderr and "mesh '" in result.stderr,
          "lightmap: a bake without lightmaps: exit %d, %s" % (result.returncode, result.stderr.strip()))
    bad = os.path.join(tmp, "bad.probes")
    with open(bad, "w") as f:
        f.write("0.5 0.5\n")
    result = subprocess.run([lightmap_at_vertices, bake, bad, out], capture_output=True, text=True)
    check(result.returncode == 1 and "bad.probes:1:" in result.stderr,
          "lightmap: a bad probe file: exit %d, %s" % (result.returncode, result.stderr.strip()))


def test_reference_topup(reference_mc, tmp):
    """On the tessellated box: two wall probes and two on the ceiling above its lamp (lit only
    through a 1 cm gap, far noisier at one path count), topped up to 3 %: the dim ones get paths,
    the rest keep their bytes, every lit probe ends within the asked noise (x 1.3: the noise is
    itself estimated), and the pooling is the path-weighted mean."""
    obj = os.path.join(tmp, "topup.obj")
    run([sys.executable, os.path.join(HERE, "gen_cornell_tessellated.py"), obj])
    probes = os.path.join(tmp, "topup.probes")
    with open(probes, "w") as f:
        f.write("# two on walls, two on the ceiling above the lamp\n0 0.5 0.5 1 0 0\n0.5 0.5 0 0 0 1\n"
                "0.5625 1 0.5625 0 -1 0\n0.4375 1 0.4375 0 -1 0\n")
    reference, topped = os.path.join(tmp, "ref.csv"), os.path.join(tmp, "topped.csv")
    run([reference_mc, obj, probes, "--samples", "1024", "--threads", "2", "--seed", "1", "-o", reference])
    run([sys.executable, os.path.join(HERE, "reference_topup.py"), obj, probes, reference, "--samples", "1024",
         "--max-se", "0.03", "--lit", "median", "--threads", "2", "--reference-mc", reference_mc, "-o", topped])
    import reference_topup  # noqa: E402 (here: the module is only needed by this test)
    with open(reference) as f:
        before_lines = f.read().splitlines()
    with open(topped) as f:
        after_lines = f.read().splitlines()
    before, after = vertex_error.read_csv_rows(reference), vertex_error.read_csv_rows(topped)
    check(len(after) == 4 and before_lines[0] == after_lines[0], "topup: rows and header kept")
    lit, _ = vertex_error.lit_mask(before, "median")
    for i in range(4):
        rel0, rel1 = reference_topup.relative_se(before[i]), reference_topup.relative_se(after[i])
        if rel0 <= 0.03 or not lit[i]:
            check(before_lines[i + 1] == after_lines[i + 1], "topup: probe %d (%.3f) changed" % (i, rel0))
        else:
            check(rel1 < rel0 and rel1 <= 0.03 * 1.3, "topup: probe %d noise %.3f -> %.3f" % (i, rel0, rel1))
    check(all(lit[2:]) and any(reference_topup.relative_se(r) > 0.03 for r in before[2:]),
          "topup: the ceiling probes were lit and noisy")
    row = {"r": "1", "g": "2", "b": "3", "se_r": "0.3", "se_g": "0.4", "se_b": "0.5"}
    extra = {"r": "2", "g": "2", "b": "2", "se_r": "0.1", "se_g": "0.1", "se_b": "0.1"}
    pooled = reference_topup.pooled(row, 1000, extra, 3000)
    check(abs(float(pooled["r"]) - 1.75) < 1e-9 and abs(float(pooled["b"]) - 2.25) < 1e-9,
          "topup: pooled means %s" % pooled)
    check(abs(float(pooled["se_r"]) - math.sqrt(300.0 ** 2 + 300.0 ** 2) / 4000) < 1e-3,  # printed %.3g
          "topup: pooled error %s" % pooled["se_r"])


def main(argv):
    if len(argv) != 5:
        sys.stderr.write("usage: test_scale_tools.py RADBAKE VERTEX_PROBES REFERENCE_MC LIGHTMAP_AT_VERTICES\n")
        return 2
    radbake, vertex_probes, reference_mc, lightmap_at_vertices = argv[1:]
    with tempfile.TemporaryDirectory() as tmp:
        test_cornell(radbake, vertex_probes, tmp)
        test_building(radbake, reference_mc, tmp)
        test_lightmap_at_vertices(radbake, vertex_probes, lightmap_at_vertices, tmp)
        test_reference_topup(reference_mc, tmp)
    test_vertex_error()
    print("%d failure(s)" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

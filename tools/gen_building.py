#!/usr/bin/env python3
"""Writes a generated building (issue 11's growth yardstick) as VRML97.

    python3 tools/gen_building.py OUT.wrl --rooms NX NY [--panels K] [--boxes B] [--seed S]
                                  [--lamps all|one|none] [--windows]

A grid of NX x NY rooms (NX along x, NY along z, y up; each 4 m x 4 m, 3 m high; walls 0.2 m
thick), every pair of neighbouring rooms joined by a doorway (1 m x 2.1 m, through the wall:
two jambs, a head and a threshold, so the building stays closed and light passes between rooms
only through doorways). Every room is a closed shell facing inward: floor and ceiling K x K
quads, each wall K x K quads (a wall with a doorway: the panels beside and above the opening,
each about 4/K m wide, so the count stays close to K x K); under each ceiling a lamp (a 0.5 m x
0.5 m emissive quad, emissiveColor 1, facing down, 2 cm below the ceiling); on each floor up to
B boxes (default 3; 5 faces each, no bottom, randomly sized and turned about y, placed clear of
each other and of the doorways), their faces ceil(K/4) quads a side. Each face has its own
vertices (none shared across an edge). Surfaces are one-sided (`solid TRUE`, the default) and
flat (`creaseAngle 0`). --lamps one lights the first room's lamp only and --lamps none no lamp
(the others stay as white unlit fixtures): the scenes where the cost must follow the light.
--windows cuts a window (1.2 m wide, 1.2 m high, its sill 0.9 m up) in the middle of every outside
wall and glazes it with a pane (transparency 0.7, diffuseColor 0.1), for daylight (issue 30:
`radbake bake OUT.wrl --sky overcast --sun 135,35 --lamps none`).

Prints the counts; the triangle count is twice the quad count (the readers split every
planar quad into two triangles). The arguments used for the scale yardsticks (docs/scale.md):

    --rooms 2 1 --panels 6      ->     1,108 triangles  (about 1k)
    --rooms 2 2 --panels 7      ->     2,912 triangles  (about 3k)
    --rooms 4 4 --panels 9      ->    19,808 triangles  (about 20k)
    --rooms 10 10 --panels 12   ->   192,710 triangles  (about 200k)
    --rooms 20 20 --panels 13   ->   969,156 triangles  (about 1M; a 33 MB file, 12 s to write)

Deterministic: the same arguments (and --seed, default 1) give the same bytes. Python
standard library only.
"""
import argparse
import math
import random
import sys

ROOM_W = 4.0   # x
ROOM_D = 4.0   # z
ROOM_H = 3.0   # y
WALL_T = 0.2
DOOR_W = 1.0
DOOR_H = 2.1
LAMP = 0.5
LAMP_DROP = 0.02

X, Y, Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)


def add(*vs):
    return tuple(sum(c) for c in zip(*vs))


def scale(v, s):
    return tuple(c * s for c in v)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


class MeshBuilder:
    """One IndexedFaceSet: points and quads, every added rectangle with its own vertices."""

    def __init__(self):
        self.points = []
        self.quads = []

    def rect(self, origin, u, v, nu, nv, normal):
        """o + s u + t v cut into nu x nv quads, facing `normal` (u, v swapped if needed)."""
        if dot(cross(u, v), normal) < 0:
            u, v, nu, nv = v, u, nv, nu
        nu, nv = max(1, nu), max(1, nv)
        first = len(self.points)
        for j in range(nv + 1):
            for i in range(nu + 1):
                self.points.append(add(origin, scale(u, i / nu), scale(v, j / nv)))
        row = nu + 1
        for j in range(nv):
            for i in range(nu):
                a = first + j * row + i
                self.quads.append((a, a + 1, a + row + 1, a + row))


def panels(length, k, full):
    """Panels along `length` when `full` gets k of them: about the same panel size everywhere."""
    return max(1, int(math.ceil(k * length / full - 1e-9)))


def wall(mesh, base, along, length, normal, k, door, window=None):
    """A wall base + s along + t y, s in [0, length], t in [0, H]; door = (s0, s1) or None;
    window = (s0, s1, t0, t1) or None (an opening with a sill, for an outside wall)."""
    def sub(s0, s1, t0, t1):
        mesh.rect(add(base, scale(along, s0), scale(Y, t0)), scale(along, s1 - s0), scale(Y, t1 - t0),
                  panels(s1 - s0, k, length), panels(t1 - t0, k, ROOM_H), normal)
    if window is not None:
        s0, s1, t0, t1 = window
        sub(0.0, s0, 0.0, ROOM_H)
        sub(s1, length, 0.0, ROOM_H)
        sub(s0, s1, 0.0, t0)
        sub(s0, s1, t1, ROOM_H)
    elif door is None:
        sub(0.0, length, 0.0, ROOM_H)
    else:
        s0, s1 = door
        sub(0.0, s0, 0.0, ROOM_H)
        sub(s1, length, 0.0, ROOM_H)
        sub(s0, s1, DOOR_H, ROOM_H)


def tunnel(mesh, start, along, across, s0, s1):
    """The doorway through a wall: from `start` (on the wall's first face, s = 0 there) `across`
    the wall's thickness; the opening spans s0..s1 along `along` and 0..DOOR_H in y. Faces inward."""
    depth = scale(across, WALL_T)
    width = scale(along, s1 - s0)
    low = add(start, scale(along, s0))
    high = add(start, scale(along, s1))
    mesh.rect(low, depth, scale(Y, DOOR_H), 1, 1, along)                         # jamb at s0, facing +along
    mesh.rect(high, depth, scale(Y, DOOR_H), 1, 1, scale(along, -1))             # jamb at s1
    mesh.rect(add(low, scale(Y, DOOR_H)), width, depth, 1, 1, (0.0, -1.0, 0.0))  # head, facing down
    mesh.rect(low, width, depth, 1, 1, (0.0, 1.0, 0.0))                          # threshold, facing up


def box(mesh, cx, cz, w, h, d, degrees, k):
    a = math.radians(degrees)
    ex = (math.cos(a), 0.0, -math.sin(a))
    ez = (math.sin(a), 0.0, math.cos(a))
    ux, uy, uz = scale(ex, w), scale(Y, h), scale(ez, d)
    corner = add((cx, 0.0, cz), scale(ex, -w / 2), scale(ez, -d / 2))
    n = max(1, int(math.ceil(k / 4)))
    mesh.rect(add(corner, uy), uz, ux, n, n, Y)
    mesh.rect(add(corner, ux), uy, uz, n, n, ex)
    mesh.rect(corner, uz, uy, n, n, scale(ex, -1))
    mesh.rect(add(corner, uz), ux, uy, n, n, ez)
    mesh.rect(corner, uy, ux, n, n, scale(ez, -1))


def place_boxes(rng, count, doors_local):
    """Up to `count` boxes (cx, cz, w, h, d, degrees) in room-local coordinates, bounding circles
    apart from each other, from the walls, and from the 1.2 m in front of every doorway."""
    boxes = []
    attempts = 0
    while len(boxes) < count and attempts < 200:
        attempts += 1
        w, d, h = rng.uniform(0.4, 0.9), rng.uniform(0.4, 0.9), rng.uniform(0.4, 1.4)
        degrees = rng.uniform(0.0, 90.0)
        r = 0.5 * math.hypot(w, d)
        cx, cz = rng.uniform(0.15 + r, ROOM_W - 0.15 - r), rng.uniform(0.15 + r, ROOM_D - 0.15 - r)
        if any(math.hypot(cx - b[0], cz - b[1]) < r + 0.5 * math.hypot(b[2], b[4]) + 0.1 for b in boxes):
            continue
        # Door zones: (x0, x1, z0, z1) rectangles in front of the doorways.
        if any(cx + r > x0 and cx - r < x1 and cz + r > z0 and cz - r < z1 for x0, x1, z0, z1 in doors_local):
            continue
        boxes.append((cx, cz, w, h, d, degrees))
    return boxes


WINDOW_W, WINDOW_H, WINDOW_SILL = 1.2, 1.2, 0.9


def build(nx, nz, k, box_count, seed, windows=False):
    rng = random.Random(seed)
    pitch_x, pitch_z = ROOM_W + WALL_T, ROOM_D + WALL_T
    # Doorway offsets (start of the opening along the wall), one per shared wall.
    margin = 0.3
    door_x = {}  # wall between (i, j) and (i + 1, j): opening along z, room-local
    door_z = {}  # wall between (i, j) and (i, j + 1): opening along x, room-local
    for j in range(nz):
        for i in range(nx):
            if i + 1 < nx:
                door_x[i, j] = rng.uniform(margin, ROOM_D - margin - DOOR_W)
            if j + 1 < nz:
                door_z[i, j] = rng.uniform(margin, ROOM_W - margin - DOOR_W)
    shells, lamps, boxes = [], [], []
    glass = MeshBuilder()
    for j in range(nz):
        for i in range(nx):
            x0, z0 = i * pitch_x, j * pitch_z
            x1, z1 = x0 + ROOM_W, z0 + ROOM_D
            shell = MeshBuilder()
            shell.rect((x0, 0.0, z0), scale(Z, ROOM_D), scale(X, ROOM_W), k, k, Y)                    # floor
            shell.rect((x0, ROOM_H, z0), scale(X, ROOM_W), scale(Z, ROOM_D), k, k, (0.0, -1.0, 0.0))  # ceiling
            west = door_x.get((i - 1, j))
            east = door_x.get((i, j))
            south = door_z.get((i, j - 1))
            north = door_z.get((i, j))
            span = lambda s: None if s is None else (s, s + DOOR_W)
            # An outside wall (no neighbour there) gets a window when asked.
            opening = lambda length: (0.5 * (length - WINDOW_W), 0.5 * (length + WINDOW_W), WINDOW_SILL,
                                      WINDOW_SILL + WINDOW_H)
            out_w, out_e = windows and i == 0, windows and i == nx - 1
            out_s, out_n = windows and j == 0, windows and j == nz - 1
            wall(shell, (x0, 0.0, z0), Z, ROOM_D, X, k, span(west), opening(ROOM_D) if out_w else None)
            wall(shell, (x1, 0.0, z0), Z, ROOM_D, (-1.0, 0.0, 0.0), k, span(east), opening(ROOM_D) if out_e else None)
            wall(shell, (x0, 0.0, z0), X, ROOM_W, Z, k, span(south), opening(ROOM_W) if out_s else None)
            wall(shell, (x0, 0.0, z1), X, ROOM_W, (0.0, 0.0, -1.0), k, span(north), opening(ROOM_W) if out_n else None)
            for outside, base, along, length, normal in (
                    (out_w, (x0, 0.0, z0), Z, ROOM_D, X), (out_e, (x1, 0.0, z0), Z, ROOM_D, (-1.0, 0.0, 0.0)),
                    (out_s, (x0, 0.0, z0), X, ROOM_W, Z), (out_n, (x0, 0.0, z1), X, ROOM_W, (0.0, 0.0, -1.0))):
                if outside:
                    s0, s1, t0, t1 = opening(length)
                    glass.rect(add(base, scale(along, s0), scale(Y, t0)), scale(along, s1 - s0), scale(Y, t1 - t0),
                               1, 1, normal)
            if east is not None:
                tunnel(shell, (x1, 0.0, z0), Z, X, east, east + DOOR_W)
            if north is not None:
                tunnel(shell, (x0, 0.0, z1), X, Z, north, north + DOOR_W)
            shells.append(shell)
            lamp = MeshBuilder()
            lamp.rect((x0 + 0.5 * (ROOM_W - LAMP), ROOM_H - LAMP_DROP, z0 + 0.5 * (ROOM_D - LAMP)),
                      scale(X, LAMP), scale(Z, LAMP), 1, 1, (0.0, -1.0, 0.0))
            lamps.append(lamp)
            zones = []
            if west is not None: zones.append((0.0, 1.2, west, west + DOOR_W))
            if east is not None: zones.append((ROOM_W - 1.2, ROOM_W, east, east + DOOR_W))
            if south is not None: zones.append((south, south + DOOR_W, 0.0, 1.2))
            if north is not None: zones.append((north, north + DOOR_W, ROOM_D - 1.2, ROOM_D))
            room_boxes = MeshBuilder()
            for cx, cz, w, h, d, degrees in place_boxes(rng, box_count, zones):
                box(room_boxes, x0 + cx, z0 + cz, w, h, d, degrees, k)
            colour = (round(rng.uniform(0.2, 0.8), 3), round(rng.uniform(0.2, 0.8), 3), round(rng.uniform(0.2, 0.8), 3))
            boxes.append((room_boxes, colour))
    return shells, lamps, boxes, glass


def fmt(x):
    text = "%.7g" % x
    return "0" if text == "-0" else text


def write_ifs(out, mesh, appearance):
    out.append("Shape {\n  appearance %s\n  geometry IndexedFaceSet {\n    creaseAngle 0\n    coord Coordinate { point [\n" % appearance)
    out.append(",\n".join("      %s %s %s" % (fmt(p[0]), fmt(p[1]), fmt(p[2])) for p in mesh.points))
    out.append(" ] }\n    coordIndex [\n")
    out.append(",\n".join("      %d, %d, %d, %d, -1" % q for q in mesh.quads))
    out.append(" ]\n  }\n}\n")


def main(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out", help="the .wrl to write")
    p.add_argument("--rooms", nargs=2, type=int, required=True, metavar=("NX", "NY"))
    p.add_argument("--panels", type=int, default=4, metavar="K", help="quads a side on every wall, floor and ceiling")
    p.add_argument("--boxes", type=int, default=3, metavar="B", help="boxes per room")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--windows", action="store_true",
                   help="a glazed window in every outside wall (transparency 0.7), for daylight")
    p.add_argument("--lamps", choices=("all", "one", "none"), default="all",
                   help="which rooms' lamps emit: all (default), the first room's only, or none (the lamps "
                        "stay, as white unlit fixtures)")
    args = p.parse_args(argv[1:])
    nx, nz = args.rooms
    if nx < 1 or nz < 1 or args.panels < 1 or args.boxes < 0:
        p.error("--rooms needs two counts >= 1, --panels >= 1, --boxes >= 0")
    shells, lamps, boxes, glass = build(nx, nz, args.panels, args.boxes, args.seed, args.windows)
    lamps_arg = ("" if args.lamps == "all" else " --lamps " + args.lamps) + (" --windows" if args.windows else "")
    out = ["#VRML V2.0 utf8\n",
           "# generated building: tools/gen_building.py --rooms %d %d --panels %d --boxes %d --seed %d%s\n" % (
               nx, nz, args.panels, args.boxes, args.seed, lamps_arg),
           "WorldInfo { title \"building %dx%d rooms, %d panels\" }\n" % (nx, nz, args.panels),
           # From inside the first room, looking towards the far corner.
           "Viewpoint { position 0.4 1.6 0.4 orientation 0 1 0 -2.356 description \"room 0\" }\n"]
    quads = points = 0
    for index, shell in enumerate(shells):
        write_ifs(out, shell, "DEF WALL Appearance { material Material { diffuseColor 0.7 0.7 0.7 } }"
                  if index == 0 else "USE WALL")
        lit = args.lamps == "all" or (args.lamps == "one" and index == 0)
        if lit:
            write_ifs(out, lamps[index], "DEF LAMP Appearance { material Material { diffuseColor 0 0 0 emissiveColor 1 1 1 } }"
                      if index == 0 else "USE LAMP")
        else:
            first_unlit = index == (1 if args.lamps == "one" else 0)
            write_ifs(out, lamps[index], "DEF UNLIT Appearance { material Material { diffuseColor 0.8 0.8 0.8 } }"
                      if first_unlit else "USE UNLIT")
        room_boxes, colour = boxes[index]
        if room_boxes.quads:
            write_ifs(out, room_boxes, "Appearance { material Material { diffuseColor %s %s %s } }" % tuple(fmt(c) for c in colour))
        for mesh in (shell, lamps[index], room_boxes):
            quads += len(mesh.quads)
            points += len(mesh.points)
    if glass.quads:
        write_ifs(out, glass, "Appearance { material Material { diffuseColor 0.1 0.1 0.1 transparency 0.7 } }")
        quads += len(glass.quads)
        points += len(glass.points)
    with open(args.out, "w", newline="\n") as f:
        f.write("".join(out))
    print("%s: %d x %d rooms, %d panels: %d quads, %d triangles, %d vertices" % (
        args.out, nx, nz, args.panels, quads, 2 * quads, points))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

#!/usr/bin/env python3
"""Writes the "tessellated Cornell box" of issue 11 (the yardstick of issues 11-13) as OBJ + MTL.

    python3 tools/gen_cornell_tessellated.py OUT.obj      # also writes OUT.mtl beside it

The scene, in metres, y up, seen from the front (a camera at z > 1 looking down -z):
  - a closed 1 x 1 x 1 room [0,1]^3, every wall facing inward: white (Kd 0.75) floor (y=0),
    ceiling (y=1), back wall (z=0) and front wall (z=1); red (0.75 0.15 0.15) left wall (x=0);
    green (0.15 0.75 0.15) right wall (x=1);
  - a one-sided 0.2 x 0.2 emitter centred under the ceiling at y = 0.99, facing down
    (Ke 10 10 10, Kd 0);
  - a tall box 0.3 x 0.6 x 0.3 rotated +17 degrees about y at (0.337, 0.372) (back left) and a
    short box 0.3^3 rotated -17 degrees at (0.666, 0.698) (front right), each of 5 faces facing
    outward (no bottom), standing on the floor. Angles follow the right-hand rule about +y
    (counter-clockwise seen from above). Centres and angles are the classic Cornell box's
    measured blocks (centres (368.5, 351.25) and (185.5, 169) in its 556 x 559.2 floor, edges
    at 16.7 degrees), turned 180 degrees about y so that its red wall (x = 556 there) is at
    x = 0 here;
  - every wall a 16 x 16 grid of quads, the light 4 x 4, the short box's faces and the tall
    box's top 8 x 8, the tall box's sides 8 (across) x 16 (up);
  - every face (wall, light, box side) is its own OBJ object with its own vertices and one
    vertex normal, so that no importer welds vertices across an edge: 2,448 quads and 2,857
    vertices in all (asserted below).
Deterministic: the same bytes on every run. Python standard library only.
"""
import math
import os
import sys

WHITE = (0.75, 0.75, 0.75)
RED = (0.75, 0.15, 0.15)
GREEN = (0.15, 0.75, 0.15)

EXPECTED_QUADS = 2448
EXPECTED_VERTICES = 2857


def add(*vs):
    return tuple(sum(c) for c in zip(*vs))


def scale(v, s):
    return tuple(c * s for c in v)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def normalize(v):
    length = math.sqrt(dot(v, v))
    return scale(v, 1.0 / length)


class Face:
    """A parallelogram o + s u + t v (s, t in [0, 1]) cut into nu x nv quads; its front is u x v."""

    def __init__(self, name, material, origin, u, v, nu, nv):
        self.name, self.material = name, material
        self.normal = normalize(cross(u, v))
        self.vertices = [add(origin, scale(u, i / nu), scale(v, j / nv)) for j in range(nv + 1) for i in range(nu + 1)]
        row = nu + 1
        # Counter-clockwise seen from the front (u x v side).
        self.quads = [(j * row + i, j * row + i + 1, (j + 1) * row + i + 1, (j + 1) * row + i)
                      for j in range(nv) for i in range(nu)]


def room_faces():
    x, y, z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
    o = (0.0, 0.0, 0.0)
    return [
        Face("floor", "white", o, z, x, 16, 16),                  # z x x = +y
        Face("ceiling", "white", (0.0, 1.0, 0.0), x, z, 16, 16),  # x x z = -y
        Face("back_wall", "white", o, x, y, 16, 16),              # x x y = +z
        Face("front_wall", "white", (0.0, 0.0, 1.0), y, x, 16, 16),  # y x x = -z
        Face("left_wall", "red", o, y, z, 16, 16),                # y x z = +x
        Face("right_wall", "green", (1.0, 0.0, 0.0), z, y, 16, 16),  # z x y = -x
        Face("light", "light", (0.4, 0.99, 0.4), scale(x, 0.2), scale(z, 0.2), 4, 4),  # facing -y
    ]


def box_faces(name, centre_x, centre_z, width, height, depth, degrees, n_across, n_up):
    """The 5 outward faces (no bottom) of a box standing on y = 0, rotated about y."""
    a = math.radians(degrees)
    ex = (math.cos(a), 0.0, -math.sin(a))  # R_y(a) applied to +x
    ez = (math.sin(a), 0.0, math.cos(a))   # R_y(a) applied to +z
    ey = (0.0, 1.0, 0.0)
    c = (centre_x, 0.0, centre_z)
    u_x, u_y, u_z = scale(ex, width), scale(ey, height), scale(ez, depth)
    corner = add(c, scale(ex, -width / 2), scale(ez, -depth / 2))  # the (-x, -z) bottom corner
    return [
        Face(name + "_top", "white", add(corner, u_y), u_z, u_x, n_across, n_across),  # ez x ex = +y
        Face(name + "_px", "white", add(corner, u_x), u_y, u_z, n_up, n_across),       # ey x ez = +ex
        Face(name + "_nx", "white", corner, u_z, u_y, n_across, n_up),                 # ez x ey = -ex
        Face(name + "_pz", "white", add(corner, u_z), u_x, u_y, n_across, n_up),       # ex x ey = +ez
        Face(name + "_nz", "white", corner, u_y, u_x, n_up, n_across),                 # ey x ex = -ez
    ]


def footprint(face_list):
    """The box's footprint corners (x, z) from its top face's corner vertices."""
    top = face_list[0]
    n = int(math.isqrt(len(top.vertices)))
    corners = [top.vertices[0], top.vertices[n - 1], top.vertices[-1], top.vertices[-n]]
    return [(p[0], p[2]) for p in corners]


def separated(poly_a, poly_b):
    """Separating-axis test for two convex polygons in the plane."""
    for poly in (poly_a, poly_b):
        for i in range(len(poly)):
            (x0, z0), (x1, z1) = poly[i], poly[(i + 1) % len(poly)]
            axis = (z1 - z0, x0 - x1)
            pa = [axis[0] * p[0] + axis[1] * p[1] for p in poly_a]
            pb = [axis[0] * p[0] + axis[1] * p[1] for p in poly_b]
            if max(pa) < min(pb) or max(pb) < min(pa):
                return True
    return False


def build():
    tall = box_faces("tall_box", 0.337, 0.372, 0.3, 0.6, 0.3, 17.0, 8, 16)
    short = box_faces("short_box", 0.666, 0.698, 0.3, 0.3, 0.3, -17.0, 8, 8)
    faces = room_faces() + tall + short
    # The geometry the issue describes, checked rather than trusted.
    quads = sum(len(f.quads) for f in faces)
    vertices = sum(len(f.vertices) for f in faces)
    assert quads == EXPECTED_QUADS, quads
    assert vertices == EXPECTED_VERTICES, vertices
    for f in faces:
        for p in f.vertices:
            assert all(-1e-12 <= c <= 1.0 + 1e-12 for c in p), (f.name, p)
        for q in f.quads:  # every quad's winding agrees with the face's normal
            a, b, c = (f.vertices[k] for k in q[:3])
            assert dot(cross(tuple(bb - aa for aa, bb in zip(a, b)), tuple(cc - aa for aa, cc in zip(a, c))), f.normal) > 0
    centre = (0.5, 0.5, 0.5)
    for f in faces[:6]:  # walls face the room's centre
        assert dot(f.normal, tuple(c - p for c, p in zip(centre, f.vertices[0]))) > 0, f.name
    assert faces[6].normal == (0.0, -1.0, 0.0)
    for box in (tall, short):  # box sides face away from the box's axis
        top = box[0]
        axis = add(scale(top.vertices[0], 0.5), scale(top.vertices[-1], 0.5))
        for f in box[1:]:
            mid = add(scale(f.vertices[0], 0.5), scale(f.vertices[-1], 0.5))
            assert dot(f.normal, (mid[0] - axis[0], 0.0, mid[2] - axis[2])) > 0, f.name
    assert separated(footprint(tall), footprint(short)), "the boxes overlap"
    return faces


def fmt(x):
    text = "%.9g" % x
    return "0" if text == "-0" else text


def write(obj_path, faces):
    base = os.path.splitext(obj_path)[0]
    mtl_path = base + ".mtl"
    mtl_name = os.path.basename(mtl_path)
    with open(mtl_path, "w", newline="\n") as f:
        f.write("# tessellated Cornell box (radbake issue 11), tools/gen_cornell_tessellated.py\n")
        for name, kd, ke in (("white", WHITE, (0, 0, 0)), ("red", RED, (0, 0, 0)), ("green", GREEN, (0, 0, 0)),
                             ("light", (0, 0, 0), (10, 10, 10))):
            f.write("\nnewmtl %s\nKa 0 0 0\nKd %s\nKs 0 0 0\nKe %s\nillum 1\n" % (
                name, " ".join(fmt(c) for c in kd), " ".join(fmt(c) for c in ke)))
    lines = ["# tessellated Cornell box (radbake issue 11), tools/gen_cornell_tessellated.py",
             "# %d quads, %d vertices, every face with its own vertices" % (EXPECTED_QUADS, EXPECTED_VERTICES),
             "mtllib " + mtl_name]
    first_vertex = 1
    for index, face in enumerate(faces):
        lines.append("o " + face.name)
        lines.append("usemtl " + face.material)
        lines.extend("v %s %s %s" % tuple(fmt(c) for c in p) for p in face.vertices)
        lines.append("vn %s %s %s" % tuple(fmt(c) for c in face.normal))
        normal = index + 1
        lines.extend("f " + " ".join("%d//%d" % (first_vertex + k, normal) for k in q) for q in face.quads)
        first_vertex += len(face.vertices)
    with open(obj_path, "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")
    return mtl_path


def main(argv):
    if len(argv) != 2 or argv[1].startswith("-"):
        sys.stderr.write("usage: gen_cornell_tessellated.py OUT.obj\n")
        return 2
    faces = build()
    mtl = write(argv[1], faces)
    print("%s (+ %s): %d faces, %d quads (%d triangles), %d vertices" % (
        argv[1], mtl, len(faces), EXPECTED_QUADS, 2 * EXPECTED_QUADS, EXPECTED_VERTICES))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

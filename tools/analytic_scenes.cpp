// analytic_scenes: writes scenes/analytic/ (VRML97 scenes, probe files and exact answers).
//
//   analytic_scenes OUT_DIR        (normally: analytic_scenes scenes/analytic)
//
// Every expected probe value is an exact point-to-polygon form factor of the scene's own
// (tessellated) polygons, so no discretisation error enters the answers:
//   H(x) = pi L_e F_point(x, P),  F_point = 1/(2 pi) sum_i gamma_i n . (R_i x R_i+1)/|R_i x R_i+1|
// (Lambert's contour formula: R_i = v_i - x, gamma_i the angle between R_i and R_i+1; valid
// when P lies wholly in front of the tangent plane at x, which holds in every scene here).
// The program checks its formula against the published area-to-area values before writing
// (it integrates F_point over the receiver with Gauss-Legendre quadrature) and writes those
// checks into each file's header.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "core/math.h"

namespace {

using radbake::DVec3;
using radbake::kPi;
using Polygon = std::vector<DVec3>;

double pointFormFactor(const DVec3& x, const DVec3& n, const Polygon& polygon) {
    double sum = 0.0;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const DVec3 a = polygon[i] - x, b = polygon[(i + 1) % polygon.size()] - x;
        const DVec3 c = glm::cross(a, b);
        const double length = glm::length(c);
        if (length == 0.0) continue;  // x on the edge's line: that edge contributes nothing
        const double gamma = std::atan2(length, glm::dot(a, b));
        sum += gamma * glm::dot(n, c) / length;
    }
    return std::abs(sum) / (2.0 * kPi);
}

// Gauss-Legendre nodes/weights on [0, 1] (Newton on P_n).
void gaussLegendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
    nodes.assign(n, 0.0);
    weights.assign(n, 0.0);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            const double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-16) break;
        }
        nodes[i] = 0.5 * (1.0 - z);
        weights[i] = 1.0 / ((1.0 - z * z) * dp * dp);  // 2/((1-z^2)P'^2), halved for [0,1]
    }
}

// Mean of f over a convex polygon (fan triangles, collapsed-square map, n x n Gauss points).
double polygonMean(const Polygon& polygon, const std::function<double(const DVec3&)>& f, int n) {
    std::vector<double> x, w;
    gaussLegendre(n, x, w);
    double integral = 0.0, area = 0.0;
    for (size_t t = 1; t + 1 < polygon.size(); ++t) {
        const DVec3 a = polygon[0], b = polygon[t], c = polygon[t + 1];
        const double tri_area = 0.5 * glm::length(glm::cross(b - a, c - a));
        area += tri_area;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                const double u = x[i], v = x[j] * (1.0 - u);  // Jacobian (1 - u)
                integral += w[i] * w[j] * (1.0 - u) * 2.0 * tri_area * f(a + (b - a) * u + (c - a) * v);
            }
    }
    return integral / area;
}

struct Probe {
    DVec3 p, n;
    double h = 0.0;  // expected irradiance (grey)
};

struct Surface {
    Polygon polygon;
    double rho = 0.0;
    double emission = 0.0;  // L_e
    bool solid = true;      // false: VRML `solid FALSE`, two-sided (lit, reflecting, emitting on both sides)
};

std::string fmt(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

std::string vrmlShapes(const std::vector<Surface>& surfaces) {
    std::ostringstream out;
    for (const Surface& s : surfaces) {
        out << "Shape {\n  appearance Appearance { material Material { diffuseColor " << fmt(s.rho) << ' '
            << fmt(s.rho) << ' ' << fmt(s.rho) << " emissiveColor " << fmt(s.emission) << ' ' << fmt(s.emission)
            << ' ' << fmt(s.emission) << " } }\n  geometry IndexedFaceSet {\n    solid " << (s.solid ? "TRUE" : "FALSE") << "\n"
            << "    coord Coordinate { point [\n";
        for (const DVec3& v : s.polygon) out << "      " << fmt(v.x) << ' ' << fmt(v.y) << ' ' << fmt(v.z) << ",\n";
        out << "    ] }\n    coordIndex [";
        for (size_t i = 0; i < s.polygon.size(); ++i) out << ' ' << i;
        out << " -1 ]\n  }\n}\n";
    }
    return out.str();
}

void writeFile(const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) {
        std::fprintf(stderr, "analytic_scenes: cannot write %s\n", path.string().c_str());
        std::exit(1);
    }
}

std::string commentBlock(const std::string& text) {
    std::istringstream in(text);
    std::string line, out;
    while (std::getline(in, line)) out += line.empty() ? "#\n" : "# " + line + "\n";
    return out;
}

void writeScene(const std::filesystem::path& dir, const std::string& name, const std::string& header,
                const std::vector<Surface>& surfaces, const std::vector<Probe>& probes, double rel_tol) {
    writeFile(dir / (name + ".wrl"), "#VRML V2.0 utf8\n" + commentBlock(header) + "\n" + vrmlShapes(surfaces));
    std::string probe_text = "# " + name + ": x y z nx ny nz (generated by tools/analytic_scenes.cpp)\n";
    std::string expected = "x,y,z,nx,ny,nz,r,g,b,rel_tol\n";
    for (const Probe& p : probes) {
        probe_text += fmt(p.p.x) + ' ' + fmt(p.p.y) + ' ' + fmt(p.p.z) + ' ' + fmt(p.n.x) + ' ' + fmt(p.n.y) + ' ' +
                      fmt(p.n.z) + '\n';
        expected += fmt(p.p.x) + ',' + fmt(p.p.y) + ',' + fmt(p.p.z) + ',' + fmt(p.n.x) + ',' + fmt(p.n.y) + ',' +
                    fmt(p.n.z) + ',' + fmt(p.h) + ',' + fmt(p.h) + ',' + fmt(p.h) + ',' + fmt(rel_tol) + '\n';
    }
    writeFile(dir / (name + ".probes"), probe_text);
    writeFile(dir / (name + ".expected.csv"), expected);
    std::printf("%-24s %4zu probes\n", name.c_str(), probes.size());
}

void check(bool ok, const std::string& what) {
    if (!ok) {
        std::fprintf(stderr, "analytic_scenes: self-check failed: %s\n", what.c_str());
        std::exit(1);
    }
}

Polygon square(const DVec3& origin, const DVec3& u, const DVec3& v) {
    return {origin, origin + u, origin + u + v, origin + v};  // CCW around u x v
}

// Receiver grid: cell centres of an n x n grid on the unit square z = 0, facing +z.
std::vector<Probe> gridProbes(int n, const Polygon& source, double pi_le) {
    std::vector<Probe> probes;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const DVec3 p((i + 0.5) / n, (j + 0.5) / n, 0.0), normal(0, 0, 1);
            probes.push_back({p, normal, pi_le * pointFormFactor(p, normal, source)});
        }
    return probes;
}

double meanOf(const std::vector<Probe>& probes) {
    double sum = 0.0;
    for (const Probe& p : probes) sum += p.h;
    return sum / probes.size();
}

const double kLeUnit = 1.0 / kPi;  // so B = pi L_e = 1 and H = F
constexpr int kGrid = 8;

// Two unit squares: the receiver z = 0 facing +z, the source hinged on the x axis at angle
// `degrees` to it (90: perpendicular), or parallel at height 1 when degrees == 0.
void squaresScene(const std::filesystem::path& dir, const std::string& name, double degrees, double published) {
    Polygon source;
    if (degrees == 0.0) {
        source = square(DVec3(0, 0, 1), DVec3(0, 1, 0), DVec3(1, 0, 0));  // faces -z
    } else {
        const double t = degrees * kPi / 180.0;
        // Spanned by x and (0, cos t, sin t); CCW around (0, sin t, -cos t), towards the receiver.
        source = square(DVec3(0, 0, 0), DVec3(0, std::cos(t), std::sin(t)), DVec3(1, 0, 0));
    }
    const Polygon receiver = square(DVec3(0, 0, 0), DVec3(1, 0, 0), DVec3(0, 1, 0));
    const double area_f = polygonMean(receiver, [&](const DVec3& x) { return pointFormFactor(x, DVec3(0, 0, 1), source); },
                                      degrees == 0.0 ? 24 : 64);
    check(std::abs(area_f - published) < (degrees == 0.0 ? 1e-12 : 2e-5) * published, name + " area form factor");
    const std::vector<Probe> probes = gridProbes(kGrid, source, 1.0);
    char text[2048];
    std::snprintf(text, sizeof text,
                  "%s: unit squares, %s.\n"
                  "Source: emits L_e = 1/pi (so B = 1), reflects 0. Receiver: the unit square z = 0 facing +z, black.\n"
                  "Closed form: area-to-area form factor F = %.15f (the value in issue 6; the classical\n"
                  "closed forms for aligned parallel plates and for plates sharing an edge at an angle, as in\n"
                  "J. R. Howell, \"A Catalog of Radiation Heat Transfer Configuration Factors\").\n"
                  "Probes: the %dx%d cell centres of the receiver. Expected H at each = pi L_e F_point(x, source),\n"
                  "Lambert's exact point-to-polygon formula (tools/analytic_scenes.cpp). Their mean, %.9f, differs\n"
                  "from F by the grid's own midpoint-rule error (%.2e); integrating F_point over the receiver\n"
                  "with Gauss-Legendre quadrature gives %.12f.\n",
                  name.c_str(),
                  degrees == 0.0 ? "parallel at distance 1"
                                 : (degrees == 90.0 ? "perpendicular, sharing the edge on the x axis"
                                                    : (std::string("hinged on the x axis at ") + fmt(degrees) + " degrees").c_str()),
                  published, kGrid, kGrid, meanOf(probes), meanOf(probes) - published, area_f);
    writeScene(dir, name, text,
               {{source, 0.0, kLeUnit}, {receiver, 0.0, 0.0}}, probes, 0.01);
}

Polygon disk(double radius, double z, int segments, bool facing_down) {
    Polygon polygon;
    for (int k = 0; k < segments; ++k) {
        const double a = 2.0 * kPi * (facing_down ? -k : k) / segments;
        polygon.push_back(DVec3(radius * std::cos(a), radius * std::sin(a), z));
    }
    return polygon;
}

void disksScene(const std::filesystem::path& dir) {
    const int segments = 64;
    const Polygon source = disk(1.0, 1.0, segments, true), receiver = disk(1.0, 0.0, segments, false);
    const double exact_disks = (3.0 - std::sqrt(5.0)) / 2.0;
    // Point-to-exact-disk closed form on the axis: F = R^2 / (R^2 + h^2) = 1/2; self-check.
    check(std::abs(pointFormFactor(DVec3(0), DVec3(0, 0, 1), disk(1.0, 1.0, 4096, true)) - 0.5) < 1e-6,
          "point to disk on the axis");
    const double polygon_f =
        polygonMean(receiver, [&](const DVec3& x) { return pointFormFactor(x, DVec3(0, 0, 1), source); }, 12);
    std::vector<Probe> probes;
    const int n = 10;
    const double inner = std::cos(kPi / segments);  // the 64-gon's inscribed radius
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const DVec3 p(-1.0 + (2.0 * i + 1.0) / n, -1.0 + (2.0 * j + 1.0) / n, 0.0);
            if (std::hypot(p.x, p.y) > inner) continue;
            probes.push_back({p, DVec3(0, 0, 1), pointFormFactor(p, DVec3(0, 0, 1), source)});
        }
    char text[2048];
    std::snprintf(text, sizeof text,
                  "coaxial_disks: two coaxial disks of radius 1 at distance 1, each a regular %d-gon inscribed in\n"
                  "the circle (one convex polygon; the receiver z = 0 faces +z, the source z = 1 faces -z).\n"
                  "Source: emits L_e = 1/pi (B = 1), reflects 0. Receiver: black.\n"
                  "Closed form for exact disks: F = (3 - sqrt 5)/2 = %.15f (Howell's catalogue, coaxial\n"
                  "parallel disks: F = (X - sqrt(X^2 - 4 (R2/R1)^2))/2, X = 1 + (1 + R2^2)/R1^2, R = r/h). The %d-gons' own\n"
                  "area-to-area F (Gauss-Legendre quadrature of the exact point-to-polygon formula over the\n"
                  "receiver) is %.12f, %.3e relative below the disks' value.\n"
                  "Probes: the cell centres of a 10x10 grid over [-1,1]^2 inside the inscribed circle (%zu).\n"
                  "Expected H = pi L_e F_point(x, source polygon), exact (Lambert's formula).\n",
                  segments, exact_disks, segments, polygon_f, (polygon_f - exact_disks) / exact_disks, probes.size());
    writeScene(dir, "coaxial_disks", text, {{source, 0.0, kLeUnit}, {receiver, 0.0, 0.0}}, probes, 0.01);
}

void cornerScene(const std::filesystem::path& dir) {
    const double le = 1.0;  // H = pi L_e F: this scene checks the factor pi too
    const Polygon source = square(DVec3(0, 0, 1), DVec3(0, 1, 0), DVec3(1, 0, 0));  // faces -z
    const Polygon floor = square(DVec3(-1, -1, 0), DVec3(3, 0, 0), DVec3(0, 3, 0));
    const double published = 0.138531605994892997;
    const double corner = pointFormFactor(DVec3(0), DVec3(0, 0, 1), source);
    check(std::abs(corner - published) < 1e-14, "point under the corner");
    std::vector<Probe> probes;
    probes.push_back({DVec3(0), DVec3(0, 0, 1), kPi * le * corner});
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) {
            const DVec3 p(-0.5 + 0.5 * i, -0.5 + 0.5 * j, 0.0);
            if (p == DVec3(0)) continue;
            probes.push_back({p, DVec3(0, 0, 1), kPi * le * pointFormFactor(p, DVec3(0, 0, 1), source)});
        }
    char text[2048];
    std::snprintf(text, sizeof text,
                  "corner_point: the point under a corner of a unit square at height 1.\n"
                  "Source: the unit square [0,1]^2 at z = 1 facing -z, emitting L_e = 1 (W sr^-1 m^-2), reflecting 0.\n"
                  "Floor: the black square [-1,2]^2 at z = 0 facing +z (it only carries the probes).\n"
                  "Closed form: the point-to-rectangle form factor from a point below a rectangle's corner,\n"
                  "F = 1/(2 pi) [A/sqrt(1+A^2) atan(B/sqrt(1+A^2)) + B/sqrt(1+B^2) atan(A/sqrt(1+B^2))], A = a/h,\n"
                  "B = b/h (Howell's catalogue, differential element\n"
                  "to a parallel rectangle); for A = B = 1, F = %s, so H = pi L_e F = %.15f.\n"
                  "The first probe is that point (0,0,0); the others, on a 5x5 grid of step 0.5 over [-0.5,1.5]^2,\n"
                  "have H = pi L_e F_point (Lambert's formula, exact).\n",
                  "0.138531605994892997", kPi * le * published);
    writeScene(dir, "corner_point", text, {{source, 0.0, le}, {floor, 0.0, 0.0}}, probes, 0.01);
}

DVec3 polygonNormal(const Polygon& p);
DVec3 polygonCentroid(const Polygon& p);

// Six faces of the unit cube [0,1]^3, each turned to face in.
std::vector<Polygon> cubeInward() {
    std::vector<Polygon> faces = {square(DVec3(0, 0, 0), DVec3(0, 1, 0), DVec3(1, 0, 0)),   // z = 0
            square(DVec3(0, 0, 1), DVec3(1, 0, 0), DVec3(0, 1, 0)),   // z = 1
            square(DVec3(0, 0, 0), DVec3(1, 0, 0), DVec3(0, 0, 1)),   // y = 0
            square(DVec3(0, 1, 0), DVec3(0, 0, 1), DVec3(1, 0, 0)),   // y = 1
            square(DVec3(0, 0, 0), DVec3(0, 0, 1), DVec3(0, 1, 0)),   // x = 0
            square(DVec3(1, 0, 0), DVec3(0, 1, 0), DVec3(0, 0, 1))};  // x = 1
    for (Polygon& f : faces)
        if (glm::dot(polygonNormal(f), DVec3(0.5) - polygonCentroid(f)) < 0) std::reverse(f.begin(), f.end());
    return faces;
}

DVec3 polygonNormal(const Polygon& p) { return glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0])); }
DVec3 polygonCentroid(const Polygon& p) {
    DVec3 c(0.0);
    for (const DVec3& v : p) c += v;
    return c / double(p.size());
}

std::vector<Probe> enclosureProbes(const std::vector<Polygon>& faces, double h, const DVec3& centre, int stride) {
    std::vector<Probe> probes;
    for (size_t f = 0; f < faces.size(); f += stride) {
        const Polygon& face = faces[f];
        const DVec3 n = polygonNormal(face), c = polygonCentroid(face);
        probes.push_back({c, n, h});
        if (face.size() == 4) {  // and two points towards opposite corners
            probes.push_back({c + (face[0] - c) * 0.8, n, h});
            probes.push_back({c + (face[2] - c) * 0.5, n, h});
        }
    }
    for (const DVec3& n : {DVec3(1, 0, 0), DVec3(-1, 0, 0), DVec3(0, 1, 0), DVec3(0, -1, 0), DVec3(0, 0, 1), DVec3(0, 0, -1)})
        probes.push_back({centre, n, h});
    return probes;
}

void furnaceScene(const std::filesystem::path& dir, double rho, const std::string& tag, double rel_tol) {
    std::vector<Surface> surfaces;
    for (const Polygon& face : cubeInward()) surfaces.push_back({face, rho, 1.0});
    const double h = kPi / (1.0 - rho);
    char text[2048];
    std::snprintf(text, sizeof text,
                  "furnace_%s: the inside of the closed unit cube [0,1]^3, every face (one quad, facing in)\n"
                  "emitting L_e = 1 and reflecting rho = %g.\n"
                  "Closed form (the white furnace): radiance is the same in every direction at every point,\n"
                  "L = L_e + rho L, so L = L_e/(1 - rho) and H = pi L = pi L_e/(1 - rho) = %.15f everywhere,\n"
                  "whatever the enclosure's shape or tessellation (it only needs to be closed).\n"
                  "Probes: three on each face (centre and two off-centre) facing in, and six at the cube's\n"
                  "centre facing along +-x, +-y, +-z (free-space probes see the same radiance).\n"
                  "Tolerance: %g relative at the default quality (issue 6: 1%% at rho = 0.99).\n",
                  tag.c_str(), rho, h, rel_tol);
    writeScene(dir, "furnace_" + tag, text, surfaces, enclosureProbes(cubeInward(), h, DVec3(0.5), 1), rel_tol);
}

// The same cube with every face turned OUT and two-sided (`solid FALSE`): its inside is the
// back of every face, so it is the white furnace again (the same closed form), seen through
// the back twins the bake gives two-sided faces.
void twoSidedFurnaceScene(const std::filesystem::path& dir) {
    const double rho = 0.5, h = kPi / (1.0 - rho);
    std::vector<Surface> surfaces;
    for (Polygon face : cubeInward()) {
        std::reverse(face.begin(), face.end());  // facing out
        surfaces.push_back({face, rho, 1.0, false});
    }
    char text[2048];
    std::snprintf(text, sizeof text,
                  "furnace_two_sided: the closed unit cube [0,1]^3, every face (one quad) facing OUT and two-sided\n"
                  "(solid FALSE), emitting L_e = 1 and reflecting rho = %g on both sides.\n"
                  "Closed form: inside, the backs of the faces make the white furnace, H = pi L_e/(1 - rho) =\n"
                  "%.15f everywhere (outside, the fronts see nothing: H = 0, which the tests check).\n"
                  "Probes: three on each face facing in, and six at the cube's centre facing along +-x, +-y, +-z.\n"
                  "Tolerance: 0.02 relative (issue 13).\n",
                  rho, h);
    writeScene(dir, "furnace_two_sided", text, surfaces, enclosureProbes(cubeInward(), h, DVec3(0.5), 1), 0.02);
}

// A thin two-sided wall lit from one side only: the unit square z = 0 facing +z (solid FALSE,
// rho 0.5) under a black one-sided emitter, the unit square at z = 1/2 facing -z (L_e = 1).
// The emitter is black and faces only the wall's front, so nothing comes back: the front's H is
// pi L_e F_point(x, emitter) exactly, and the back sees nothing at all (H = 0).
void thinWallScene(const std::filesystem::path& dir) {
    const Polygon emitter = square(DVec3(0, 0, 0.5), DVec3(0, 1, 0), DVec3(1, 0, 0));  // faces -z
    const Polygon wall = square(DVec3(0, 0, 0), DVec3(1, 0, 0), DVec3(0, 1, 0));       // faces +z
    const double le = 1.0;
    std::vector<Probe> probes;
    for (const Probe& p : gridProbes(4, emitter, kPi * le)) probes.push_back(p);
    char text[2048];
    std::snprintf(text, sizeof text,
                  "thin_wall_two_sided: a thin two-sided wall lit from one side.\n"
                  "Wall: the unit square z = 0 facing +z, solid FALSE (two-sided), reflecting rho = 0.5.\n"
                  "Emitter: the unit square at z = 0.5 facing -z, one-sided, emitting L_e = 1, reflecting 0.\n"
                  "Closed form: the black emitter returns nothing, so on the wall's lit side H = pi L_e\n"
                  "F_point(x, emitter) (Lambert's formula, exact), and on its back, which sees nothing, H = 0\n"
                  "(the tests check that side).\n"
                  "Probes: the 4x4 cell centres of the wall's lit side, facing +z.\n");
    writeScene(dir, "thin_wall_two_sided", text, {{emitter, 0.0, le}, {wall, 0.5, 0.0, false}}, probes, 0.02);
}

// A UV sphere of radius 1 about the origin: `bands` latitude bands x `sectors` longitudes,
// vertices on the sphere, faces facing IN. Quads between two latitudes are isosceles
// trapezoids (planar); the polar caps are triangles.
std::vector<Polygon> sphereInward(int bands, int sectors) {
    auto vertex = [&](int band, int sector) {
        const double theta = kPi * band / bands, phi = 2.0 * kPi * sector / sectors;
        return DVec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    };
    std::vector<Polygon> faces;
    for (int b = 0; b < bands; ++b)
        for (int s = 0; s < sectors; ++s) {
            Polygon f;
            // Seen from inside (the origin), this order is counter-clockwise.
            if (b == 0) f = {vertex(0, 0), vertex(1, s + 1), vertex(1, s)};
            else if (b == bands - 1) f = {vertex(b, s), vertex(b, s + 1), vertex(bands, 0)};
            else f = {vertex(b, s), vertex(b, s + 1), vertex(b + 1, s + 1), vertex(b + 1, s)};
            if (glm::dot(polygonNormal(f), polygonCentroid(f)) > 0) std::reverse(f.begin(), f.end());
            faces.push_back(f);
        }
    return faces;
}

double polygonArea(const Polygon& p) {
    DVec3 sum(0.0);
    for (size_t i = 1; i + 1 < p.size(); ++i) sum += glm::cross(p[i] - p[0], p[i + 1] - p[0]);
    return 0.5 * glm::length(sum);
}

void sphereScenes(const std::filesystem::path& dir) {
    const int bands = 8, sectors = 16;
    const std::vector<Polygon> faces = sphereInward(bands, sectors);
    {
        const double rho = 0.5, h = kPi / (1.0 - rho);
        std::vector<Surface> surfaces;
        for (const Polygon& f : faces) surfaces.push_back({f, rho, 1.0});
        char text[2048];
        std::snprintf(text, sizeof text,
                      "sphere_furnace: the inside of a UV sphere of radius 1 (%d latitude bands x %d sectors, %zu\n"
                      "faces: trapezoids and, at the poles, triangles; vertices on the sphere), every face emitting\n"
                      "L_e = 1 and reflecting rho = 0.5. Closed form as for the furnace boxes: the enclosure is\n"
                      "closed, so H = pi L_e/(1 - rho) = 2 pi = %.15f everywhere.\n"
                      "Probes: the centroid of every fourth face facing in, and six at the centre.\n",
                      bands, sectors, faces.size(), h);
        writeScene(dir, "sphere_furnace", text, surfaces, enclosureProbes(faces, h, DVec3(0), 4), 0.01);
    }
    {
        const size_t j = (bands / 2) * sectors;  // a trapezoid just below the equator, at phi = 0
        const Polygon& patch = faces[j];
        const double a_j = polygonArea(patch), sphere_value = a_j / (4.0 * kPi);
        std::vector<Surface> surfaces;
        std::vector<Probe> probes;
        double max_dev = 0.0;
        for (size_t f = 0; f < faces.size(); ++f) {
            surfaces.push_back({faces[f], 0.0, f == j ? kLeUnit : 0.0});
            if (f == j) continue;
            const DVec3 c = polygonCentroid(faces[f]), n = polygonNormal(faces[f]);
            const double fp = pointFormFactor(c, n, patch);
            probes.push_back({c, n, fp});
            max_dev = std::max(max_dev, std::abs(fp - sphere_value) / sphere_value);
        }
        // Self-check of the exact-sphere property with points on the sphere (not on faces):
        // F from any point of the sphere to a spherical cap is cap area / (4 pi R^2).
        {
            const Polygon cap_rim = disk(std::sin(0.3), std::cos(0.3), 4096, false);  // cap of half-angle 0.3 about +z
            const DVec3 x(std::sin(2.0), 0.0, std::cos(2.0));                       // on the sphere, outside the cap
            const double cap_area = 2.0 * kPi * (1.0 - std::cos(0.3));
            check(std::abs(pointFormFactor(x, -x, cap_rim) - cap_area / (4.0 * kPi)) < 1e-5 * cap_area,
                  "sphere cap property");
        }
        char text[3072];
        std::snprintf(text, sizeof text,
                      "sphere_patch: the same UV sphere (radius R = 1, %zu faces facing in), all black (rho = 0),\n"
                      "one face j (a trapezoid just below the equator, area A_j = %.12f) emitting L_e = 1/pi (B = 1).\n"
                      "Derivation: for two points x, y on a sphere the chord r = |x - y| makes equal angles with both\n"
                      "normals, cos t_x = cos t_y = r/(2R), so the kernel cos t_x cos t_y/(pi r^2) = 1/(4 pi R^2) is\n"
                      "constant: every point of the sphere sees a region of area A with F = A/(4 pi R^2), and\n"
                      "H = pi L_e A/(4 pi R^2) = B A/(4 pi R^2). Here that is %.12f.\n"
                      "The tessellation breaks the property: a flat face's centroid is not on the sphere and face j\n"
                      "is a chord polygon, not a spherical region. So the expected H at each probe (the centroid of\n"
                      "every other face, facing in) is the exact point-to-polygon value B F_point(x, j) (Lambert's\n"
                      "formula; nothing occludes inside a convex enclosure); these differ from A_j/(4 pi R^2) by up to\n"
                      "%.1f%% (most at the faces next to j). The tool checks the exact-sphere property on a finely\n"
                      "tessellated cap before writing.\n",
                      faces.size(), a_j, sphere_value, 100.0 * max_dev);
        writeScene(dir, "sphere_patch", text, surfaces, probes, 0.02);
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: analytic_scenes OUT_DIR\n");
        return 2;
    }
    const std::filesystem::path dir = argv[1];
    std::filesystem::create_directories(dir);
    squaresScene(dir, "parallel_squares", 0.0, 0.199824895698387383);
    squaresScene(dir, "perpendicular_squares", 90.0, 0.200043776075403154);
    squaresScene(dir, "hinged_60", 60.0, 0.370905321150051);
    squaresScene(dir, "hinged_120", 120.0, 0.0866150011182761);
    disksScene(dir);
    cornerScene(dir);
    furnaceScene(dir, 0.5, "rho_0.5", 0.01);
    furnaceScene(dir, 0.9, "rho_0.9", 0.01);
    furnaceScene(dir, 0.99, "rho_0.99", 0.01);
    furnaceScene(dir, 0.999, "rho_0.999", 0.02);
    twoSidedFurnaceScene(dir);
    thinWallScene(dir);
    sphereScenes(dir);
    return 0;
}

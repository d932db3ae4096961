// Why a surface point reads what it reads (issue 12/13 diagnosis): solves SCENE, finds the
// leaf element holding the world point on mesh M (the triangle nearest to it) and prints the
// leaf, its ancestors and every link that reaches them (source, form factor, visibility,
// whether rays sampled it), then the point's irradiance from the link reconstruction and from
// the exhaustive gather.
//   explain_point SCENE MESH X Y Z NX NY NZ [--quality medium] [--threads 0]
// MESH -1: the mesh whose triangle facing the normal is nearest to the point.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "radbake.h"
#include "radiosity/cluster_nodes.h"
#include "radiosity/elements.h"
#include "radiosity/form_factor.h"
#include "readout/gather.h"
#include "readout/reconstruct.h"

using namespace radbake;

int main(int argc, char** argv) {
    if (argc < 9) {
        std::fprintf(stderr, "usage: explain_point SCENE MESH X Y Z NX NY NZ [--quality Q] [--threads N] [--rays N] [--interior X Y Z]\n");
        return 2;
    }
    const std::string path = argv[1];
    uint32_t mesh_index = static_cast<uint32_t>(std::atoi(argv[2]));
    const DVec3 p(std::atof(argv[3]), std::atof(argv[4]), std::atof(argv[5]));
    const DVec3 n = glm::normalize(DVec3(std::atof(argv[6]), std::atof(argv[7]), std::atof(argv[8])));
    std::string quality = "medium";
    int threads = 0;
    long mc_rays = 0;
    DVec3 interior(0.0);
    for (int i = 9; i + 1 < argc; i += 2) {
        const std::string key = argv[i];
        if (key == "--interior" && i + 3 < argc) {
            interior = glm::normalize(DVec3(std::atof(argv[i + 1]), std::atof(argv[i + 2]), std::atof(argv[i + 3])));
            i += 2;
            continue;
        }
        if (key == "--quality") quality = argv[i + 1];
        else if (key == "--threads") threads = std::atoi(argv[i + 1]);
        else if (key == "--rays") mc_rays = std::atol(argv[i + 1]);
    }
    Diagnostics diagnostics;
    diagnostics.sink = [](const Diagnostic& d) {
        if (d.severity == Severity::Error) std::fprintf(stderr, "%s\n", formatDiagnostic(d).c_str());
    };
    auto scene = importScene(path, ImportOptions{}, diagnostics);
    if (!scene) return 1;
    addBackTwins(*scene);  // as bake() does: both sides of two-sided meshes take part
    if (std::atoi(argv[2]) < 0) {
        double nearest = INFINITY;
        for (uint32_t m = 0; m < scene->meshes.size(); ++m) {
            const Mesh& mesh = scene->meshes[m];
            for (const UVec3& t : mesh.triangles) {
                const DVec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
                const DVec3 cr = glm::cross(b - a, c - a);
                if (!(glm::length(cr) > 0.0) || glm::dot(glm::normalize(cr), n) < 0.99) continue;
                const DVec3 corners[3] = {a, b, c};
                PolygonView tri;
                tri.vertices = corners;
                tri.normal = glm::normalize(cr);
                const double d = pointPolygonDistance(p, tri);
                if (d < nearest) nearest = d, mesh_index = m;
            }
        }
    }
    if (mesh_index >= scene->meshes.size()) return 1;
    const Quality q = qualityNamed(quality);
    const BakeOptions preset = BakeOptions::forQuality(q);
    Progress progress(false);
    ParallelRunner runner(Threading{.threads = threads});
    const PartSet parts = buildParts(*scene, PartOptions{}, diagnostics);
    const auto solution = solveRadiosity(*scene, parts, preset.solver, runner, progress, diagnostics);
    if (!solution) return 1;
    const Solution& s = *solution;
    // The triangle of the mesh nearest to p.
    const Mesh& mesh = scene->meshes[mesh_index];
    uint32_t triangle = 0;
    double best = INFINITY;
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const DVec3 corners[3] = {DVec3(mesh.positions[mesh.triangles[t].x]), DVec3(mesh.positions[mesh.triangles[t].y]),
                                  DVec3(mesh.positions[mesh.triangles[t].z])};
        const DVec3 cr = glm::cross(corners[1] - corners[0], corners[2] - corners[0]);
        if (!(glm::length(cr) > 0.0)) continue;
        PolygonView tri;
        tri.vertices = corners;
        tri.normal = glm::normalize(cr);
        const double d = pointPolygonDistance(p, tri);
        if (d < best) best = d, triangle = t;
    }
    const LinkReconstruction links(s, preset.readout, runner);
    const uint32_t leaf = links.leafAt(mesh_index, triangle, p);
    std::printf("triangle %u (distance %g), leaf %u\n", triangle, best, leaf);
    const auto describe = [&](uint32_t e) {
        const Element& el = s.elements[e];
        std::printf("element %u mesh %u polygon %u depth %u area %.4g centroid (%.4g %.4g %.4g) normal (%.2g %.2g %.2g) "
                    "B %.4g E %.4g\n",
                    e, el.mesh, el.polygon, el.depth, el.area, el.centroid.x, el.centroid.y, el.centroid.z, el.normal.x,
                    el.normal.y, el.normal.z, el.radiosity.x, el.gathered.x);
    };
    double sum = 0.0;
    for (uint32_t a = leaf; a != kNoElement; a = s.elements[a].parent) {
        std::printf("-- ");
        describe(a);
        for (const Link& link : s.links) {
            if (link.receiver != a) continue;
            const Element& src = s.elements[link.source];
            // What the source brings at the point, gathered as the reconstruction gathers a
            // partly visible link (rays at the point), and unoccluded.
            const double lift = gather::kLift * s.scene_extent;
            gather::Gatherer g{.s = s,
                               .o = preset.readout,
                               .point = p,
                               .normal = n,
                               .origin = p + lift * n,
                               .lift = lift,
                               .coarse_rule = false,
                               .coarse_rule_on_emitters = true,
                               .max_visibility_splits = 1};
            g.visit(link.source);
            const double with_rays = g.sum.x;
            g.sum = DVec3(0.0);
            g.use_rays = false;
            g.visit(link.source);
            std::printf("   from %u (mesh %u, centroid %.3g %.3g %.3g, area %.3g, B %.4g): F %.4g V %.3f%s -> %.4g;"
                        " at the point %.4g (unoccluded %.4g)\n",
                        link.source, src.mesh, src.centroid.x, src.centroid.y, src.centroid.z, src.area, src.radiosity.x,
                        link.form_factor, link.visibility, link.by_rays ? " rays" : "",
                        link.form_factor * src.radiosity.x, with_rays, g.sum.x);
            sum += link.form_factor * src.radiosity.x;
        }
    }
    std::printf("element links' gathered (red) %.5g; cluster links %zu in the solution\n", sum, s.cluster_links.size());
    // The exhaustive gather's share from each root (more than 1 % of the point's total).
    {
        const DVec3 total = probeIrradiance(s, preset.readout, p, n, mesh_index);
        const double lift = gather::kLift * s.scene_extent;
        const DVec3 point = gather::liftOffSurfaces(s, p, n, lift);
        for (uint32_t r = 0; r < s.root_count; ++r) {
            gather::Gatherer g{.s = s,
                               .o = preset.readout,
                               .point = point,
                               .normal = n,
                               .origin = point + lift * n,
                               .lift = lift,
                               .use_rays = s.rays != nullptr};
            g.visit(r);
            if (g.sum.x > 0.01 * total.x) {
                std::printf("   exhaustive from root %u: %.4g  ", r, g.sum.x);
                const Element& el = s.elements[r];
                std::printf("(mesh %u, centroid %.3g %.3g %.3g, normal %.2g %.2g %.2g, B %.4g)\n", el.mesh,
                            el.centroid.x, el.centroid.y, el.centroid.z, el.normal.x, el.normal.y, el.normal.z,
                            el.radiosity.x);
                // The cluster links that carry this root's light to the point's root.
                const auto holds = [&](uint32_t node, uint32_t root) {
                    const NodeMembers m = membersOf(s, node);
                    return s.member_position[root] - m.first < m.count;
                };
                for (const Link& link : s.links)
                    if (s.elements[link.receiver].root == s.elements[leaf].root && s.elements[link.source].root == r)
                        std::printf("      element link: receiver %u (centroid %.3g %.3g %.3g) <- %u, F %.4g V %.3f\n",
                                    link.receiver, s.elements[link.receiver].centroid.x,
                                    s.elements[link.receiver].centroid.y, s.elements[link.receiver].centroid.z,
                                    link.source, link.form_factor, link.visibility);
                for (const ClusterLink& cl : s.cluster_links)
                    if (holds(cl.receiver, s.elements[leaf].root) && holds(cl.source, r))
                        std::printf("      cluster link: %u receiver roots <- %u source roots, visibility %.3f, %s\n",
                                    membersOf(s, cl.receiver).count, membersOf(s, cl.source).count, cl.visibility,
                                    cl.kernel == kNoKernel ? "separable" : "pairwise kernel");
            }
        }
    }
    const DVec3 h_links = links.irradiance(mesh_index, triangle, p, n);
    const DVec3 h_exhaustive = probeIrradiance(s, preset.readout, p, n, mesh_index);
    std::printf("H links %.5g %.5g %.5g\nH exhaustive %.5g %.5g %.5g\n", h_links.x, h_links.y, h_links.z,
                h_exhaustive.x, h_exhaustive.y, h_exhaustive.z);
    {
        // The edge correction as the vertex bake applies it (alone: no other face's vertex at
        // the point), with the way in `--interior` (zero: read at the point).
        const DVec3 h0 = links.irradianceUncorrected(mesh_index, triangle, p, n);
        const auto terms = links.edgeTermsAt(mesh_index, triangle, p, n, h0, {}, interior);
        for (const auto& f : terms.faces)
            std::printf("   face beside (normal %.3g %.3g %.3g, leaf %u): weight %.4g, B mean %.4g, H read %.4g (red)\n",
                        f.normal.x, f.normal.y, f.normal.z, f.leaf, f.weight,
                        f.weight != 0.0 ? f.weighted_mean.x / f.weight : 0.0, f.h_read.x);
        const DVec3 c = terms.correction({});
        std::printf("H uncorrected %.5g %.5g %.5g, corrected %.5g %.5g %.5g\n", h0.x, h0.y, h0.z, h0.x + c.x,
                    h0.y + c.y, h0.z + c.z);
    }
    if (mc_rays > 0) {
        // The same solution read with exact visibility: cosine-distributed rays from the point,
        // each bringing the B of the leaf it meets (H = E[B]); per root against the exhaustive
        // gather's share (green), to tell the solution's error from the gather's.
        const double lift = gather::kLift * s.scene_extent;
        const DVec3 point = gather::liftOffSurfaces(s, p, n, lift), o = point + lift * n;
        const DVec3 t1 = glm::normalize(glm::cross(std::abs(n.x) < 0.9 ? DVec3(1, 0, 0) : DVec3(0, 1, 0), n));
        const DVec3 t2 = glm::cross(n, t1);
        DVec3 sum(0.0);
        std::map<uint32_t, double> per_root;
        uint64_t state = 12345;
        const auto uniform = [&] {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            return double(state >> 11) / double(1ull << 53);
        };
        for (long i = 0; i < mc_rays; ++i) {
            const double u1 = uniform(), u2 = uniform(), r = std::sqrt(u1), phi = 2.0 * kPi * u2;
            const DVec3 d = r * std::cos(phi) * t1 + r * std::sin(phi) * t2 + std::sqrt(std::max(0.0, 1.0 - u1)) * n;
            const auto hit = s.rays->closestHit(o, d, 1e30);
            if (!hit) continue;
            const uint32_t lf = links.leafAt(hit->triangle.mesh, hit->triangle.triangle, o + hit->t * d);
            if (lf == kNoElement || !(glm::dot(s.elements[lf].normal, d) < 0.0)) continue;
            sum += s.elements[lf].radiosity / double(mc_rays);
            per_root[s.elements[lf].root] += s.elements[lf].radiosity.y / double(mc_rays);
        }
        for (const auto& [r, v] : per_root) {
            gather::Gatherer g{
                .s = s, .o = preset.readout, .point = point, .normal = n, .origin = o, .lift = lift, .use_rays = true};
            g.visit(r);
            if (v > 0.01 * sum.y || g.sum.y > 0.01 * sum.y)
                std::printf("   root %u (centroid %.3f %.3f %.3f): rays %.4g, exhaustive %.4g (green)\n", r,
                            s.elements[r].centroid.x, s.elements[r].centroid.y, s.elements[r].centroid.z, v, g.sum.y);
        }
        std::printf("H rays %.5g %.5g %.5g (%ld cosine rays)\n", sum.x, sum.y, sum.z, mc_rays);
    }
    return 0;
}

// The bundled scenes/cornell_box.wrl (a VRML97 file, kept with the VRML 1.0 reader's tests
// because the same helper owns it): counts, areas and orientations checked against the
// published Cornell Box measurements, recomputed here from the millimetre corners.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "io/import.h"

using namespace radbake;

namespace {

using Quad = std::array<DVec3, 4>;

// Area of a (possibly slightly non-planar) quad split along its 0-2 diagonal, in m^2.
double quadArea(const Quad& q_mm) {
    const DVec3 a = q_mm[0] / 1000.0, b = q_mm[1] / 1000.0, c = q_mm[2] / 1000.0, d = q_mm[3] / 1000.0;
    return 0.5 * glm::length(glm::cross(b - a, c - a)) + 0.5 * glm::length(glm::cross(c - a, d - a));
}

std::vector<Quad> blockFaces(const std::array<DVec2, 4>& footprint, double height) {
    std::vector<Quad> faces;
    auto at = [&](int i, double y) { return DVec3(footprint[i].x, y, footprint[i].y); };
    faces.push_back({at(0, height), at(1, height), at(2, height), at(3, height)});
    for (int i = 0; i < 4; ++i) faces.push_back({at(i, 0), at((i + 1) % 4, 0), at((i + 1) % 4, height), at(i, height)});
    return faces;
}

struct Loaded {
    Scene scene;
    std::map<std::string, const Mesh*> by_name;
};

Loaded load() {
    Diagnostics diagnostics;
    std::optional<Scene> scene =
        importScene(std::string(RADBAKE_SOURCE_DIR) + "/scenes/cornell_box.wrl", ImportOptions{}, diagnostics);
    REQUIRE(scene);
    CHECK(diagnostics.warningCount() == 0);
    Loaded loaded{std::move(*scene), {}};
    for (const Mesh& mesh : loaded.scene.meshes) loaded.by_name[mesh.name] = &mesh;
    return loaded;
}

double area(const Mesh& mesh) {
    double a = 0.0;
    for (size_t t = 0; t < mesh.triangles.size(); ++t) a += triangleArea(mesh, t);
    return a;
}

// How many triangles turn their front towards `point` (normal . (centroid - point) <= 0).
int facingTowards(const Mesh& mesh, const DVec3& point) {
    int towards = 0;
    for (const UVec3& t : mesh.triangles) {
        const DVec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
        if (glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0 - point) <= 0.0) ++towards;
    }
    return towards;
}

}  // namespace

TEST_CASE("cornell box: counts, materials and the camera") {
    const Loaded box = load();
    const SceneSummary summary = summarize(box.scene);
    CHECK(box.scene.meshes.size() == 8);
    CHECK(summary.polygons == 1 + 4 + 1 + 1 + 1 + 1 + 5 + 5);
    CHECK(summary.triangles == 2 * summary.polygons);
    CHECK(summary.emitters == 1);
    CHECK(summary.materials == 4);
    CHECK(summary.lights == 0);
    CHECK(summary.bounds_min == Vec3(0.0f));
    CHECK(summary.bounds_max == Vec3(0.556f, 0.5488f, 0.5592f));

    REQUIRE(box.by_name.count("Light"));
    const Material& light = box.scene.materials[box.by_name.at("Light")->material];
    CHECK(light.emission == Vec3(17.20f, 11.47f, 3.06f));
    CHECK(light.reflectance == Vec3(0.78f));
    const Material& red = box.scene.materials[box.by_name.at("LeftWall")->material];
    CHECK(red.reflectance.x > 5.0f * red.reflectance.y);
    const Material& green = box.scene.materials[box.by_name.at("RightWall")->material];
    CHECK(green.reflectance.y > 4.0f * green.reflectance.x);
    CHECK(box.by_name.at("ShortBlock")->material == box.by_name.at("Floor")->material);

    REQUIRE(box.scene.cameras.size() == 1);
    const Camera& camera = box.scene.cameras[0];
    CHECK(camera.position == Vec3(0.278f, 0.273f, -0.8f));
    CHECK(camera.field_of_view == doctest::Approx(2.0 * std::atan(12.5 / 35.0)).epsilon(1e-4));
    const Vec3 forward = camera.orientation * Vec3(0.0f, 0.0f, -1.0f);
    CHECK(forward.z == doctest::Approx(1.0f));
    const Vec3 right = camera.orientation * Vec3(1.0f, 0.0f, 0.0f);
    CHECK(right.x == doctest::Approx(-1.0f));  // the green wall (x = 0) is on the right
}

TEST_CASE("cornell box: areas match the published corners, the ceiling leaves the light's opening") {
    const Loaded box = load();
    const double light = 0.130 * 0.105;
    CHECK(area(*box.by_name.at("Light")) == doctest::Approx(light).epsilon(1e-5));
    CHECK(area(*box.by_name.at("Ceiling")) == doctest::Approx(0.556 * 0.5592 - light).epsilon(1e-5));
    CHECK(area(*box.by_name.at("Floor")) ==
          doctest::Approx(quadArea({DVec3(552.8, 0, 0), {0, 0, 0}, {0, 0, 559.2}, {549.6, 0, 559.2}})).epsilon(1e-5));
    CHECK(area(*box.by_name.at("BackWall")) ==
          doctest::Approx(quadArea({DVec3(549.6, 0, 559.2), {0, 0, 559.2}, {0, 548.8, 559.2}, {556, 548.8, 559.2}}))
              .epsilon(1e-5));
    CHECK(area(*box.by_name.at("LeftWall")) ==
          doctest::Approx(quadArea({DVec3(552.8, 0, 0), {549.6, 0, 559.2}, {556, 548.8, 559.2}, {556, 548.8, 0}}))
              .epsilon(1e-5));
    double short_block = 0.0, tall_block = 0.0;
    for (const Quad& q : blockFaces({DVec2(130, 65), {82, 225}, {240, 272}, {290, 114}}, 165)) short_block += quadArea(q);
    for (const Quad& q : blockFaces({DVec2(423, 247), {265, 296}, {314, 456}, {472, 406}}, 330)) tall_block += quadArea(q);
    CHECK(area(*box.by_name.at("ShortBlock")) == doctest::Approx(short_block).epsilon(1e-5));
    CHECK(area(*box.by_name.at("TallBlock")) == doctest::Approx(tall_block).epsilon(1e-5));
}

TEST_CASE("cornell box: room surfaces face into the room, blocks face out, the light faces down") {
    const Loaded box = load();
    const DVec3 room_centre(0.278, 0.2744, 0.2796);
    for (const char* name : {"Floor", "Ceiling", "BackWall", "LeftWall", "RightWall", "Light"}) {
        CAPTURE(name);
        const Mesh& mesh = *box.by_name.at(name);
        CHECK(mesh.solid);
        // Facing into the room: each triangle's normal points back towards the centre.
        CHECK(facingTowards(mesh, room_centre) == static_cast<int>(mesh.triangles.size()));
    }
    const Mesh& light = *box.by_name.at("Light");
    for (const UVec3& t : light.triangles) {
        const Vec3 n = glm::cross(light.positions[t.y] - light.positions[t.x], light.positions[t.z] - light.positions[t.x]);
        CHECK(n.y < 0.0f);
    }
    CHECK(facingTowards(*box.by_name.at("ShortBlock"), DVec3(0.1855, 0.0825, 0.169)) == 0);
    CHECK(facingTowards(*box.by_name.at("TallBlock"), DVec3(0.3685, 0.165, 0.351)) == 0);
}

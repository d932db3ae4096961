#include "scene/two_sided.h"

namespace radbake {
namespace {

Mesh backTwinOf(const Mesh& front) {
    Mesh back = front;
    back.name = front.name + kBackSuffix;
    for (Vec3& n : back.normals) n = -n;
    // Reversed winding: (a, c, b) keeps corner 0, so barycentrics (u, v) of the front are
    // (v, u) on the back.
    for (UVec3& t : back.triangles) std::swap(t.y, t.z);
    back.convex_solid = false;  // its inside is seen
    back.back = true;
    return back;
}

}  // namespace

size_t addBackTwins(Scene& scene) {
    const size_t original = scene.meshes.size();
    size_t added = 0;
    for (size_t m = 0; m < original; ++m) {
        if (scene.meshes[m].solid || scene.meshes[m].twin != kNoMesh || scene.meshes[m].back) continue;
        if (scene.meshes[m].triangles.empty()) continue;
        Mesh back = backTwinOf(scene.meshes[m]);
        back.twin = static_cast<uint32_t>(m);
        scene.meshes[m].twin = static_cast<uint32_t>(scene.meshes.size());
        scene.meshes[m].convex_solid = false;  // a surface seen from inside is no occluding volume
        scene.meshes.push_back(std::move(back));
        ++added;
    }
    return added;
}

}  // namespace radbake

#include "scene/weld.h"

#include <cstring>
#include <unordered_map>

namespace radbake {

WeldedPositions weldPositions(const Mesh& mesh) {
    struct Hash {
        size_t operator()(const Vec3& v) const {
            uint32_t b[3];
            std::memcpy(b, &v, sizeof b);
            return (size_t(b[0]) * 73856093u) ^ (size_t(b[1]) * 19349663u) ^ (size_t(b[2]) * 83492791u);
        }
    };
    WeldedPositions w;
    std::unordered_map<Vec3, uint32_t, Hash> index;
    w.id.resize(mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        Vec3 p = mesh.positions[i];
        if (p.x == 0.0f) p.x = 0.0f;  // -0 and +0 weld
        if (p.y == 0.0f) p.y = 0.0f;
        if (p.z == 0.0f) p.z = 0.0f;
        const auto [it, inserted] = index.emplace(p, uint32_t(w.points.size()));
        if (inserted) w.points.push_back(DVec3(p));
        w.id[i] = it->second;
    }
    return w;
}

}  // namespace radbake

#include "readout/realtime_emission.h"

namespace radbake {

RealtimeEmissionLeftOut::RealtimeEmissionLeftOut(Solution& solution) : solution_(solution) {
    const Scene* scene = solution.scene;
    if (!scene) return;
    for (uint32_t i = 0; i < solution.elements.size(); ++i) {
        Element& e = solution.elements[i];
        const Mesh& mesh = scene->meshes[e.mesh];
        if (mesh.realtime_light.empty()) continue;
        // Inner elements hold their leaves' area average: the same constant comes off each.
        const DVec3 own = kPi * DVec3(polygonEmission(*scene, mesh, e.polygon));
        if (own == DVec3(0.0)) continue;
        e.emission -= own;
        e.radiosity -= own;
        elements_.push_back(i);
        own_.push_back(own);
    }
}

RealtimeEmissionLeftOut::~RealtimeEmissionLeftOut() {
    for (size_t k = 0; k < elements_.size(); ++k) {
        Element& e = solution_.elements[elements_[k]];
        e.emission += own_[k];
        e.radiosity += own_[k];
    }
}

}  // namespace radbake

// `pvm`: penumbra volume maps (cournia2005 chapter 4). The CPU geometry the passes draw: the
// silhouette loops from the light centre (the winged-edge silhouettes ssv uses, scene/mesh_topology.h),
// each vertex's outer and inner extrusion vectors (sec. 4.1.2, shaders/shared/penumbra_volumes.glsl)
// and per edge an outer and an inner volume quadrilateral. Public for the views and the tests: the
// views draw exactly these quads, the GPU rasterizes exactly these quads.
#pragma once
#include <array>
#include <functional>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "graph/technique.h"
#include "scene/scene.h"
#include "ssv/ssv.h"

namespace shadowlab {

const TechniqueDesc& pvmTechnique();

// One silhouette edge a -> b, clockwise seen from the light centre (the occluder on its right; the
// orientation penumbra_volumes.glsl's formulas assume), with its neighbours in its loop and the
// extrusion vectors at its two ends.
struct PvmEdge {
    glm::vec3 a{0.0f}, b{0.0f};
    int object = 0;             // index into scene.objects
    uint32_t topologyEdge = 0;
    bool boundary = false;      // a boundary edge of an open mesh
    int prev = -1, next = -1;   // the edges before and after it in its loop; -1: the end of an open chain
    // The line of the edge passes through the light centre: it has no hard shadow plane and no
    // volume (seen from the light it is a point); its neighbours extrude along their own planes.
    bool degenerate = false;
    glm::vec3 outerA{0.0f}, outerB{0.0f};  // v^- at a and b (unit)
    glm::vec3 innerA{0.0f}, innerB{0.0f};  // v^+ at a and b (unit)
};

struct PvmGeometry {
    std::vector<PvmEdge> edges;
    std::vector<std::string> warnings;  // non-manifold objects, named
    size_t chainEnds = 0;       // edge ends without a neighbour (open silhouette chains)
    size_t branchVertices = 0;  // vertices with more than one silhouette edge leaving them (paired in edge order)
    size_t degenerateEdges = 0;
};

// Silhouette loops and extrusion vectors of the casters posed at time t, for a light centred at l
// with radius r (pvmLightRadius).
PvmGeometry buildPvmGeometry(const Scene& scene, const std::vector<SsvCaster>& casters, double t, const glm::vec3& l,
                             float r);

// The volume quadrilateral of an edge on one side (PVM_OUTER or PVM_INNER): a, a + w v_a, b + w v_b,
// b (sec. 4.1.2), w putting the extruded points beyond every receiver.
std::array<glm::vec3, 4> pvmQuad(const PvmEdge& edge, float side, float w);

// pvmf's simplified volume of an edge on one side (cournia2005 sec. 5.1, shaders/shared/penumbra_mask.glsl):
// the end points moved towards the light by s_e d_e, e^0, e^0 + w v_0, e^1 + w v_1, e^1, for a light of
// radius r centred at l. Independent of the edge's neighbours.
std::array<glm::vec3, 4> pvmfQuad(const PvmEdge& edge, const glm::vec3& l, float r, float se, float side, float w);

// The start both volume techniques' per-pixel records share: the receiver at `pixel` (the G-buffer
// row flipped), its light-view coordinate and the light's fraction in front of its tangent plane,
// written into `j` as receiver, receiver_depth and front_fraction. nullopt (and j = {background:
// true}) when the pixel shows no geometry.
struct RecordReceiver {
    glm::vec3 p{0.0f}, n{0.0f};
    glm::vec4 coord{0.0f};  // shadowMapCoord: xy texture, z light-view depth, w 0 outside the frustum
    float front = 0.0f;
};
std::optional<RecordReceiver> beginReceiverRecord(PassContext& ctx, glm::ivec2 pixel, nlohmann::json& j);

// The `silhouettes` and `penumbra_volumes` meshes both volume techniques draw and export: per edge
// a line (attributes object, boundary, prev, next, degenerate) and, unless degenerate, the outer
// then the inner quad `quad(edge, side)` as two triangles (attributes edge, side 0 outer / 1 inner,
// object). An edge seen end-on from the light centre casts no penumbra of its own: its neighbours'
// volumes cover its point.
void writePvmMeshes(const Scene& scene, const PvmGeometry& g,
                    const std::function<std::array<glm::vec3, 4>(const PvmEdge&, float side)>& quad, MeshData& lines,
                    MeshData& volumes);

// The extrusion length w for a scene: twice the distance from the light centre to the farthest
// corner of the bounds, so that a + w v (v unit, pointing away from the light) lies outside them.
float pvmExtrusionLength(const Bounds& bounds, const glm::vec3& l);

}  // namespace shadowlab

// The CPU geometry of `pvm` (cournia2005 sec. 4.1.1-4.1.2): silhouette loops from the light centre
// and the extrusion vectors of their vertices. See pvm.h and README.md.
#include <algorithm>
#include <cmath>
#include <map>

#include "pvm/pvm.h"
#include "scene/mesh_topology.h"
#include "shared/shared.h"

namespace shadowlab {

void writePvmMeshes(const Scene& scene, const PvmGeometry& g,
                    const std::function<std::array<glm::vec3, 4>(const PvmEdge&, float side)>& quad, MeshData& lines,
                    MeshData& volumes) {
    lines = MeshData{};
    volumes = MeshData{};
    lines.verticesPerPrimitive = 2;
    std::vector<float> object, boundary, prev, next, degenerate;
    std::vector<float> edgeOf, side, volumeObject;
    for (size_t i = 0; i < g.edges.size(); ++i) {
        const PvmEdge& e = g.edges[i];
        const uint32_t base = uint32_t(lines.positions.size());
        lines.positions.push_back(e.a);
        lines.positions.push_back(e.b);
        lines.indices.insert(lines.indices.end(), {base, base + 1});
        const float id = float(scene.objects[size_t(e.object)].id);
        object.push_back(id);
        boundary.push_back(e.boundary ? 1.0f : 0.0f);
        prev.push_back(float(e.prev));
        next.push_back(float(e.next));
        degenerate.push_back(e.degenerate ? 1.0f : 0.0f);
        if (e.degenerate) continue;
        // Outer then inner quadrilateral, two triangles each: q0, q1, q2 and q0, q2, q3.
        for (float s : {shared::PVM_OUTER, shared::PVM_INNER}) {
            const std::array<glm::vec3, 4> q = quad(e, s);
            const uint32_t v = uint32_t(volumes.positions.size());
            volumes.positions.insert(volumes.positions.end(), q.begin(), q.end());
            volumes.indices.insert(volumes.indices.end(), {v, v + 1, v + 2, v, v + 2, v + 3});
            for (int t = 0; t < 2; ++t) {
                edgeOf.push_back(float(i));
                side.push_back(s == shared::PVM_OUTER ? 0.0f : 1.0f);
                volumeObject.push_back(id);
            }
        }
    }
    lines.primitiveAttributes = {
        {"object", object}, {"boundary", boundary}, {"prev", prev}, {"next", next}, {"degenerate", degenerate}};
    volumes.primitiveAttributes = {{"edge", edgeOf}, {"side", side}, {"object", volumeObject}};
}

float pvmExtrusionLength(const Bounds& bounds, const glm::vec3& l) {
    float far = 0.0f;
    for (int k = 0; k < 8; ++k) {
        const glm::vec3 corner((k & 1) ? bounds.hi.x : bounds.lo.x, (k & 2) ? bounds.hi.y : bounds.lo.y,
                               (k & 4) ? bounds.hi.z : bounds.lo.z);
        far = std::max(far, glm::length(corner - l));
    }
    return 2.0f * far + 1e-3f;
}

std::array<glm::vec3, 4> pvmQuad(const PvmEdge& e, float side, float w) {
    const glm::vec3 va = side == shared::PVM_OUTER ? e.outerA : e.innerA;
    const glm::vec3 vb = side == shared::PVM_OUTER ? e.outerB : e.innerB;
    return {e.a, e.a + w * va, e.b + w * vb, e.b};
}

std::array<glm::vec3, 4> pvmfQuad(const PvmEdge& e, const glm::vec3& l, float r, float se, float side, float w) {
    const float de = shared::pvmfEdgeDistance(e.a, e.b, l);
    const glm::vec3 a = shared::pvmfMovedPoint(e.a, de, l, se), b = shared::pvmfMovedPoint(e.b, de, l, se);
    const glm::vec3 n = shared::pvmPlaneNormal(e.a, e.b, l);
    const glm::vec3 va = shared::pvmfExtrusion(a, a, b, n, l, r, shared::PVMF_START, side);
    const glm::vec3 vb = shared::pvmfExtrusion(b, a, b, n, l, r, shared::PVMF_END, side);
    return {a, a + w * va, b + w * vb, b};
}

PvmGeometry buildPvmGeometry(const Scene& scene, const std::vector<SsvCaster>& casters, double t, const glm::vec3& l,
                             float r) {
    PvmGeometry g;
    for (const SsvCaster& caster : casters) {
        const Object& object = scene.objects[size_t(caster.object)];
        const MeshTopology& topo = caster.topology;
        if (topo.edges.empty()) continue;
        const glm::mat4 worldFromObject = object.worldFromObjectAt(t);
        const glm::vec3 lightInObject = glm::vec3(glm::inverse(worldFromObject) * glm::vec4(l, 1.0f));
        if (topo.nonManifoldEdges() > 0)
            g.warnings.push_back("object '" + object.name + "' is not a manifold (" +
                                 std::to_string(topo.nonManifoldEdges()) +
                                 " edges with more than two faces): pvm takes every non-manifold edge as a silhouette "
                                 "and pairs the loops that branch there in edge order, which may misplace volumes");
        std::vector<glm::vec3> world(topo.vertices.size());
        for (size_t v = 0; v < world.size(); ++v) world[v] = glm::vec3(worldFromObject * glm::vec4(topo.vertices[v], 1.0f));
        // Sec. 4.1.1: the winged-edge silhouette from the light centre, each edge reversed from
        // orientSilhouetteEdge's counter-clockwise order to the clockwise one of penumbra_volumes.glsl.
        const size_t first = g.edges.size();
        std::vector<uint32_t> from, to;
        for (uint32_t e : silhouetteEdges(topo, lightInObject)) {
            const glm::uvec2 ccw = orientSilhouetteEdge(topo, e, lightInObject);
            PvmEdge s;
            s.a = world[ccw.y];
            s.b = world[ccw.x];
            s.object = caster.object;
            s.topologyEdge = e;
            s.boundary = topo.edges[e].boundary();
            from.push_back(ccw.y);
            to.push_back(ccw.x);
            g.edges.push_back(s);
        }
        // Loops: each edge's successor is an edge leaving the vertex it ends at, not yet taken by
        // another (in edge order where a vertex has several: two loops touching at a vertex).
        std::multimap<uint32_t, size_t> leaving;
        for (size_t i = 0; i < from.size(); ++i) leaving.emplace(from[i], i);
        std::map<uint32_t, size_t> outCount;
        for (uint32_t v : from) ++outCount[v];
        for (const auto& [v, n] : outCount) g.branchVertices += n > 1;
        for (size_t i = 0; i < to.size(); ++i) {
            auto [lo, hi] = leaving.equal_range(to[i]);
            for (auto it = lo; it != hi; ++it) {
                PvmEdge& candidate = g.edges[first + it->second];
                if (candidate.prev >= 0 || it->second == i) continue;
                g.edges[first + i].next = int(first + it->second);
                candidate.prev = int(first + i);
                break;
            }
        }
    }
    // Sec. 4.1.2: the extrusion vectors at both ends of every edge, from the edge and its neighbour
    // (the same three vertices on both edges sharing a vertex, so their quads meet exactly, but at
    // spikes: pvmEdgeEndExtrusion).
    for (PvmEdge& e : g.edges) {
        e.degenerate = glm::dot(shared::pvmPlaneNormal(e.a, e.b, l), shared::pvmPlaneNormal(e.a, e.b, l)) == 0.0f;
        g.degenerateEdges += e.degenerate;
        const glm::vec3 before = e.prev >= 0 ? g.edges[size_t(e.prev)].a : e.a;
        const glm::vec3 after = e.next >= 0 ? g.edges[size_t(e.next)].b : e.b;
        g.chainEnds += (e.prev < 0) + (e.next < 0);
        e.outerA = shared::pvmEdgeEndExtrusion(before, e.a, e.b, l, r, shared::PVM_OUTER, 1.0f);
        e.innerA = shared::pvmEdgeEndExtrusion(before, e.a, e.b, l, r, shared::PVM_INNER, 1.0f);
        e.outerB = shared::pvmEdgeEndExtrusion(e.a, e.b, after, l, r, shared::PVM_OUTER, 0.0f);
        e.innerB = shared::pvmEdgeEndExtrusion(e.a, e.b, after, l, r, shared::PVM_INNER, 0.0f);
    }
    return g;
}

}  // namespace shadowlab

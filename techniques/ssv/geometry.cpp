// The CPU geometry of `ssv` (assarsson2004): silhouettes from the light centre, the hard shadow
// volume and the penumbra wedges. See ssv.h and README.md.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "ssv/ssv.h"

namespace shadowlab {

std::array<glm::vec3, 4> SsvLight::corners() const {
    const float h = 0.5f * size;
    return {centre - h * right - h * up, centre + h * right - h * up, centre + h * right + h * up,
            centre - h * right + h * up};
}

SsvLight SsvLight::from(const Light& light) {
    SsvLight l;
    l.shape = light.shape;
    l.centre = light.position;
    l.direction = light.direction;
    l.up = light.up;
    l.right = light.right();
    l.size = light.isPoint() ? 0.0f : light.size;
    return l;
}

std::vector<Light> ssvSubLights(const Light& light, int split) {
    if (split < 2 || light.isPoint() || light.shape != LightShape::Square) return {light};
    std::vector<Light> quarters;
    const float q = 0.25f * light.size;
    for (int k = 0; k < 4; ++k) {
        Light l = light;
        l.size = 0.5f * light.size;
        l.position = light.position + ((k & 1) ? q : -q) * light.right() + ((k & 2) ? q : -q) * light.up;
        quarters.push_back(l);
    }
    return quarters;
}

bool SsvWedge::contains(const glm::vec3& x, float tolerance) const {
    for (const SsvPlane* p : {&front, &back, &side0, &side1, &bottom})
        if (p->distance(x) < -tolerance) return false;
    return true;
}

namespace {

SsvPlane planeThrough(const glm::vec3& n, const glm::vec3& point) { return {n, glm::dot(n, point)}; }

// The side plane at end point e (step C): normal m = cos(theta) inward + sin(theta) toCentre in
// the plane of the edge and the light centre, rotated (theta as large as possible) until the light
// lies on its outer side, touching it. `inward` points along the edge into it; `toCentre` is the
// unit component of (I_c - e) perpendicular to the edge.
std::optional<SsvPlane> sidePlane(const SsvLight& light, const glm::vec3& e, const glm::vec3& inward,
                                  const glm::vec3& toCentre, std::string& why) {
    float theta = 0.0f;
    if (light.shape == LightShape::Square) {
        theta = std::numeric_limits<float>::infinity();
        for (const glm::vec3& corner : light.corners()) {
            const glm::vec3 w = corner - e;
            const float along = glm::dot(inward, w), across = glm::dot(toCentre, w);
            if (across <= 1e-4f * glm::length(w)) {
                why = "a light corner lies on the far side of the edge's line (no side plane)";
                return std::nullopt;
            }
            theta = std::min(theta, std::atan(-along / across));
        }
    } else {
        const float r = light.size;
        const float A = glm::dot(inward, light.centre - e), B = glm::dot(toCentre, light.centre - e);
        const float R = std::sqrt(A * A + B * B);
        if (R <= r * (1.0f + 1e-4f)) {
            why = "the end point is inside the light's sphere";
            return std::nullopt;
        }
        theta = std::atan2(B, A) - std::acos(-r / R);
    }
    if (theta <= -0.5f * float(M_PI) + 1e-3f) {
        why = "the side plane would turn past the edge's line";
        return std::nullopt;
    }
    const glm::vec3 m = glm::normalize(std::cos(theta) * inward + std::sin(theta) * toCentre);
    return planeThrough(m, e);
}

}  // namespace

SsvWedge buildWedge(const SsvLight& light, const glm::vec3& e0, const glm::vec3& e1, float farDistance,
                    const Bounds* receivers) {
    SsvWedge w;
    const glm::vec3 c = light.centre;
    const float d0 = glm::length(e0 - c), d1 = glm::length(e1 - c);
    const float scale = std::max({d0, d1, 1e-30f});
    const glm::vec3 edge = e1 - e0;
    const float length = glm::length(edge);
    w.apex0 = e0;
    w.apex1 = e1;
    if (length <= 1e-7f * scale || glm::length(glm::cross(edge, c - e0)) / length <= 1e-6f * scale) {
        // Projected from any point, an edge on a line through the light centre lies on a ray from
        // the centre: the radial integration gives it no area (backprojection.glsl).
        w.kind = SsvWedge::Kind::None;
        w.why = "the edge lies on a line through the light centre: it covers nothing";
        return w;
    }
    auto everywhere = [&](const std::string& why) {
        w.kind = SsvWedge::Kind::Everywhere;
        w.why = why;
        return w;
    };
    // A. Move the farther end point towards the light centre until both are equally far.
    glm::vec3 a0 = e0, a1 = e1;
    if (d0 > d1) a0 = c + (e0 - c) * (d1 / d0);
    if (d1 > d0) a1 = c + (e1 - c) * (d0 / d1);
    w.apex0 = a0;
    w.apex1 = a1;
    const glm::vec3 moved = a1 - a0;
    const float movedLength = glm::length(moved);
    if (movedLength <= 1e-5f * scale) return everywhere("the moved edge is too short to carry planes");
    const glm::vec3 t = moved / movedLength;
    const glm::vec3 toC = c - a0;
    const glm::vec3 perp = toC - t * glm::dot(toC, t);
    const float D = glm::length(perp);
    if (D <= 1e-5f * scale) return everywhere("the edge's line passes too near the light centre");
    const glm::vec3 ah = perp / D, bh = glm::cross(t, ah);
    // B. Front and back planes through the moved edge, tangent to the light: the light spans the
    // angles [psiMin, psiMax] about the edge's line (0 towards the centre); the planes at the two
    // extremes leave it on their outer sides.
    float psiMin = 0.0f, psiMax = 0.0f;
    if (light.shape == LightShape::Square) {
        psiMin = std::numeric_limits<float>::infinity();
        psiMax = -psiMin;
        for (const glm::vec3& corner : light.corners()) {
            const glm::vec3 v = corner - a0;
            const float along = glm::dot(ah, v), across = glm::dot(bh, v);
            if (along <= 1e-4f * glm::length(v)) return everywhere("the edge's line passes through the light");
            const float psi = std::atan2(across, along);
            psiMin = std::min(psiMin, psi);
            psiMax = std::max(psiMax, psi);
        }
    } else {
        if (light.size >= D * (1.0f - 1e-4f)) return everywhere("the edge's line passes through the light's sphere");
        psiMax = std::asin(light.size / D);
        psiMin = -psiMax;
    }
    w.front = planeThrough(-std::sin(psiMax) * ah + std::cos(psiMax) * bh, a0);
    w.back = planeThrough(std::sin(psiMin) * ah - std::cos(psiMin) * bh, a0);
    // C. Side planes about the end points.
    std::optional<SsvPlane> s0 = sidePlane(light, a0, t, ah, w.why);
    if (!s0) return everywhere(w.why);
    std::optional<SsvPlane> s1 = sidePlane(light, a1, -t, ah, w.why);
    if (!s1) return everywhere(w.why);
    w.side0 = *s0;
    w.side1 = *s1;
    // D. The bottom plane: perpendicular to the wedge's axis (light centre to the edge's middle),
    // at farDistance from the centre.
    const glm::vec3 axis = glm::normalize(0.5f * (a0 + a1) - c);
    if (receivers && !receivers->empty()) {
        // The box's farthest corner along the axis (a linear function peaks at a corner), a little
        // beyond, and beyond the edge itself.
        float deepest = std::max(glm::dot(axis, a0 - c), glm::dot(axis, a1 - c));
        float box = -std::numeric_limits<float>::infinity();
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 corner((k & 1) ? receivers->hi.x : receivers->lo.x, (k & 2) ? receivers->hi.y : receivers->lo.y,
                                   (k & 4) ? receivers->hi.z : receivers->lo.z);
            box = std::max(box, glm::dot(axis, corner - c));
        }
        deepest = std::max(deepest, box);
        farDistance = std::min(farDistance, 1.02f * deepest + 1e-3f);
    }
    w.bottom = {-axis, -(farDistance + glm::dot(axis, c))};
    auto bottomCorner = [&](const glm::vec3& apex, const SsvPlane& p, const SsvPlane& q) -> std::optional<glm::vec3> {
        glm::vec3 dir = glm::cross(p.n, q.n);
        const float l = glm::length(dir);
        if (l < 1e-6f) return std::nullopt;
        dir /= l;
        if (glm::dot(dir, axis) < 0.0f) dir = -dir;
        const float along = glm::dot(axis, dir);
        if (along <= 1e-3f) return std::nullopt;
        const float s = (farDistance - glm::dot(axis, apex - c)) / along;
        if (s <= 0.0f) return std::nullopt;
        return apex + s * dir;
    };
    const std::optional<glm::vec3> fs0 = bottomCorner(a0, w.front, w.side0), fs1 = bottomCorner(a1, w.front, w.side1),
                                   bs1 = bottomCorner(a1, w.back, w.side1), bs0 = bottomCorner(a0, w.back, w.side0);
    if (!fs0 || !fs1 || !bs1 || !bs0) return everywhere("a wedge corner does not reach the bottom plane");
    w.corners = {a0, a1, *fs0, *fs1, *bs1, *bs0};
    // The six corners must bound the five planes' intersection (a convex wedge); otherwise the
    // planes cross before the bottom and the polyhedron would not be the wedge.
    const float tolerance = 1e-4f * farDistance;
    for (const glm::vec3& corner : w.corners)
        if (!w.contains(corner, tolerance)) return everywhere("the wedge's planes cross before its bottom");
    w.triangles = {glm::uvec3{0, 1, 3}, {0, 3, 2}, {0, 5, 4}, {0, 4, 1}, {0, 2, 5}, {1, 4, 3}, {2, 3, 4}, {2, 4, 5}};
    w.faceOfTriangle = {0, 0, 1, 1, 2, 2, 3, 3};
    glm::vec3 centroid(0.0f);
    for (const glm::vec3& corner : w.corners) centroid += corner / 6.0f;
    for (glm::uvec3& tri : w.triangles) {
        const glm::vec3 &p0 = w.corners[tri.x], &p1 = w.corners[tri.y], &p2 = w.corners[tri.z];
        if (glm::dot(glm::cross(p1 - p0, p2 - p0), p0 - centroid) < 0.0f) std::swap(tri.y, tri.z);
    }
    w.kind = SsvWedge::Kind::Wedge;
    w.why.clear();
    return w;
}

std::vector<SsvCaster> buildSsvCasters(const Scene& scene) {
    std::vector<SsvCaster> casters;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        if (!scene.objects[i].castsShadows) continue;
        casters.push_back({int(i), buildTopology(scene.objects[i].mesh)});
    }
    return casters;
}

SsvGeometry buildSsvGeometry(const Scene& scene, const std::vector<SsvCaster>& casters, double t,
                             const SsvLight& light, float farDistance, float capOffset, const Bounds* receivers) {
    SsvGeometry g;
    const glm::vec3 c = light.centre;
    for (const SsvCaster& caster : casters) {
        const Object& object = scene.objects[size_t(caster.object)];
        const MeshTopology& topo = caster.topology;
        if (topo.edges.empty()) continue;
        const glm::mat4 worldFromObject = object.worldFromObjectAt(t);
        const glm::vec3 lightInObject = glm::vec3(glm::inverse(worldFromObject) * glm::vec4(c, 1.0f));
        // What the topology repaired or closed, said once per object (the pass keeps what it said).
        if (!topo.reorientedTriangles.empty())
            g.warnings.push_back("object '" + object.name + "': " + std::to_string(topo.reorientedTriangles.size()) +
                                 " triangles wound against their neighbours were turned round for its silhouettes "
                                 "and caps");
        if (!topo.duplicateTriangles.empty())
            g.warnings.push_back("object '" + object.name + "': " + std::to_string(topo.duplicateTriangles.size()) +
                                 " duplicate triangles (the corners of an earlier one) were left out");
        if (!topo.fillCentres.empty())
            g.warnings.push_back("object '" + object.name + "': " + std::to_string(topo.fillCentres.size()) +
                                 " openings of a solid were closed by fans for its shadow volume; its inside, where "
                                 "it shows through them, is lit");
        if (topo.nonManifoldEdges() > 0)
            g.warnings.push_back("object '" + object.name + "' is not a manifold (" +
                                 std::to_string(topo.nonManifoldEdges()) +
                                 " edges with more than two faces): each such edge is a silhouette edge of the "
                                 "weight its caps leave; a component that is not a solid is capped from both sides");
        // World positions: the welded vertices, then the centres of the fans that close a solid's
        // openings (MeshTopology::holeFills).
        const size_t meshVertices = topo.vertices.size();
        std::vector<glm::vec3> world(meshVertices + topo.fillCentres.size());
        for (size_t v = 0; v < meshVertices; ++v) world[v] = glm::vec3(worldFromObject * glm::vec4(topo.vertices[v], 1.0f));
        for (size_t c = 0; c < topo.fillCentres.size(); ++c)
            world[meshVertices + c] = glm::vec3(worldFromObject * glm::vec4(topo.fillCentres[c], 1.0f));
        // Volume vertices, made on first use: the finite one moved away from the light by capOffset,
        // and the one at infinity in the same direction from the light centre.
        std::vector<int> finite(world.size(), -1), infinite(world.size(), -1);
        auto finiteVertex = [&](uint32_t v) {
            if (finite[v] < 0) {
                const glm::vec3 dir = glm::normalize(world[v] - c);
                finite[v] = int(g.volume.vertices.size());
                g.volume.vertices.push_back(glm::vec4(world[v] + capOffset * dir, 1.0f));
            }
            return uint32_t(finite[v]);
        };
        auto infiniteVertex = [&](uint32_t v) {
            if (infinite[v] < 0) {
                infinite[v] = int(g.volume.vertices.size());
                g.volume.vertices.push_back(glm::vec4(glm::normalize(world[v] - c), 0.0f));
            }
            return uint32_t(infinite[v]);
        };
        auto addCap = [&](glm::uvec3 v) {  // wound to face the light
            g.volume.triangles.push_back({finiteVertex(v.x), finiteVertex(v.y), finiteVertex(v.z)});
            g.volume.kind.push_back(0);
            g.volume.edge.push_back(-1);
            g.volume.triangles.push_back({infiniteVertex(v.x), infiniteVertex(v.z), infiniteVertex(v.y)});
            g.volume.kind.push_back(1);
            g.volume.edge.push_back(-1);
        };
        // Caps: the triangles that occlude, each wound to face the light, as a near cap and the
        // same reversed at infinity as the far cap. A solid (MeshTopology::Component::solid: closed,
        // or with openings spanning at most a quarter of its area) caps with its triangles facing
        // away from the light (its dark side), so its lit surface is far outside its own volume,
        // and with the fans that close its openings (MeshTopology::holeFills) facing the same way,
        // so no light passes an opening that the lit side stops. A sheet caps with all its
        // triangles (each occludes from both sides).
        // Sides: the boundary of the caps as a chain (README.md, "Open and imperfect meshes"): each
        // cap adds +1 to the edges it runs v0 -> v1 and -1 to those it runs v1 -> v0, wound as it
        // faces the light; an edge whose sum m is not 0 is a silhouette edge of weight |m|, running
        // the way the caps run it. The volume is then closed whatever the mesh: on a closed mesh the
        // edges between a lit and a dark face (weight 1); on a sheet its interior silhouettes
        // (weight 2) and its boundary (1); an edge of three or more faces gets what its caps leave.
        std::vector<int> chain(topo.edges.size(), 0);
        for (size_t tri = 0; tri < topo.triangles.size(); ++tri) {
            if (topo.edgesOfTriangle[tri].x == MeshTopology::Edge::kNone) continue;  // degenerate, duplicate
            const bool faces = facesPoint(topo, uint32_t(tri), lightInObject);
            const MeshTopology::Component& component = topo.components[topo.componentOfTriangle[tri]];
            if (component.solid() && faces) continue;
            glm::uvec3 v = topo.triangles[tri];
            if (!faces) std::swap(v.y, v.z);  // now wound to face the light
            addCap(v);
            for (int k = 0; k < 3; ++k) {
                const uint32_t e = topo.edgesOfTriangle[tri][k];
                // Edge k runs triangles[tri][k] -> [k + 1]; reversed when the cap was flipped.
                const uint32_t from = faces ? topo.triangles[tri][k] : topo.triangles[tri][(k + 1) % 3];
                chain[e] += from == topo.edges[e].v0 ? 1 : -1;
            }
        }
        // The fans: triangle (b, a, centre) per boundary edge a -> b of a solid; its spokes are edges
        // of the fan alone, counted per vertex (+1 for a run vertex -> centre).
        std::vector<int> spoke(topo.holeFills.empty() ? 0 : meshVertices, 0);
        std::vector<uint32_t> centreOf(spoke.size(), 0);
        for (const MeshTopology::HoleFill& f : topo.holeFills) {
            const glm::dvec3 a(topo.vertices[f.a]), b(topo.vertices[f.b]), m(topo.fillCentres[f.centre]);
            const bool faces = glm::dot(glm::cross(a - b, m - b), glm::dvec3(lightInObject) - b) > 0.0;
            centreOf[f.a] = centreOf[f.b] = f.centre;
            const MeshTopology::Component& component = topo.components[topo.componentOfTriangle[size_t(topo.edges[f.edge].face0)]];
            if (faces || !component.solid()) continue;  // a solid caps its dark side
            const uint32_t centre = uint32_t(meshVertices + f.centre);
            // Flipped to face the light, (b, centre, a) runs a -> b, b -> centre and centre -> a.
            addCap({f.b, centre, f.a});
            chain[f.edge] += f.a == topo.edges[f.edge].v0 ? 1 : -1;
            spoke[f.b] += 1;
            spoke[f.a] -= 1;
        }
        auto addSilhouette = [&](uint32_t from, uint32_t to, int weight, uint32_t topologyEdge, bool boundary) {
            SsvEdge s;
            s.a = world[from];
            s.b = world[to];
            s.object = caster.object;
            s.topologyEdge = topologyEdge;
            s.boundary = boundary;
            s.weight = float(weight);
            const int index = int(g.edges.size());
            g.edges.push_back(s);
            for (int k = 0; k < weight; ++k) {
                const uint32_t f0 = finiteVertex(from), t0 = finiteVertex(to);
                const uint32_t fInf = infiniteVertex(from), tInf = infiniteVertex(to);
                g.volume.triangles.push_back({t0, f0, fInf});
                g.volume.triangles.push_back({t0, fInf, tInf});
                for (int q = 0; q < 2; ++q) {
                    g.volume.kind.push_back(2);
                    g.volume.edge.push_back(index);
                }
            }
        };
        for (uint32_t e = 0; e < topo.edges.size(); ++e) {
            if (chain[e] == 0) continue;
            const MeshTopology::Edge& edge = topo.edges[e];
            if (chain[e] > 0) addSilhouette(edge.v0, edge.v1, chain[e], e, edge.boundary());
            else addSilhouette(edge.v1, edge.v0, -chain[e], e, edge.boundary());
        }
        for (uint32_t v = 0; v < spoke.size(); ++v) {
            if (spoke[v] == 0) continue;
            const uint32_t centre = uint32_t(meshVertices + centreOf[v]);
            if (spoke[v] > 0) addSilhouette(v, centre, spoke[v], MeshTopology::Edge::kNone, false);
            else addSilhouette(centre, v, -spoke[v], MeshTopology::Edge::kNone, false);
        }
    }
    g.wedges.reserve(g.edges.size());
    for (const SsvEdge& e : g.edges) {
        g.wedges.push_back(buildWedge(light, e.a, e.b, farDistance, receivers));
        if (g.wedges.back().kind == SsvWedge::Kind::Everywhere) ++g.wedgesEverywhere;
        if (g.wedges.back().kind == SsvWedge::Kind::None) ++g.wedgesNone;
    }
    return g;
}

}  // namespace shadowlab

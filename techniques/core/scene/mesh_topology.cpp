// Welding, the winged-edge list and silhouettes (see mesh_topology.h). Both building steps are
// near-linear: welding looks each position up in a hash grid (8 cells), the edges are bucketed by
// their smaller vertex (a counting sort) and only each small bucket is sorted.
#include "scene/mesh_topology.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <tuple>

namespace shadowlab {

namespace {

// --- welding --------------------------------------------------------------------------------------

// An open-addressing map from a packed grid cell to the most recently welded vertex in it; the
// other vertices of the cell follow through `next`. Grows at half load.
class CellTable {
public:
    static constexpr uint64_t kEmpty = ~0ull;

    CellTable() : keys_(1024, kEmpty), heads_(1024, 0), mask_(1023) {}

    uint32_t find(uint64_t key) const {
        for (size_t i = slot(key);; i = (i + 1) & mask_) {
            if (keys_[i] == key) return heads_[i];
            if (keys_[i] == kEmpty) return MeshTopology::Edge::kNone;
        }
    }
    void setHead(uint64_t key, uint32_t vertex) {
        if (2 * (count_ + 1) > keys_.size()) grow();
        size_t i = slot(key);
        while (keys_[i] != kEmpty && keys_[i] != key) i = (i + 1) & mask_;
        if (keys_[i] == kEmpty) {
            keys_[i] = key;
            ++count_;
        }
        heads_[i] = vertex;
    }

private:
    size_t slot(uint64_t key) const {
        // splitmix64's finalizer: neighbouring cells land far apart.
        key = (key ^ (key >> 30)) * 0xBF58476D1CE4E5B9ull;
        key = (key ^ (key >> 27)) * 0x94D049BB133111EBull;
        return static_cast<size_t>(key ^ (key >> 31)) & mask_;
    }
    void grow() {
        std::vector<uint64_t> oldKeys = std::move(keys_);
        std::vector<uint32_t> oldHeads = std::move(heads_);
        const size_t size = 2 * oldKeys.size();
        keys_.assign(size, kEmpty);
        heads_.assign(size, 0);
        mask_ = size - 1;
        count_ = 0;
        for (size_t i = 0; i < oldKeys.size(); ++i)
            if (oldKeys[i] != kEmpty) setHead(oldKeys[i], oldHeads[i]);
    }

    std::vector<uint64_t> keys_;
    std::vector<uint32_t> heads_;
    size_t mask_ = 0;
    size_t count_ = 0;
};

// Merges positions closer than `tolerance` into the first of them. Grid cells are 16 tolerances
// wide, so a position's welding partners lie in its own cell or, on an axis where it is within
// the tolerance of a cell border (a quarter more, for rounding), in the neighbour across that
// border: usually one cell is searched, at most 8. Among all partners the lowest index wins, which
// makes the result independent of hashing. Non-finite positions are never welded.
void weld(const std::vector<glm::vec3>& positions, float tolerance, MeshTopology& topology) {
    Bounds bounds;
    for (const glm::vec3& p : positions)
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) bounds.extend(p);
    const glm::dvec3 lo = bounds.empty() ? glm::dvec3(0.0) : glm::dvec3(bounds.lo);
    const double diagonal = bounds.empty() ? 0.0 : glm::length(glm::dvec3(bounds.hi) - lo);
    // 2^20 cells per axis at most, so a cell index (plus one on either side) packs into 21 bits.
    constexpr double kMaxCells = 1048576.0;
    const double cell = std::max({16.0 * static_cast<double>(tolerance), diagonal / kMaxCells, 1e-30});
    const double border = 1.25 * static_cast<double>(tolerance) / cell;  // in cells
    const double toleranceSq = static_cast<double>(tolerance) * static_cast<double>(tolerance);
    const auto pack = [](int64_t x, int64_t y, int64_t z) {
        return static_cast<uint64_t>(x) | static_cast<uint64_t>(y) << 21 | static_cast<uint64_t>(z) << 42;
    };

    CellTable table;
    std::vector<uint32_t> next;  // per welded vertex: the previous one in its cell
    topology.weldedFromMeshVertex.resize(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) {
        const glm::vec3& p = positions[i];
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) {
            topology.weldedFromMeshVertex[i] = static_cast<uint32_t>(topology.vertices.size());
            topology.vertices.push_back(p);
            next.push_back(MeshTopology::Edge::kNone);
            continue;
        }
        const glm::dvec3 g = (glm::dvec3(p) - lo) / cell;
        int64_t base[3], side[3];
        for (int a = 0; a < 3; ++a) {
            const double f = std::floor(g[a]);
            base[a] = std::clamp<int64_t>(static_cast<int64_t>(f), 0, 1 << 20) + 1;
            side[a] = g[a] - f < border ? -1 : g[a] - f > 1.0 - border ? 1 : 0;
        }
        uint32_t best = MeshTopology::Edge::kNone;
        for (int corner = 0; corner < 8; ++corner) {
            if (((corner & 1) && !side[0]) || ((corner & 2) && !side[1]) || ((corner & 4) && !side[2])) continue;
            const uint64_t key = pack(base[0] + ((corner & 1) ? side[0] : 0),
                                      base[1] + ((corner & 2) ? side[1] : 0),
                                      base[2] + ((corner & 4) ? side[2] : 0));
            for (uint32_t v = table.find(key); v != MeshTopology::Edge::kNone; v = next[v]) {
                const glm::dvec3 d = glm::dvec3(topology.vertices[v]) - glm::dvec3(p);
                if (v < best && glm::dot(d, d) <= toleranceSq) best = v;
            }
        }
        if (best == MeshTopology::Edge::kNone) {
            best = static_cast<uint32_t>(topology.vertices.size());
            topology.vertices.push_back(p);
            const uint64_t key = pack(base[0], base[1], base[2]);
            next.push_back(table.find(key));
            table.setHead(key, best);
        }
        topology.weldedFromMeshVertex[i] = best;
    }
}

// --- edges ----------------------------------------------------------------------------------------

// One side of an edge: triangle t traverses it from corner k to corner k + 1.
struct HalfEdge {
    uint32_t other;     // the larger welded vertex of the edge (the bucket is the smaller one)
    uint32_t triangle;
    uint32_t corner;
};

// Does triangle `tri` run from a to b (a directly followed by b in its cyclic order)?
bool runs(const glm::uvec3& tri, uint32_t a, uint32_t b) {
    return (tri[0] == a && tri[1] == b) || (tri[1] == a && tri[2] == b) || (tri[2] == a && tri[0] == b);
}

glm::dvec3 corner(const MeshTopology& topology, uint32_t triangle, int k) {
    return glm::dvec3(topology.vertices[topology.triangles[triangle][k]]);
}

}  // namespace

namespace {

// The winged edges of the non-degenerate triangles (cleared and rebuilt: orientComponents calls it
// again after flipping triangles).
void buildEdges(MeshTopology& topology) {
    const size_t triangleCount = topology.triangles.size();
    topology.edges.clear();
    topology.edgesOfTriangle.assign(triangleCount, glm::uvec3(MeshTopology::Edge::kNone));
    topology.consistentlyOriented = true;
    // Half-edges bucketed by their smaller vertex (counting sort, stable in triangle order).
    const size_t vertexCount = topology.vertices.size();
    std::vector<uint32_t> bucketStart(vertexCount + 1, 0);
    const auto isDegenerate = [&](size_t t) { return topology.faceNormals[t] == glm::vec3(0.0f); };
    for (size_t t = 0; t < triangleCount; ++t) {
        if (isDegenerate(t)) continue;
        const glm::uvec3& tri = topology.triangles[t];
        for (int k = 0; k < 3; ++k) ++bucketStart[std::min(tri[k], tri[(k + 1) % 3]) + 1];
    }
    for (size_t v = 0; v < vertexCount; ++v) bucketStart[v + 1] += bucketStart[v];
    std::vector<HalfEdge> halfEdges(bucketStart[vertexCount]);
    {
        std::vector<uint32_t> fill(bucketStart.begin(), bucketStart.end() - 1);
        for (size_t t = 0; t < triangleCount; ++t) {
            if (isDegenerate(t)) continue;
            const glm::uvec3& tri = topology.triangles[t];
            for (uint32_t k = 0; k < 3; ++k) {
                const uint32_t a = tri[k], b = tri[(k + 1) % 3];
                halfEdges[fill[std::min(a, b)]++] = {std::max(a, b), uint32_t(t), k};
            }
        }
    }

    // Each bucket sorted by the other vertex; a run of equal (v0, v1) is one edge.
    topology.edges.reserve(halfEdges.size() / 2 + 1);
    for (uint32_t v0 = 0; v0 < vertexCount; ++v0) {
        const auto first = halfEdges.begin() + bucketStart[v0], last = halfEdges.begin() + bucketStart[v0 + 1];
        std::sort(first, last, [](const HalfEdge& x, const HalfEdge& y) {
            return std::tie(x.other, x.triangle, x.corner) < std::tie(y.other, y.triangle, y.corner);
        });
        for (auto run = first; run != last;) {
            auto end = run;
            while (end != last && end->other == run->other) ++end;
            MeshTopology::Edge edge;
            edge.v0 = v0;
            edge.v1 = run->other;
            edge.faceCount = static_cast<uint32_t>(end - run);
            const auto forward = [&](const HalfEdge& h) { return topology.triangles[h.triangle][h.corner] == v0; };
            // face0: the first face running v0 -> v1, else the first face; face1: the next other.
            auto side0 = std::find_if(run, end, forward);
            if (side0 == end) side0 = run;
            auto side1 = run == side0 ? run + 1 : run;
            const auto opposite = [&](const HalfEdge& h) { return topology.triangles[h.triangle][(h.corner + 2) % 3]; };
            edge.face0 = int32_t(side0->triangle);
            edge.opposite0 = opposite(*side0);
            if (side1 != end) {
                edge.face1 = int32_t(side1->triangle);
                edge.opposite1 = opposite(*side1);
                // Consistent orientation: the two faces of a manifold edge traverse it oppositely.
                if (edge.faceCount == 2 && forward(*side0) == forward(*side1)) topology.consistentlyOriented = false;
            }
            const uint32_t index = static_cast<uint32_t>(topology.edges.size());
            for (auto h = run; h != end; ++h) topology.edgesOfTriangle[h->triangle][h->corner] = index;
            topology.edges.push_back(edge);
            run = end;
        }
    }
}

// Triangles with the same three welded corners as an earlier one, in either winding (a mesh
// exported twice, a two-sided plane modelled as two faces): the later ones are left out of the edge
// structure like degenerate triangles, so that the first one's edges keep two faces.
void markDuplicates(MeshTopology& topology) {
    std::vector<std::pair<std::array<uint32_t, 3>, uint32_t>> keys;
    keys.reserve(topology.triangles.size());
    for (size_t t = 0; t < topology.triangles.size(); ++t) {
        if (topology.faceNormals[t] == glm::vec3(0.0f)) continue;
        std::array<uint32_t, 3> k = {topology.triangles[t][0], topology.triangles[t][1], topology.triangles[t][2]};
        std::sort(k.begin(), k.end());
        keys.push_back({k, uint32_t(t)});
    }
    std::sort(keys.begin(), keys.end());
    for (size_t i = 1; i < keys.size(); ++i)
        if (keys[i].first == keys[i - 1].first) {
            const uint32_t t = keys[i].second;
            topology.duplicateTriangles.push_back(t);
            topology.degenerateTriangles.push_back(t);
            topology.faceNormals[t] = glm::vec3(0.0f);
        }
    std::sort(topology.duplicateTriangles.begin(), topology.duplicateTriangles.end());
    std::sort(topology.degenerateTriangles.begin(), topology.degenerateTriangles.end());
}

// Walks each patch of triangles joined by two-face edges and flips the ones wound against the
// patch's first triangle, then flips the whole patch if most of its area was wound the other way
// (the author's majority decides which side is out). Returns the triangles flipped. A patch that
// cannot be oriented (a Moebius strip) keeps the first winding found for each triangle.
size_t orientComponents(MeshTopology& topology) {
    const size_t n = topology.triangles.size();
    std::vector<int8_t> flip(n, -1);  // -1 not reached, 0 kept, 1 flipped
    std::vector<uint32_t> patch, stack;
    size_t flipped = 0;
    const auto area = [&](uint32_t t) {
        const glm::dvec3 a = corner(topology, t, 0), b = corner(topology, t, 1), c = corner(topology, t, 2);
        return glm::length(glm::cross(b - a, c - a));
    };
    for (uint32_t seed = 0; seed < n; ++seed) {
        if (flip[seed] >= 0 || topology.edgesOfTriangle[seed][0] == MeshTopology::Edge::kNone) continue;
        patch.clear();
        flip[seed] = 0;
        stack.push_back(seed);
        while (!stack.empty()) {
            const uint32_t t = stack.back();
            stack.pop_back();
            patch.push_back(t);
            for (int k = 0; k < 3; ++k) {
                const MeshTopology::Edge& e = topology.edges[topology.edgesOfTriangle[t][k]];
                if (e.faceCount != 2) continue;
                const uint32_t other = uint32_t(e.face0 == int32_t(t) ? e.face1 : e.face0);
                if (flip[other] >= 0) continue;
                // Consistent: the two faces traverse the edge in opposite directions, once each
                // face's own flip is applied.
                const bool tForward = runs(topology.triangles[t], e.v0, e.v1) != (flip[t] == 1);
                const bool oForward = runs(topology.triangles[other], e.v0, e.v1);
                flip[other] = tForward == oForward ? 1 : 0;
                stack.push_back(other);
            }
        }
        double kept = 0.0, reversed = 0.0;
        for (uint32_t t : patch) (flip[t] ? reversed : kept) += area(t);
        const bool invert = reversed > kept;
        for (uint32_t t : patch) {
            if ((flip[t] == 1) == invert) continue;
            std::swap(topology.triangles[t][1], topology.triangles[t][2]);
            topology.faceNormals[t] = -topology.faceNormals[t];
            topology.reorientedTriangles.push_back(t);
            ++flipped;
        }
    }
    std::sort(topology.reorientedTriangles.begin(), topology.reorientedTriangles.end());
    return flipped;
}

// Connected components across every shared edge (two faces or more) and, per component, its area
// (its openings' area: fillOpenings). Non-manifold edges join: a scanned solid with a few of them is
// still one solid.
void findComponents(MeshTopology& topology) {
    const size_t n = topology.triangles.size();
    topology.componentOfTriangle.assign(n, MeshTopology::Edge::kNone);
    topology.components.clear();
    // Faces per edge, for walking across non-manifold edges (the winged edge keeps two).
    std::vector<uint32_t> start(topology.edges.size() + 1, 0), faces;
    for (size_t t = 0; t < n; ++t)
        if (topology.edgesOfTriangle[t][0] != MeshTopology::Edge::kNone)
            for (int k = 0; k < 3; ++k) ++start[topology.edgesOfTriangle[t][k] + 1];
    for (size_t e = 0; e < topology.edges.size(); ++e) start[e + 1] += start[e];
    faces.resize(start.back());
    {
        std::vector<uint32_t> fill(start.begin(), start.end() - 1);
        for (size_t t = 0; t < n; ++t)
            if (topology.edgesOfTriangle[t][0] != MeshTopology::Edge::kNone)
                for (int k = 0; k < 3; ++k) faces[fill[topology.edgesOfTriangle[t][k]]++] = uint32_t(t);
    }
    std::vector<uint32_t> stack;
    for (uint32_t seed = 0; seed < n; ++seed) {
        if (topology.componentOfTriangle[seed] != MeshTopology::Edge::kNone ||
            topology.edgesOfTriangle[seed][0] == MeshTopology::Edge::kNone)
            continue;
        const uint32_t id = uint32_t(topology.components.size());
        MeshTopology::Component c;
        topology.componentOfTriangle[seed] = id;
        stack.push_back(seed);
        while (!stack.empty()) {
            const uint32_t t = stack.back();
            stack.pop_back();
            ++c.triangles;
            const glm::dvec3 a = corner(topology, t, 0), b = corner(topology, t, 1), d = corner(topology, t, 2);
            const glm::dvec3 twice = glm::cross(b - a, d - a);
            c.area += 0.5 * glm::length(twice);
            for (int k = 0; k < 3; ++k) {
                const uint32_t ei = topology.edgesOfTriangle[t][k];
                const MeshTopology::Edge& e = topology.edges[ei];
                if (e.boundary()) ++c.boundaryEdges;
                if (e.faceCount == 2) {
                    const uint32_t other = uint32_t(e.face0 == int32_t(t) ? e.face1 : e.face0);
                    if (runs(topology.triangles[t], e.v0, e.v1) == runs(topology.triangles[other], e.v0, e.v1))
                        c.orientable = false;
                }
                for (uint32_t i = start[ei]; i < start[ei + 1]; ++i) {
                    const uint32_t other = faces[i];
                    if (topology.componentOfTriangle[other] != MeshTopology::Edge::kNone) continue;
                    topology.componentOfTriangle[other] = id;
                    stack.push_back(other);
                }
            }
        }
        topology.components.push_back(c);
    }
    // Each non-manifold edge once, in the component it belongs to.
    for (size_t e = 0; e < topology.edges.size(); ++e)
        if (topology.edges[e].nonManifold())
            ++topology.components[topology.componentOfTriangle[size_t(topology.edges[e].face0)]].nonManifoldEdges;
}

// The openings: boundary edges grouped by the vertices they share (union-find). Each opening's area
// is the length of its vector area, half the sum of (a - c) x (b - c) over its edges a -> b as their
// faces run them, c its centre (the area of the flat patch that would close a planar opening); a
// component's openArea is the sum over its openings. Then MeshTopology::holeFills: each opening of a solid component closed
// by a fan about its centre, the mean of its vertices.
void fillOpenings(MeshTopology& topology) {
    std::vector<uint32_t> parent;
    std::vector<uint32_t> slot(topology.vertices.size(), MeshTopology::Edge::kNone);
    std::vector<uint32_t> vertexOf;
    const auto find = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    const auto slotOf = [&](uint32_t v) {
        if (slot[v] == MeshTopology::Edge::kNone) {
            slot[v] = uint32_t(parent.size());
            parent.push_back(slot[v]);
            vertexOf.push_back(v);
        }
        return slot[v];
    };
    std::vector<MeshTopology::HoleFill> edges;
    for (uint32_t e = 0; e < topology.edges.size(); ++e) {
        const MeshTopology::Edge& edge = topology.edges[e];
        if (!edge.boundary()) continue;
        MeshTopology::HoleFill f;
        const bool forward = runs(topology.triangles[size_t(edge.face0)], edge.v0, edge.v1);
        f.a = forward ? edge.v0 : edge.v1;
        f.b = forward ? edge.v1 : edge.v0;
        f.edge = e;
        const uint32_t x = find(slotOf(f.a)), y = find(slotOf(f.b));
        if (x != y) parent[x] = y;
        edges.push_back(f);
    }
    if (edges.empty()) return;
    // Per opening (indexed by its root's order of appearance): centre, vector area, component.
    std::vector<uint32_t> openingOfRoot(parent.size(), MeshTopology::Edge::kNone);
    std::vector<glm::dvec3> sum, vectorArea;
    std::vector<double> count;
    std::vector<uint32_t> componentOf;
    for (uint32_t i = 0; i < parent.size(); ++i) {
        const uint32_t r = find(i);
        if (openingOfRoot[r] == MeshTopology::Edge::kNone) {
            openingOfRoot[r] = uint32_t(sum.size());
            sum.push_back(glm::dvec3(0.0));
            vectorArea.push_back(glm::dvec3(0.0));
            count.push_back(0.0);
            componentOf.push_back(MeshTopology::Edge::kNone);
        }
        sum[openingOfRoot[r]] += glm::dvec3(topology.vertices[vertexOf[i]]);
        count[openingOfRoot[r]] += 1.0;
    }
    for (MeshTopology::HoleFill& f : edges) {
        const uint32_t o = openingOfRoot[find(slot[f.a])];
        f.centre = o;
        // About the opening's centre: the same for a closed loop, and the fan's area for a chain that
        // ends at a non-manifold vertex (which about the origin would depend on where the origin is).
        const glm::dvec3 c = sum[o] / count[o];
        vectorArea[o] += 0.5 * glm::cross(glm::dvec3(topology.vertices[f.a]) - c, glm::dvec3(topology.vertices[f.b]) - c);
        if (componentOf[o] == MeshTopology::Edge::kNone)
            componentOf[o] = topology.componentOfTriangle[size_t(topology.edges[f.edge].face0)];
    }
    for (size_t o = 0; o < sum.size(); ++o) topology.components[componentOf[o]].openArea += glm::length(vectorArea[o]);
    // The fans, for the openings of solid components (renumbered: fillCentres holds only theirs).
    std::vector<uint32_t> centre(sum.size(), MeshTopology::Edge::kNone);
    for (const MeshTopology::HoleFill& f : edges) {
        if (!topology.components[componentOf[f.centre]].solid()) continue;
        if (centre[f.centre] == MeshTopology::Edge::kNone) {
            centre[f.centre] = uint32_t(topology.fillCentres.size());
            topology.fillCentres.push_back(glm::vec3(sum[f.centre] / count[f.centre]));
        }
        MeshTopology::HoleFill fill = f;
        fill.centre = centre[f.centre];
        topology.holeFills.push_back(fill);
    }
}

}  // namespace

MeshTopology buildTopology(const Mesh& mesh, float weldTolerance) {
    MeshTopology topology;
    // Default tolerance: 1e-6 of the bounding-box diagonal, far above float rounding of positions
    // computed twice by the same formula and far below any feature a scene models.
    if (weldTolerance < 0.0f) {
        Bounds bounds;
        for (const glm::vec3& p : mesh.positions)
            if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) bounds.extend(p);
        weldTolerance = bounds.empty() ? 0.0f : 1e-6f * glm::length(bounds.hi - bounds.lo);
    }
    topology.weldTolerance = weldTolerance;
    weld(mesh.positions, weldTolerance, topology);

    // Triangles, their normals, and the degenerate ones: repeated welded corners, or a height
    // (twice the area over the longest side) within the weld tolerance, the same distance under
    // which two vertices merge.
    const size_t triangleCount = mesh.triangleCount();
    topology.triangles.resize(triangleCount);
    topology.faceNormals.assign(triangleCount, glm::vec3(0.0f));
    topology.edgesOfTriangle.assign(triangleCount, glm::uvec3(MeshTopology::Edge::kNone));
    for (size_t t = 0; t < triangleCount; ++t) {
        glm::uvec3 tri;
        for (int k = 0; k < 3; ++k) {
            const uint32_t index = mesh.indices[3 * t + k];
            if (index >= mesh.positions.size()) {
                std::fprintf(stderr, "buildTopology: triangle %zu index %u >= %zu positions\n", t, index,
                             mesh.positions.size());
                std::abort();
            }
            tri[k] = topology.weldedFromMeshVertex[index];
        }
        topology.triangles[t] = tri;
        const glm::dvec3 a = corner(topology, uint32_t(t), 0), b = corner(topology, uint32_t(t), 1),
                         c = corner(topology, uint32_t(t), 2);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        const double twiceArea = glm::length(n);
        const double longest =
            std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        const bool repeated = tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0];
        if (repeated || !(twiceArea > static_cast<double>(weldTolerance) * longest) || !(twiceArea > 0.0) ||
            !std::isfinite(twiceArea)) {
            topology.degenerateTriangles.push_back(uint32_t(t));
            continue;
        }
        topology.faceNormals[t] = glm::vec3(n / twiceArea);
    }

    markDuplicates(topology);
    buildEdges(topology);
    if (!topology.consistentlyOriented && orientComponents(topology) > 0) buildEdges(topology);
    findComponents(topology);
    fillOpenings(topology);
    return topology;
}

size_t MeshTopology::boundaryEdges() const {
    return static_cast<size_t>(std::count_if(edges.begin(), edges.end(), [](const Edge& e) { return e.boundary(); }));
}

size_t MeshTopology::nonManifoldEdges() const {
    return static_cast<size_t>(std::count_if(edges.begin(), edges.end(), [](const Edge& e) { return e.nonManifold(); }));
}

bool MeshTopology::isClosed() const {
    return !edges.empty() && std::all_of(edges.begin(), edges.end(), [](const Edge& e) { return e.faceCount == 2; });
}

int64_t MeshTopology::eulerCharacteristic() const {
    std::vector<bool> used(vertices.size(), false);
    for (const Edge& e : edges) used[e.v0] = used[e.v1] = true;
    const int64_t v = std::count(used.begin(), used.end(), true);
    const int64_t f = static_cast<int64_t>(triangles.size() - degenerateTriangles.size());
    return v - static_cast<int64_t>(edges.size()) + f;
}

std::vector<uint32_t> MeshTopology::adjacencyIndices() const {
    std::vector<uint32_t> indices;
    indices.reserve(6 * (triangles.size() - degenerateTriangles.size()));
    for (size_t t = 0; t < triangles.size(); ++t) {
        const glm::uvec3& tri = triangles[t];
        if (edgesOfTriangle[t][0] == Edge::kNone) continue;  // degenerate
        for (int k = 0; k < 3; ++k) {
            const Edge& e = edges[edgesOfTriangle[t][k]];
            const uint32_t own = tri[(k + 2) % 3];
            uint32_t across = own;  // boundary or non-manifold: the marker convention
            if (e.hasAdjacency()) across = e.face0 == int32_t(t) ? e.opposite1 : e.opposite0;
            indices.push_back(tri[k]);
            indices.push_back(across);
        }
    }
    return indices;
}

bool facesPoint(const MeshTopology& topology, uint32_t triangle, const glm::vec3& point) {
    // The sign of the plane equation at the point, in double so that the CPU answer is stable;
    // a degenerate triangle has a zero normal and faces nothing.
    if (topology.faceNormals[triangle] == glm::vec3(0.0f)) return false;
    const glm::dvec3 a = corner(topology, triangle, 0), b = corner(topology, triangle, 1),
                     c = corner(topology, triangle, 2);
    return glm::dot(glm::cross(b - a, c - a), glm::dvec3(point) - a) > 0.0;
}

std::vector<uint32_t> silhouetteEdges(const MeshTopology& topology, const glm::vec3& lightPosition) {
    // Facing of every face once, so that both sides of an edge see the same answer.
    std::vector<bool> front(topology.triangles.size());
    for (size_t t = 0; t < topology.triangles.size(); ++t) front[t] = facesPoint(topology, uint32_t(t), lightPosition);
    std::vector<uint32_t> silhouette;
    for (size_t i = 0; i < topology.edges.size(); ++i) {
        const MeshTopology::Edge& e = topology.edges[i];
        if (!e.hasAdjacency() || front[size_t(e.face0)] != front[size_t(e.face1)]) silhouette.push_back(uint32_t(i));
    }
    return silhouette;
}

glm::uvec2 orientSilhouetteEdge(const MeshTopology& topology, uint32_t edge, const glm::vec3& lightPosition) {
    const MeshTopology::Edge& e = topology.edges[edge];
    const auto along = [&](int32_t face) {
        return runs(topology.triangles[size_t(face)], e.v0, e.v1) ? glm::uvec2(e.v0, e.v1) : glm::uvec2(e.v1, e.v0);
    };
    if (facesPoint(topology, uint32_t(e.face0), lightPosition)) return along(e.face0);
    if (e.face1 >= 0 && facesPoint(topology, uint32_t(e.face1), lightPosition)) return along(e.face1);
    const glm::uvec2 d = along(e.face0);
    return glm::uvec2(d.y, d.x);
}

}  // namespace shadowlab

// Mesh topology for the silhouette techniques (ssv, pvm, pvmf): welded vertices, a winged-edge
// list (each edge with the faces on its two sides), boundary and non-manifold edges, an index
// buffer with triangle adjacency for geometry shaders, and the silhouette seen from the light
// centre.
//
// Why welding: primitives and glTF files split vertices for flat normals and UV seams, so a box
// has 24 positions where its surface has 8 corners. Silhouette detection needs the faces on both
// sides of an edge (assarsson2004, "silhouette edges from the light centre"; cournia2005 ch. 4,
// "winged-edge silhouettes"), and a split vertex makes every crease look like a boundary.
#pragma once
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "scene/scene.h"

namespace shadowlab {

struct MeshTopology {
    // An edge between two welded vertices and the faces that share it (winged edge). face0 is the
    // face in which the edge runs v0 -> v1 (the first such face), or the first face found when no
    // face runs that way; face1 is the next face found, -1 when the edge is a boundary. Faces
    // beyond the second (non-manifold edges) are only counted.
    struct Edge {
        static constexpr uint32_t kNone = ~0u;
        uint32_t v0 = 0, v1 = 0;          // welded vertex indices, v0 < v1
        int32_t face0 = -1, face1 = -1;   // triangle indices
        uint32_t opposite0 = kNone;       // the vertex of face0 that is not on the edge
        uint32_t opposite1 = kNone;       // the vertex of face1 that is not on the edge (kNone: boundary)
        uint32_t faceCount = 0;           // all non-degenerate faces sharing the edge

        bool boundary() const { return faceCount == 1; }
        bool nonManifold() const { return faceCount > 2; }
        // The edge has exactly one neighbouring face across it: adjacencyIndices() carries it.
        bool hasAdjacency() const { return faceCount == 2; }
    };

    std::vector<glm::vec3> vertices;                  // welded, in order of first occurrence
    std::vector<uint32_t> weldedFromMeshVertex;       // Mesh position index -> welded vertex
    std::vector<glm::uvec3> triangles;                // one per Mesh triangle, same order, welded
    std::vector<glm::vec3> faceNormals;               // unit, cross(b - a, c - a); zero if degenerate
    std::vector<uint32_t> degenerateTriangles;        // ascending; not in the edge structure (duplicates too)
    // Triangles with the corners of an earlier one, in either winding: in degenerateTriangles too,
    // so the first one alone is in the edge structure (a duplicated mesh stays a manifold).
    std::vector<uint32_t> duplicateTriangles;
    // Triangles whose winding buildTopology reversed so that every edge with two faces is traversed
    // in opposite directions (see consistentlyOriented); `triangles` and `faceNormals` hold the
    // reversed ones. Within a patch joined by two-face edges, the winding of most of its area wins.
    std::vector<uint32_t> reorientedTriangles;
    std::vector<Edge> edges;                          // sorted by (v0, v1)
    // edgesOfTriangle[t][k]: the edge from triangles[t][k] to triangles[t][(k + 1) % 3];
    // Edge::kNone for degenerate triangles.
    std::vector<glm::uvec3> edgesOfTriangle;
    float weldTolerance = 0.0f;                       // the distance used (object space)
    // Every edge with two faces is traversed in opposite directions by them (non-manifold edges are
    // not judged). Outward normals of a closed mesh then all point outwards or all inwards. False
    // after buildTopology only where no winding makes it so (a non-orientable patch).
    bool consistentlyOriented = true;

    // A connected component: triangles joined by shared edges (two faces or more).
    struct Component {
        size_t triangles = 0;
        double area = 0.0;
        // The area its openings span: per opening (boundary edges joined at their vertices), the
        // length of its vector area (half the sum of (a - c) x (b - c) over its edges a -> b, c the
        // opening's centre), summed. 0 for a
        // closed surface; the whole area for a flat sheet, half of it for a hemisphere.
        double openArea = 0.0;
        size_t boundaryEdges = 0, nonManifoldEdges = 0;
        bool orientable = true;
        // A solid with openings (a scanned model with holes, a box missing a face): orientable (every
        // two-face edge run both ways) and its openings span at most kSolidOpenFraction of its area. Shadow volumes cap it on one
        // side (techniques/ssv/README.md); any other patch is a sheet, which occludes from both.
        static constexpr double kSolidOpenFraction = 0.25;
        bool solid() const { return orientable && openArea <= kSolidOpenFraction * area; }
    };
    std::vector<Component> components;
    std::vector<uint32_t> componentOfTriangle;        // per triangle; Edge::kNone for degenerate ones

    // The openings of the solid components closed by fans (shadow volumes need a closed surface to
    // cap on one side: techniques/ssv/README.md). Boundary edges joined at their vertices form an
    // opening; its centre is the mean of its vertices; each of its boundary edges, run a -> b by its
    // face, is closed by the triangle (b, a, centre), wound like the mesh, so that the filled
    // surface is closed and consistently wound wherever the opening is a simple loop.
    struct HoleFill {
        uint32_t a = 0, b = 0;  // welded vertices
        uint32_t centre = 0;    // index into fillCentres
        uint32_t edge = 0;      // the boundary edge closed
    };
    std::vector<glm::vec3> fillCentres;
    std::vector<HoleFill> holeFills;

    size_t boundaryEdges() const;
    size_t nonManifoldEdges() const;
    // Every edge has exactly two faces. An empty topology (no edges) is not closed.
    bool isClosed() const;
    // V - E + F over the surface: vertices used by a non-degenerate triangle, edges, and
    // non-degenerate triangles. 2 for a sphere-like closed surface, 0 for a torus, 1 for a disk.
    int64_t eulerCharacteristic() const;

    // Index buffer (into `vertices`) for GL_TRIANGLES_ADJACENCY: 6 indices per non-degenerate
    // triangle, in triangle order (degenerate triangles are skipped, so gl_PrimitiveID is the
    // index among non-degenerate triangles): v0, opp(v0v1), v1, opp(v1v2), v2, opp(v2v0), where
    // opp(ab) is the vertex of the neighbouring face across ab that is not on it.
    // Convention for an edge without exactly one neighbour (boundary or non-manifold edge): opp is
    // the triangle's own opposite vertex, so the geometry shader detects it as
    // gl_in[2k + 1] == gl_in[(2k + 4) % 6] (the same vertex, hence the same shader output). The
    // per-edge flag is Edge::hasAdjacency(). The neighbour is assumed to be wound like the
    // triangle (consistentlyOriented): its facing is that of (v[k+1], v[k], opp).
    std::vector<uint32_t> adjacencyIndices() const;
};

// Welds `mesh`'s positions and builds its winged-edge topology. weldTolerance < 0 selects
// 1e-6 times the bounding-box diagonal; 0 welds only identical positions. Near-linear: a hash
// grid for welding, a bucket sort by the smaller vertex for the edges. Triangles whose welded
// corners repeat, or whose height is within the weld tolerance, are degenerate.
MeshTopology buildTopology(const Mesh& mesh, float weldTolerance = -1.0f);

// Does triangle t face the point? True when the point is strictly on the side its normal points
// to; a point in the triangle's plane (and a degenerate triangle) counts as facing away.
bool facesPoint(const MeshTopology& topology, uint32_t triangle, const glm::vec3& point);

// Silhouette edges seen from the light centre (assarsson2004: "silhouette edges from the light
// centre"; cournia2005 ch. 4 uses the winged-edge test): the indices of edges whose two faces
// face the light differently, plus every boundary and non-manifold edge. Open meshes are treated
// as assarsson2004 treats them: a boundary edge is always a silhouette candidate, whichever way
// its face points (its wedge is needed from both sides); a non-manifold edge likewise, because a
// missed wedge leaves a hole while an extra one only costs fill. Ascending edge order.
std::vector<uint32_t> silhouetteEdges(const MeshTopology& topology, const glm::vec3& lightPosition);

// A silhouette edge as a directed segment (from, to) of welded vertices: it runs the way the face
// that faces the light traverses it, so that face lies on the left of from -> to seen from the
// light (counter-clockwise faces). When no face on the edge faces the light (a back-facing
// boundary), it runs against face0. On a closed, consistently oriented mesh the directed
// silhouette edges form closed loops: every vertex has as many incoming as outgoing edges.
glm::uvec2 orientSilhouetteEdge(const MeshTopology& topology, uint32_t edge,
                                const glm::vec3& lightPosition);

}  // namespace shadowlab

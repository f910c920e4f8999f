// `ssv`: soft shadow volumes with penumbra wedges (assarsson2004). The CPU geometry the passes
// draw: silhouette edges from the light centre, the hard shadow volume (sides, caps, points at
// infinity) and one penumbra wedge per silhouette edge, built as the slides build it. Public for
// the views and the tests: the views draw exactly these meshes.
#pragma once
#include <array>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "graph/technique.h"
#include "scene/mesh_topology.h"
#include "scene/scene.h"

namespace shadowlab {

const TechniqueDesc& ssvTechnique();

// The light as the wedge construction sees it: its centre and plane, and its extent (square:
// corners; disk and sphere: a sphere of radius r about the centre, which contains the disk, so a
// wedge tangent to it encloses the disk's penumbra too).
struct SsvLight {
    LightShape shape = LightShape::Square;
    glm::vec3 centre{0.0f}, right{1, 0, 0}, up{0, 1, 0}, direction{0, 0, -1};
    float size = 1.0f;  // square: width w_l; disk, sphere: radius r
    std::array<glm::vec3, 4> corners() const;  // square only
    float halfSize() const { return shape == LightShape::Square ? 0.5f * size : size; }
    static SsvLight from(const Light& light);
};

// The slides' 2x2 light splitting ("Light splitting": parameter `split` = 2): a square light as
// its four quarter squares (width w_l / 2, centres at +-w_l / 4 along right and up), each with its
// own silhouettes, volume and wedges; v is the mean of the quarters' (each a quarter of the light's
// area). With split 1, or a disk, sphere or point light (not split: README.md), the light itself.
std::vector<Light> ssvSubLights(const Light& light, int split);

// A plane n . x = d (n unit); inside is n . x >= d.
struct SsvPlane {
    glm::vec3 n{0.0f};
    float d = 0.0f;
    float distance(const glm::vec3& x) const { return glm::dot(n, x) - d; }
};

// One penumbra wedge (assarsson2004, "Wedge construction: in practice"):
//  A. the farther end point moved towards the light centre until both are equally far;
//  B. front and back planes through the (moved) edge, each rotated until it touches one side of
//     the light;
//  C. a side plane at each end point, about the axis cross(e1 - e0, I_c - e0), rotated until it
//     touches the far side of the light;
//  D. a bottom plane beyond every receiver (the scene's bounds).
// Its six corners are the two apexes (the moved edge) and four bottom corners; it is drawn as 8
// triangles, wound outwards. `kind` says how it is rasterised.
struct SsvWedge {
    enum class Kind {
        Wedge,       // a closed convex wedge: the stencil culling of the slides applies
        Everywhere,  // the construction has no tangent planes (the edge's line passes through or too
                     // near the light): the edge's coverage is evaluated at every pixel instead
        None,        // the edge lies on a line through the light centre: its coverage is 0 everywhere
    };
    Kind kind = Kind::Wedge;
    glm::vec3 apex0{0.0f}, apex1{0.0f};  // the moved edge e0' -> e1'
    SsvPlane front, back, side0, side1, bottom;
    std::array<glm::vec3, 6> corners{};  // apex0, apex1, front-side0, front-side1, back-side1, back-side0 (bottom)
    std::array<glm::uvec3, 8> triangles{};  // into corners, wound outwards
    std::array<int, 8> faceOfTriangle{};    // 0 front, 1 back, 2 side, 3 bottom
    bool contains(const glm::vec3& x, float tolerance = 0.0f) const;
    std::string why;  // for Everywhere and None: which step failed
};
// `farDistance`: the bottom plane lies at this distance from the light centre along the wedge's
// axis (beyond every receiver). With `receivers` (the scene's bounds), nearer when it can: just
// beyond the box's farthest corner along this wedge's axis (every receiver lies in the box, so
// nothing is lost, and the wedge stops under the floor instead of far below it: fewer pixels to
// rasterize).
SsvWedge buildWedge(const SsvLight& light, const glm::vec3& e0, const glm::vec3& e1, float farDistance,
                    const Bounds* receivers = nullptr);

// A silhouette edge in world space: an edge of the boundary of the caps (buildSsvGeometry), oriented
// the way the caps, wound to face the light centre, run it (on a closed mesh: the face facing the
// light lies on its left seen from the light, as orientSilhouetteEdge), with its weight, the number
// of caps' sides it carries: 1 on a solid; on a sheet (every triangle occludes from both sides) an
// interior silhouette edge bounds two caps and counts twice, a boundary edge once.
struct SsvEdge {
    glm::vec3 a{0.0f}, b{0.0f};
    float weight = 1.0f;
    int object = 0;  // index into scene.objects
    uint32_t topologyEdge = 0;  // MeshTopology::Edge::kNone: a spoke of a fan closing a solid's opening
    bool boundary = false;
};

// The hard shadow volume from the light centre (Crow 1977, z-fail with caps; Everitt and Kilgard
// 2002's infinite far plane): triangles with homogeneous vertices (w = 0: the point at infinity in
// the direction xyz from the light centre).
struct SsvVolume {
    std::vector<glm::vec4> vertices;
    std::vector<glm::uvec3> triangles;
    std::vector<int> kind;  // per triangle: 0 near cap, 1 far cap, 2 side
    std::vector<int> edge;  // per triangle: the silhouette edge of a side, -1 for caps
};

struct SsvGeometry {
    std::vector<SsvEdge> edges;
    std::vector<SsvWedge> wedges;  // one per edge
    SsvVolume volume;
    std::vector<std::string> warnings;  // non-manifold objects, named
    size_t wedgesEverywhere = 0, wedgesNone = 0;
};

// Topologies of the casters, built once per scene (buildTopology welds and finds the winged edges).
struct SsvCaster {
    int object = 0;
    MeshTopology topology;
};
std::vector<SsvCaster> buildSsvCasters(const Scene& scene);

// Silhouettes, volume and wedges of the casters posed at time t. `capOffset` moves the finite
// vertices of the volume away from the light centre by this distance, so that a receiver on the
// occluder's own surface is not inside its own volume by rounding.
SsvGeometry buildSsvGeometry(const Scene& scene, const std::vector<SsvCaster>& casters, double t,
                             const SsvLight& light, float farDistance, float capOffset,
                             const Bounds* receivers = nullptr);

}  // namespace shadowlab

// Penumbra volume maps (cournia2005 chapter 4): the extrusion of a silhouette vertex into the inner
// and outer penumbra volumes (sec. 4.1.2), and the visibility of a spherical light of radius r at a
// point inside a volume from the cutting plane and the disk segment (sec. 4.2, eq. 4.1-4.2 and the
// Bernstein interpolant v = 3k^2 - 2k^3). The math shared by techniques/pvm/ (CPU geometry, the
// per-pixel record), shaders/pvm/visibility.frag and the tests. Common GLSL/C++ subset (see
// shaders/shared/shared.h). Everything is in world space; l is the light's centre.
//
// Orientation. A silhouette loop v0 -> v1 -> v2 runs clockwise seen from the light (the occluder on
// the right of each edge): then n = (v2 - v1) x (v1 - l) points away from the occluder, d^- = l - n r
// lies on the occluder's side of the hard shadow plane and the plane through the edge and d^- bounds
// the outer penumbra, as the dissertation's Fig. 4.1 draws it. (mesh_topology.h's
// orientSilhouetteEdge runs the other way: techniques/pvm/ reverses it.) The edge maps store the
// edge in the same clockwise order, so that the visible side of the cutting plane is its positive
// half-space, as sec. 4.2 says ("the percentage of the area of the disk that is in the positive
// half-space of the cutting plane").
#ifndef SHADOWLAB_PENUMBRA_VOLUMES_GLSL
#define SHADOWLAB_PENUMBRA_VOLUMES_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif

const float PVM_PI = 3.14159265358979f;
// The sides of an edge's volume: the outer one through d^- = l - n r, the inner one through
// d^+ = l + n r (sec. 4.1.2).
const float PVM_OUTER = -1.0f;
const float PVM_INNER = 1.0f;
// Two volume planes whose normals differ by less than this angle (radians, as the sine of their
// cross product) are coincident (sec. 4.1.2's n0 == n1 case): their intersection line is then
// undefined in float, and v1's extrusion vector is (v1 - d1) / |v1 - d1| as the dissertation says.
const float PVM_COINCIDENT = 1e-4f;

// The unit normal of the plane through a and b and the point c, (b - a) x (a - c) normalized: the
// hard shadow plane of edge a -> b when c is the light centre (n_1), a penumbra volume plane when c
// is a displaced light position (n_1^-, n_1^+). Zero when the three points are collinear (an edge
// whose line passes through c): no plane.
SHARED_FN vec3 pvmPlaneNormal(vec3 a, vec3 b, vec3 c) {
    vec3 n = cross(b - a, a - c);
    float len = length(n);
    if (len <= 1e-7f * length(b - a) * length(a - c) || len == 0.0f) {
        return vec3(0.0f);
    }
    return n / len;
}

// The displaced light position of an edge whose hard shadow plane has normal n: d^- = l - n r
// (side PVM_OUTER) or d^+ = l + n r (side PVM_INNER).
SHARED_FN vec3 pvmDisplacedLight(vec3 l, vec3 n, float r, float side) {
    return l + side * r * n;
}

// The extrusion vector of silhouette vertex v1 between edges e0 = v0 -> v1 and e1 = v1 -> v2 (one
// loop, clockwise seen from the light), on one side (PVM_OUTER: v^-, PVM_INNER: v^+), unit length
// (sec. 4.1.2):
//  - the intersection of e1's and e0's volume planes, n_1^side x n_0^side, negated when v1 lies in
//    the negative half-space of the plane through v0, v2 and l (normal (v0 - l) x (v2 - l));
//    (and the half of that line leaving the light where the rule, judged from l, disagrees with the
//    planes, which meet about the displaced positions: almost straight vertices of a large light);
//  - when the two hard shadow planes coincide (n0 == n1, within PVM_COINCIDENT), (v1 - d1) / |v1 - d1|.
// A vertex with one edge (the end of an open silhouette chain: pass v0 = v1 or v2 = v1) and a vertex
// whose other edge's line passes through the light (no plane) extrude along the one plane that
// exists, as in the coincident case; with neither, along v1 - l. When v0, v2 and l are collinear the
// half-space rule cannot decide, and the vector pointing away from the light is taken.
SHARED_FN vec3 pvmExtrusion(vec3 v0, vec3 v1, vec3 v2, vec3 l, float r, float side) {
    vec3 n0 = pvmPlaneNormal(v0, v1, l);
    vec3 n1 = pvmPlaneNormal(v1, v2, l);
    bool has0 = dot(n0, n0) > 0.0f;
    bool has1 = dot(n1, n1) > 0.0f;
    if (!has0 && !has1) {
        return normalize(v1 - l);
    }
    if (!has1) {
        return normalize(v1 - pvmDisplacedLight(l, n0, r, side));
    }
    if (!has0) {
        return normalize(v1 - pvmDisplacedLight(l, n1, r, side));
    }
    vec3 d0 = pvmDisplacedLight(l, n0, r, side);
    vec3 d1 = pvmDisplacedLight(l, n1, r, side);
    vec3 m0 = pvmPlaneNormal(v0, v1, d0);
    vec3 m1 = pvmPlaneNormal(v1, v2, d1);
    vec3 x = cross(m1, m0);
    float len = length(x);
    if (length(cross(n1, n0)) < PVM_COINCIDENT || len < PVM_COINCIDENT) {
        return normalize(v1 - d1);
    }
    x = x / len;
    vec3 h = cross(v0 - l, v2 - l);
    float side012 = dot(h, v1 - l);
    if (abs(side012) <= 1e-6f * length(h) * length(v1 - l)) {
        return dot(x, v1 - l) < 0.0f ? -x : x;  // the rule cannot decide: away from the light
    }
    x = side012 < 0.0f ? -x : x;
    // The rule judges v1's turn as seen from l, but the two planes meet about d0 and d1: at a vertex
    // that is almost straight seen from l (the turn smaller than about r / |v1 - l|) the turn seen from
    // the displaced positions can be the other one, and the rule would extrude towards the light. The
    // line is right, its sign is not: keep the half that leaves the light (README.md).
    return dot(x, v1 - l) < 0.0f ? -x : x;
}

// How far from the light centre, in light radii, the line of a vertex's extrusion vector may pass
// for the two edges at the vertex to share it (pvmEdgeEndExtrusion).
const float PVM_MAX_LINE_DISTANCE = 2.0f;

// The extrusion vector of one end of an edge: v1's shared vector (pvmExtrusion), or the edge's own
// where the shared one's line passes farther than PVM_MAX_LINE_DISTANCE r from the light centre.
// `ownEdge` names the edge asking: 0 for e0 = v0 -> v1 (v1 is its second end), 1 for e1 = v1 -> v2.
// The two planes meet in a line that passes at about r / sin(theta / 2) from l, theta the corner's
// angle seen from the light (r sqrt 2 at a right angle). Where a silhouette edge points almost at
// the light (the short side of a thin plate seen from above) the corner is a spike, theta almost
// 0, and the line runs almost parallel to the floor: both edges' volumes sweep a streak across it,
// where each long edge's cutting plane (through its infinite line, sec. 4.2) darkens the floor
// far beyond the edge's end (random:7002 in the README). There, each edge ends its volume in its own
// plane instead, along the ray from its displaced light through v1 (as the dissertation's n0 == n1
// rule does): its volume stays planar and ends at v1's penumbra cone, and the two volumes leave a
// gap between them where the shadow-map test decides.
SHARED_FN vec3 pvmEdgeEndExtrusion(vec3 v0, vec3 v1, vec3 v2, vec3 l, float r, float side, float ownEdge) {
    vec3 x = pvmExtrusion(v0, v1, v2, l, r, side);
    float lineDistance = length(cross(l - v1, x));
    vec3 own = ownEdge < 0.5f ? pvmPlaneNormal(v0, v1, l) : pvmPlaneNormal(v1, v2, l);
    if (lineDistance <= PVM_MAX_LINE_DISTANCE * r || dot(own, own) == 0.0f) {
        return x;
    }
    return normalize(v1 - pvmDisplacedLight(l, own, r, side));
}

// The cutting plane through the edge h0 -> h1 (clockwise seen from the light, as the edge maps store
// it) and the point p (sec. 4.2): (n, d) with n = (h1 - h0) x (p - h0) / |...| and d = -n . h0, so
// that n . x + d is the signed distance of x. Zero when p lies on the edge's line.
SHARED_FN vec4 pvmCuttingPlane(vec3 h0, vec3 h1, vec3 p) {
    vec3 n = cross(h1 - h0, p - h0);
    float len = length(n);
    if (len <= 1e-7f * length(h1 - h0) * length(p - h0) || len == 0.0f) {
        return vec4(0.0f);
    }
    n = n / len;
    return vec4(n, -dot(n, h0));
}

// The fraction k of the disk of radius r centred at the light, perpendicular to the cutting plane,
// that lies in the plane's positive (visible) half-space, s being the signed distance of the light
// centre from the plane (eq. 4.1-4.2). The dissertation's segment area a = acos(s / r) r^2 / 2 -
// s sqrt(r^2 - s^2) / 2 is the part beyond the chord seen from a centre at distance s; the centre is
// on the visible side when s > 0, so the visible part is k = 2 a(-s) / (pi r^2) (README.md). A light
// of radius 0 is a point: 1 in front, 0 behind, 1/2 on the plane.
SHARED_FN float pvmDiskFraction(float s, float r) {
    if (r <= 0.0f) {
        return s > 0.0f ? 1.0f : (s < 0.0f ? 0.0f : 0.5f);
    }
    float q = clamp(-s / r, -1.0f, 1.0f);
    float a = 0.5f * r * r * (acos(q) - q * sqrt(max(1.0f - q * q, 0.0f)));  // eq. 4.1 at distance -s
    return clamp(2.0f * a / (PVM_PI * r * r), 0.0f, 1.0f);                    // eq. 4.2
}

// Parker et al. 1998's sinusoidal falloff as the dissertation models it: v = 3k^2 - 2k^3.
SHARED_FN float pvmFalloff(float k) {
    return k * k * (3.0f - 2.0f * k);
}

// The light's visibility at a point p inside the penumbra volume of edge h0 -> h1 (sec. 4.2,
// intersectLight): the cutting plane, the disk fraction k, and v = 3k^2 - 2k^3. A point on the
// edge's line (no cutting plane) sees half of the light.
SHARED_FN float pvmVisibility(vec3 p, vec3 h0, vec3 h1, vec3 l, float r) {
    vec4 plane = pvmCuttingPlane(h0, h1, p);
    if (dot(vec3(plane), vec3(plane)) == 0.0f) {
        return pvmFalloff(0.5f);
    }
    float s = dot(vec3(plane), l) + plane.w;
    return pvmFalloff(pvmDiskFraction(s, r));
}

// The two sides kept apart (README.md, "Sides kept apart"): a receiver the light centre reaches (the
// shadow-map test lit, centreVisible 1) lies in an outer penumbra, where at least half of the light
// is visible; one the centre does not reach (0) lies in an inner penumbra, where at most half is.
// Sec. 4.2's cutting plane through one edge's infinite line can put the centre on the other side
// when the edge is not the one that bounds the receiver's shadow (a notch of a scanned mesh's
// jagged silhouette, whose outer volume reaches over the umbra of the rest of the mesh; another
// occluder's edge, Fig. 4.7): the value is then kept at 1/2, on its side, so that the error is
// never more than a hard shadow's and v stays continuous across the hard shadow's boundary, where
// both sides give 1/2.
SHARED_FN float pvmSideVisibility(float v, float centreVisible) {
    return centreVisible > 0.5f ? max(v, 0.5f) : min(v, 0.5f);
}

// The radius of the disk the volumes and the cutting plane use for a light (shape as LightShape: 1
// square, 2 disk, 3 sphere; size: a square's width w, a disk's or sphere's radius): the disk and
// sphere their radius, as the dissertation's spherical lights; a square its equal-area disk,
// r = w / sqrt(pi) (README.md).
SHARED_FN float pvmLightRadius(int shape, float size) {
    if (shape == 1) {
        return size / sqrt(PVM_PI);
    }
    return size;
}

#endif

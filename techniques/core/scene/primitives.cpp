// Primitive meshes for the scene file's object types (plane, quad, box, sphere, cylinder, disk).
// Conventions: object space, y up, centred at the origin, counter-clockwise winding seen from
// outside, so cross(b - a, c - a) points the same way as the vertex normals.
#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

#include "scene/scene.h"

namespace shadowlab {

namespace {

uint32_t addVertex(Mesh& mesh, const glm::vec3& position, const glm::vec3& normal) {
    mesh.positions.push_back(position);
    mesh.normals.push_back(normal);
    return static_cast<uint32_t>(mesh.positions.size() - 1);
}

void addTriangle(Mesh& mesh, uint32_t a, uint32_t b, uint32_t c) {
    mesh.indices.insert(mesh.indices.end(), {a, b, c});
}

// A flat rectangle centred at `centre` spanning centre ± u ± v; `normal` is the direction of
// cross(u, v), passed in because normalizing the cross product fails for tiny sizes.
void addRectangle(Mesh& mesh, const glm::vec3& centre, const glm::vec3& u, const glm::vec3& v,
                  const glm::vec3& normal) {
    const uint32_t a = addVertex(mesh, centre - u - v, normal);
    const uint32_t b = addVertex(mesh, centre + u - v, normal);
    const uint32_t c = addVertex(mesh, centre + u + v, normal);
    const uint32_t d = addVertex(mesh, centre - u + v, normal);
    addTriangle(mesh, a, b, c);
    addTriangle(mesh, a, c, d);
}

// A disk of radius r in the plane y = y0 facing +y (up) or -y, as a fan around its centre.
void addDiskFan(Mesh& mesh, float radius, float y0, bool facesUp, int segments) {
    const glm::vec3 normal(0.0f, facesUp ? 1.0f : -1.0f, 0.0f);
    const uint32_t centre = addVertex(mesh, glm::vec3(0.0f, y0, 0.0f), normal);
    const uint32_t first = static_cast<uint32_t>(mesh.positions.size());
    for (int j = 0; j < segments; ++j) {
        const float phi =
            glm::two_pi<float>() * static_cast<float>(j) / static_cast<float>(segments);
        addVertex(mesh, glm::vec3(radius * std::cos(phi), y0, radius * std::sin(phi)), normal);
    }
    for (int j = 0; j < segments; ++j) {
        const uint32_t p0 = first + static_cast<uint32_t>(j);
        const uint32_t p1 = first + static_cast<uint32_t>((j + 1) % segments);
        // phi grows from +x towards +z, so (centre, p1, p0) faces +y.
        if (facesUp) {
            addTriangle(mesh, centre, p1, p0);
        } else {
            addTriangle(mesh, centre, p0, p1);
        }
    }
}

}  // namespace

Mesh makeQuad(float sizeX, float sizeZ) {
    Mesh mesh;
    // cross(z, x) = +y.
    addRectangle(mesh, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 0.5f * sizeZ),
                 glm::vec3(0.5f * sizeX, 0.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    return mesh;
}

Mesh makeBox(const glm::vec3& size) {
    Mesh mesh;
    const glm::vec3 half = 0.5f * size;
    for (int axis = 0; axis < 3; ++axis) {
        for (float sign : {1.0f, -1.0f}) {
            // Face at sign * half[axis] along `axis`; cross(e[axis+1], e[axis+2]) = e[axis], and
            // the sign on the second in-plane axis turns the face outwards.
            glm::vec3 centre(0.0f), u(0.0f), v(0.0f), normal(0.0f);
            centre[axis] = sign * half[axis];
            u[(axis + 1) % 3] = half[(axis + 1) % 3];
            v[(axis + 2) % 3] = sign * half[(axis + 2) % 3];
            normal[axis] = sign;
            addRectangle(mesh, centre, u, v, normal);
        }
    }
    return mesh;
}

// --- Triangle counts (scene limits are checked with these before a mesh is built) ----------------

uint64_t estimateSphereTriangles(int segments) {
    // Rings of quads, two triangles each, less one at each pole.
    const uint64_t rings = static_cast<uint64_t>(std::max(2, segments / 2));
    return static_cast<uint64_t>(segments) * (2 * rings - 2);
}

uint64_t estimateCylinderTriangles(int segments) { return 4 * static_cast<uint64_t>(segments); }

uint64_t estimateDiskTriangles(int segments) { return static_cast<uint64_t>(segments); }

Mesh makeSphere(float radius, int segments) {
    Mesh mesh;
    const int rings = std::max(2, segments / 2);
    // Vertex grid: ring i at polar angle theta = pi i / rings (from +y), column j at azimuth phi.
    for (int i = 0; i <= rings; ++i) {
        const float theta = glm::pi<float>() * static_cast<float>(i) / static_cast<float>(rings);
        for (int j = 0; j <= segments; ++j) {
            const float phi = glm::two_pi<float>() * static_cast<float>(j % segments) /
                              static_cast<float>(segments);
            const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                              std::sin(theta) * std::sin(phi));
            addVertex(mesh, radius * n, n);
        }
    }
    const auto at = [segments](int i, int j) {
        return static_cast<uint32_t>(i * (segments + 1) + j);
    };
    for (int i = 0; i < rings; ++i) {
        for (int j = 0; j < segments; ++j) {
            const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            // The top ring's a and d are both the north pole, the bottom ring's b and c the south
            // pole: skip the zero-area triangle there.
            if (i != rings - 1) addTriangle(mesh, a, c, b);
            if (i != 0) addTriangle(mesh, a, d, c);
        }
    }
    return mesh;
}

Mesh makeCylinder(float radius, float height, int segments) {
    Mesh mesh;
    const float y0 = -0.5f * height, y1 = 0.5f * height;
    for (int j = 0; j <= segments; ++j) {
        const float phi = glm::two_pi<float>() * static_cast<float>(j % segments) /
                          static_cast<float>(segments);
        const glm::vec3 n(std::cos(phi), 0.0f, std::sin(phi));
        addVertex(mesh, glm::vec3(radius * n.x, y0, radius * n.z), n);
        addVertex(mesh, glm::vec3(radius * n.x, y1, radius * n.z), n);
    }
    for (int j = 0; j < segments; ++j) {
        const uint32_t a = static_cast<uint32_t>(2 * j), d = a + 1;  // bottom, top at phi_j
        const uint32_t b = a + 2, c = a + 3;                         // bottom, top at phi_j+1
        addTriangle(mesh, a, d, c);
        addTriangle(mesh, a, c, b);
    }
    addDiskFan(mesh, radius, y1, true, segments);
    addDiskFan(mesh, radius, y0, false, segments);
    return mesh;
}

Mesh makeDisk(float radius, int segments) {
    Mesh mesh;
    addDiskFan(mesh, radius, 0.0f, true, segments);
    return mesh;
}

void computeSmoothNormals(Mesh& mesh) {
    mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
        // The unnormalized cross product weights each face by twice its area.
        const glm::vec3 n = glm::cross(mesh.positions[i1] - mesh.positions[i0],
                                       mesh.positions[i2] - mesh.positions[i0]);
        mesh.normals[i0] += n;
        mesh.normals[i1] += n;
        mesh.normals[i2] += n;
    }
    for (glm::vec3& n : mesh.normals) {
        const float len = glm::length(n);
        // A vertex used only by zero-area triangles (or none) gets an arbitrary unit normal.
        n = (len > 0.0f && std::isfinite(len)) ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
    }
}

void appendMesh(Mesh& mesh, const Mesh& part, const glm::mat4& dstFromPart) {
    const uint32_t base = static_cast<uint32_t>(mesh.positions.size());
    const glm::mat3 linear(dstFromPart);
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(linear));
    for (size_t i = 0; i < part.positions.size(); ++i) {
        mesh.positions.push_back(glm::vec3(dstFromPart * glm::vec4(part.positions[i], 1.0f)));
        const glm::vec3 n = i < part.normals.size() ? normalMatrix * part.normals[i] : glm::vec3(0);
        const float len = glm::length(n);
        mesh.normals.push_back(len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f));
    }
    const bool mirrors = glm::determinant(linear) < 0.0f;
    for (size_t t = 0; t + 2 < part.indices.size(); t += 3) {
        const uint32_t a = base + part.indices[t], b = base + part.indices[t + 1],
                       c = base + part.indices[t + 2];
        if (mirrors) {
            mesh.indices.insert(mesh.indices.end(), {a, c, b});
        } else {
            mesh.indices.insert(mesh.indices.end(), {a, b, c});
        }
    }
}

}  // namespace shadowlab

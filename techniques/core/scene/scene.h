// Scenes: a camera, lights and objects (triangle meshes with id and albedo), loaded from JSON scene
// files (assets/scenes/, schema in assets/scenes/README.md). Errors name the file and the field.
#pragma once
#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace shadowlab {

// A triangle mesh in object space. normals has one entry per position (flat or smooth).
struct Mesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<uint32_t> indices;  // 3 per triangle
    size_t triangleCount() const { return indices.size() / 3; }
};

// How an object moves over time t (seconds). The frame at index i is rendered at t = i / 30.
struct Motion {
    enum class Type { None, Rotate, Keyframes };
    Type type = Type::None;
    // Rotate: about `axis` through `pivot`, degreesPerSecond.
    glm::vec3 axis{0, 1, 0};
    glm::vec3 pivot{0, 0, 0};
    float degreesPerSecond = 0.0f;
    // Keyframes: piecewise-linear translation added to the object's transform; loops.
    struct Key {
        float time;
        glm::vec3 translate;
    };
    std::vector<Key> keys;
};

struct Object {
    std::string name;
    std::string source;          // "box", "sphere", ..., "gltf:<path>", "generator:plant"
    int id = 0;                  // object id written to the id buffer; unique, >= 0
    Mesh mesh;                   // object space
    glm::mat4 worldFromObject{1.0f};  // at t = 0
    glm::vec3 albedo{0.8f};
    bool castsShadows = true;
    bool receivesShadows = true;
    Motion motion;

    bool moves() const { return motion.type != Motion::Type::None; }
    glm::mat4 worldFromObjectAt(double t) const;
};

enum class LightShape { Point, Square, Disk, Sphere };
const char* lightShapeName(LightShape shape);

struct Light {
    std::string name;
    LightShape shape = LightShape::Square;
    glm::vec3 position{0, 4, 0};
    glm::vec3 direction{0, -1, 0};  // unit, the way the light faces (the normal of its plane)
    glm::vec3 up{0, 0, -1};         // unit, in the light plane: second axis of the square
    float size = 1.0f;              // square: width w_l; disk/sphere: radius r; point: 0
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    bool castsShadows = true;
    std::string technique;          // default technique id for this light ("" = the command's)

    // First axis of the light plane: right = normalize(cross(direction, up)) (so (right, up,
    // -direction) is right-handed). A square light covers position + (u-0.5) w right + (v-0.5) w up.
    glm::vec3 right() const;
    bool isPoint() const { return shape == LightShape::Point || size <= 0.0f; }
};

struct Camera {
    glm::vec3 position{0, 5, 7};
    glm::vec3 target{0, 0, 0};
    glm::vec3 up{0, 1, 0};
    float fovYDegrees = 45.0f;
    float nearPlane = 0.1f;
    float farPlane = 100.0f;

    glm::mat4 viewFromWorld() const;
    glm::mat4 clipFromView(float aspect) const;
};

struct Bounds {
    glm::vec3 lo{1e30f};
    glm::vec3 hi{-1e30f};
    bool empty() const { return lo.x > hi.x; }
    void extend(const glm::vec3& p) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
};

struct Scene {
    std::string name;
    std::string description;
    std::string path;  // the file it came from
    Camera camera;
    float ambient = 0.15f;
    std::vector<Light> lights;
    std::vector<Object> objects;
    // Things the loader accepted but the user should know (e.g. a skinned glTF drawn in its rest
    // pose). The command line prints them as "shadowlab: warning: ...".
    std::vector<std::string> warnings;

    bool hasMotion() const;
    // World-space bounds of all objects at time t (of casters only when castersOnly).
    Bounds bounds(double t, bool castersOnly = false) const;
};

// How much geometry a scene may ask for. Every object's triangle count is known before its mesh is
// built (primitives and generators by formula, glTF from its accessors and node tree), so a scene
// over the limit is refused with exit code 2 before anything is allocated, saying what it would
// have needed. The default, 10 million triangles, is about 3 GB at kBytesPerTriangle; the command
// line's --max-triangles N changes it (docs/robustness.md).
struct SceneLimits {
    uint64_t maxTriangles = 10'000'000;
};
// Memory one triangle costs, as an estimate for messages and limits: its share of the CPU mesh
// (positions, normals, indices), the GPU copy and the ray tracer's BVH. Measured as peak resident
// memory on `complex` with 1.2 million triangles: 239 B with `hard`, 287 B with `raytraced`
// (docs/robustness.md).
constexpr uint64_t kBytesPerTriangle = 300;
// "2.1 GB", "350 MB", "12 KB": a byte count for messages.
std::string describeBytes(double bytes);

// Triangle counts of the primitives and generators below, exactly what they build.
uint64_t estimateSphereTriangles(int segments);
uint64_t estimateCylinderTriangles(int segments);
uint64_t estimateDiskTriangles(int segments);
struct PlantParams;
struct ComplexParams;
uint64_t estimatePlantTriangles(const PlantParams& params);
uint64_t estimateComplexTriangles(const ComplexParams& params);

// "square-occluder" -> <root>/assets/scenes/square-occluder.json; anything with a '/' or ending in
// ".json" is a path. Throws InputError when the file does not exist or is not a regular file.
std::string resolveScenePath(const std::string& nameOrPath);
// Loads and validates a scene file. Every error is an InputError naming the file and the field
// and its line (JSON syntax errors: line and column). Scenes over `limits` are refused before their
// meshes are built. A .gltf or .glb path is a scene around that one model (sceneAroundGltf), so
// every command opens what the window opens.
Scene loadScene(const std::string& nameOrPath, const SceneLimits& limits = {});
// A scene around one glTF file: the mesh scaled to 2 world units on a ground quad, a square light
// above it, the camera looking at it from the front.
Scene sceneAroundGltf(const std::string& path, const SceneLimits& limits = {});
// Names of the scenes in assets/scenes/ (without .json), sorted.
std::vector<std::string> listScenes();
// World-space triangles of every object at time t, one OBJ group per object ("o <name>").
void writeTrianglesOBJ(const Scene& scene, double t, const std::string& path);

// --- Building blocks of the loader, public so that tools and tests can use them directly. -------

// Primitive meshes in object space, as the scene file's object types build them. Flat faces carry
// their face normal; curved surfaces carry the analytic normal. All are wound counter-clockwise
// seen from outside. Arguments must already be valid (sizes > 0, 3 <= segments <= 1024).
Mesh makeQuad(float sizeX, float sizeZ);                   // xz plane, centred, normal +y
Mesh makeBox(const glm::vec3& size);                       // closed, centred, 12 triangles
Mesh makeSphere(float radius, int segments);               // UV sphere, segments around y
Mesh makeCylinder(float radius, float height, int segments);  // axis y, centred, capped
Mesh makeDisk(float radius, int segments);                 // xz plane, normal +y
// Appends `part` to `mesh`, transformed by dstFromPart (normals by its inverse transpose; the
// winding is flipped when the transform mirrors, so faces keep pointing outwards).
void appendMesh(Mesh& mesh, const Mesh& part, const glm::mat4& dstFromPart);
// Area-weighted smooth vertex normals (for meshes that come without normals).
void computeSmoothNormals(Mesh& mesh);

// Procedural generators: the same seed gives the same mesh on every platform (own PRNG).
struct PlantParams {
    int leaves = 300;      // 1..20000
    float height = 1.5f;   // world units, 0.001..1000
    float spread = 0.8f;   // radius of the foliage, world units, 0.001..1000
};
Mesh generatePlant(uint64_t seed, const PlantParams& params);
struct ComplexParams {
    int count = 200;       // number of boxes, 1..100000
    float extent = 3.0f;   // boxes lie in [-extent, extent]^2 in xz, 0.001..10000
    float height = 2.0f;   // and in [0, height] in y, 0.001..10000
};
Mesh generateComplex(uint64_t seed, const ComplexParams& params);

// All triangle meshes of a .gltf or .glb file (default scene, node transforms applied) merged into
// one mesh. Throws InputError naming the glTF file when it cannot be read, is not triangles, breaks
// the node-tree rules of glTF 2.0 (a node with two parents, a cycle), needs an extension shadowlab
// does not support (Draco, meshopt) or would exceed `limits` (counted before any vertex is read).
// Skins and morph targets are ignored (the rest pose is drawn) with a message in `warnings`.
Mesh loadGltfMesh(const std::string& path, const SceneLimits& limits = {},
                  std::vector<std::string>* warnings = nullptr);
// The triangle count loadGltfMesh would produce, from the node tree and accessor counts only (the
// same checks, no vertex read).
uint64_t estimateGltfTriangles(const std::string& path);

// "random:SEED": a generated scene (random_scene.cpp): 1 to 5 casters (boxes, spheres, cylinders,
// thin plates; half touching the ground) over a ground quad, one square, disk or sphere light and a
// camera, all drawn from SEED. loadScene accepts the name; the same seed gives the same scene.
// "random:SEED:mesh=NAME" adds the real mesh NAME (realMeshNames) as one more caster at a position,
// turn and scale drawn from SEED; the rest of the scene is random:SEED's.
bool isRandomSceneName(const std::string& name);
// InputError when SEED is not a whole number, an option is not mesh=NAME, NAME is not a real mesh,
// or its file is missing (scripts/fetch-meshes.sh makes them).
Scene randomScene(const std::string& name, const SceneLimits& limits = {});
// The real-mesh test set (assets/models/README.md): its names, sorted, as scripts/fetch-meshes.sh
// lists them, and the glTF file each becomes: <root>/assets/models/real/<name>.gltf.
const std::vector<std::string>& realMeshNames();
std::string realMeshPath(const std::string& name);

// Project root (holding assets/ and shaders/): $SHADOWLAB_ROOT if set, else the source directory
// the binary was built from.
std::string projectRoot();

}  // namespace shadowlab

// Scene module: the shipped scenes, primitives, generators, glTF, motion, and bad input (every
// error must name the file and the field, or the line and column).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "error.h"
#include "scene/scene.h"
#include "support/real_meshes.h"

namespace shadowlab {
namespace {

namespace fs = std::filesystem;

// --- helpers ------------------------------------------------------------------------------------

fs::path scratchDir() {
    const fs::path dir = fs::path(SHADOWLAB_TEST_TMP) / "scene";
    fs::create_directories(dir);
    return dir;
}

std::string writeFile(const std::string& name, const std::string& content) {
    const fs::path path = scratchDir() / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << content;
    return path.string();
}

// A minimal valid scene around the given objects (JSON array body).
std::string sceneWith(const std::string& objects, const std::string& lights = "") {
    return R"({
  "camera": {"position": [0, 5, 5], "target": [0, 0, 0]},
  "lights": [)" +
           (lights.empty() ? std::string(R"({"type": "square", "position": [0, 4, 0], "width": 1})")
                           : lights) +
           R"(],
  "objects": [)" +
           objects + "]\n}\n";
}

// Runs `f`, expects an InputError, and returns its message.
std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
        return "";
    }
    ADD_FAILURE() << "expected InputError, nothing was thrown";
    return "";
}

// Loads `content` written to `name` and expects an error that contains every one of `parts`.
std::string expectLoadError(const std::string& name, const std::string& content,
                            const std::vector<std::string>& parts) {
    const std::string path = writeFile(name, content);
    const std::string message = errorOf([&] { loadScene(path); });
    EXPECT_NE(message.find(path), std::string::npos)
        << "message does not name the file: " << message;
    for (const std::string& part : parts) {
        EXPECT_NE(message.find(part), std::string::npos)
            << "message lacks \"" << part << "\": " << message;
    }
    return message;
}

Bounds worldBounds(const Object& object, double t = 0.0) {
    Bounds b;
    const glm::mat4 m = object.worldFromObjectAt(t);
    for (const glm::vec3& p : object.mesh.positions) b.extend(glm::vec3(m * glm::vec4(p, 1.0f)));
    return b;
}

const Object& objectNamed(const Scene& scene, const std::string& name) {
    for (const Object& o : scene.objects) {
        if (o.name == name) return o;
    }
    throw std::runtime_error("no object " + name);
}

// Structural checks every mesh must pass: indices in range, one unit normal per position, finite
// positions, and counter-clockwise winding agreeing with the normals (face normal . vertex normal
// > 0 for non-degenerate triangles).
// windingAgrees: every triangle wound like its vertices' normals. Not so on the real meshes
// (assets/models/README.md): smooth normals across inconsistent winding and non-manifold edges.
void expectWellFormed(const Mesh& mesh, const std::string& what, bool windingAgrees = true) {
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size()) << what;
    ASSERT_EQ(mesh.indices.size() % 3, 0u) << what;
    ASSERT_GT(mesh.triangleCount(), 0u) << what;
    for (uint32_t i : mesh.indices) ASSERT_LT(i, mesh.positions.size()) << what;
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        const glm::vec3& p = mesh.positions[i];
        ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) << what;
        ASSERT_NEAR(glm::length(mesh.normals[i]), 1.0f, 1e-4f) << what << " vertex " << i;
    }
    size_t disagreeing = 0;
    for (size_t t = 0; t < mesh.indices.size(); t += 3) {
        const glm::vec3 a = mesh.positions[mesh.indices[t]],
                        b = mesh.positions[mesh.indices[t + 1]],
                        c = mesh.positions[mesh.indices[t + 2]];
        const glm::vec3 n = glm::cross(b - a, c - a);
        if (glm::length(n) < 1e-12f) continue;
        for (int k = 0; k < 3; ++k) {
            if (glm::dot(n, mesh.normals[mesh.indices[t + k]]) <= 0.0f) ++disagreeing;
        }
    }
    if (windingAgrees) EXPECT_EQ(disagreeing, 0u) << what << ": triangles wound against their normals";
}

// Every edge of a closed mesh (vertices welded by position) belongs to exactly two triangles.
bool isClosed(const Mesh& mesh) {
    const auto key = [](const glm::vec3& p) {
        return std::make_tuple(std::lround(p.x * 1e5f), std::lround(p.y * 1e5f),
                               std::lround(p.z * 1e5f));
    };
    using Key = decltype(key(glm::vec3()));
    std::map<std::pair<Key, Key>, int> edges;
    for (size_t t = 0; t < mesh.indices.size(); t += 3) {
        for (int k = 0; k < 3; ++k) {
            Key a = key(mesh.positions[mesh.indices[t + k]]);
            Key b = key(mesh.positions[mesh.indices[t + (k + 1) % 3]]);
            if (b < a) std::swap(a, b);
            ++edges[{a, b}];
        }
    }
    return std::all_of(edges.begin(), edges.end(), [](const auto& e) { return e.second == 2; });
}

// --- the shipped scenes -------------------------------------------------------------------------

TEST(Scenes, AllOfDesignSection5ExistAndLoad) {
    const std::vector<std::string> names = testing::loadableScenes();
    EXPECT_GE(names.size(), 9u);
    EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
    for (const char* required :
         {"square-occluder", "overlapping-occluders", "cube-popping", "plant", "contact", "grazing",
          "depth-discontinuities", "sphere-light", "complex"}) {
        EXPECT_NE(std::find(names.begin(), names.end(), required), names.end()) << required;
    }
    for (const std::string& name : names) {
        SCOPED_TRACE(name);
        const Scene scene = loadScene(name);
        EXPECT_EQ(scene.name, name);
        EXPECT_FALSE(scene.description.empty());
        EXPECT_GE(scene.lights.size(), 1u);
        EXPECT_GE(scene.objects.size(), 1u);
        std::set<int> ids;
        for (const Object& o : scene.objects) {
            expectWellFormed(o.mesh, name + "/" + o.name, !testing::isRealMeshObject(o));
            EXPECT_TRUE(ids.insert(o.id).second) << "duplicate id " << o.id;
        }
        for (const Light& l : scene.lights) {
            EXPECT_NEAR(glm::length(l.direction), 1.0f, 1e-5f);
            EXPECT_NEAR(glm::length(l.up), 1.0f, 1e-5f);
            EXPECT_NEAR(glm::dot(l.direction, l.up), 0.0f, 1e-5f);
            // Lights face down-ish so that a shadow frustum from the light covers the scene.
            EXPECT_LT(l.direction.y, -0.3f) << l.name;
            EXPECT_TRUE(std::isfinite(l.size) && l.size >= 0.0f);
        }
        // Every scene has at least one shadow-casting light and one caster.
        EXPECT_TRUE(std::any_of(scene.lights.begin(), scene.lights.end(),
                                [](const Light& l) { return l.castsShadows; }));
        EXPECT_FALSE(scene.bounds(0.0, true).empty());
    }
}

TEST(Scenes, SpecificFeatures) {
    const Scene depth = loadScene("depth-discontinuities");
    ASSERT_EQ(depth.lights.size(), 2u);
    EXPECT_EQ(depth.lights[1].shape, LightShape::Point);
    EXPECT_TRUE(depth.lights[1].isPoint());
    EXPECT_EQ(depth.lights[1].size, 0.0f);
    EXPECT_FALSE(depth.lights[1].castsShadows);

    const Scene complex = loadScene("complex");
    ASSERT_EQ(complex.lights.size(), 2u);
    EXPECT_TRUE(complex.lights[0].castsShadows && complex.lights[1].castsShadows);
    EXPECT_EQ(objectNamed(complex, "boxes").mesh.triangleCount(), 200u * 12u);

    const Scene sphere = loadScene("sphere-light");
    EXPECT_EQ(sphere.lights[0].shape, LightShape::Sphere);
    EXPECT_FLOAT_EQ(sphere.lights[0].size, 0.5f);

    const Scene popping = loadScene("cube-popping");
    EXPECT_TRUE(popping.hasMotion());
    EXPECT_GE(popping.lights[0].size, 1.5f);
    EXPECT_FALSE(loadScene("square-occluder").hasMotion());

    const Scene plant = loadScene("plant");
    EXPECT_EQ(objectNamed(plant, "plant").source, "generator:plant");
    EXPECT_GE(objectNamed(plant, "plant").mesh.triangleCount(), 600u);

    // contact: the box rests on the floor, the ball and the glTF torus touch it.
    const Scene contact = loadScene("contact");
    EXPECT_NEAR(worldBounds(objectNamed(contact, "box")).lo.y, 0.0f, 1e-5f);
    EXPECT_NEAR(worldBounds(objectNamed(contact, "ball")).lo.y, 0.0f, 1e-5f);
    const Object& torus = objectNamed(contact, "torus");
    EXPECT_EQ(torus.source, "gltf:../models/torus.gltf");
    EXPECT_EQ(torus.mesh.triangleCount(), 480u);
    EXPECT_NEAR(worldBounds(torus).lo.y, 0.0f, 1e-3f);
}

// DESIGN.md section 5, exactly.
TEST(SquareOccluder, GeometryIsExactlyAsSpecified) {
    const Scene scene = loadScene("square-occluder");
    ASSERT_EQ(scene.lights.size(), 1u);
    const Light& light = scene.lights[0];
    EXPECT_EQ(light.shape, LightShape::Square);
    EXPECT_EQ(light.position, glm::vec3(0, 4, 0));
    EXPECT_EQ(light.direction, glm::vec3(0, -1, 0));
    EXPECT_FLOAT_EQ(light.size, 1.0f);
    EXPECT_TRUE(light.castsShadows);
    // (right, up, -direction) is right-handed.
    EXPECT_NEAR(glm::dot(glm::cross(light.right(), light.up), -light.direction), 1.0f, 1e-6f);

    ASSERT_EQ(scene.objects.size(), 2u);
    const Object& floor = objectNamed(scene, "floor");
    const Object& occluder = objectNamed(scene, "occluder");
    EXPECT_EQ(floor.id, 0);
    EXPECT_EQ(occluder.id, 1);
    EXPECT_TRUE(floor.receivesShadows);
    EXPECT_TRUE(occluder.castsShadows);
    EXPECT_FALSE(floor.moves());
    EXPECT_FALSE(occluder.moves());

    const Bounds f = worldBounds(floor);
    EXPECT_EQ(f.lo, glm::vec3(-4, 0, -4));
    EXPECT_EQ(f.hi, glm::vec3(4, 0, 4));
    for (const glm::vec3& n : floor.mesh.normals) EXPECT_EQ(n, glm::vec3(0, 1, 0));

    const Bounds o = worldBounds(occluder);
    EXPECT_NEAR(o.lo.x, -0.5f, 1e-6f);
    EXPECT_NEAR(o.hi.x, 0.5f, 1e-6f);
    EXPECT_NEAR(o.lo.z, -0.5f, 1e-6f);
    EXPECT_NEAR(o.hi.z, 0.5f, 1e-6f);
    EXPECT_NEAR(o.lo.y, 2.0f - 0.0005f, 1e-6f);
    EXPECT_NEAR(o.hi.y, 2.0f + 0.0005f, 1e-6f);
    EXPECT_EQ(occluder.mesh.triangleCount(), 12u);
    EXPECT_TRUE(isClosed(occluder.mesh));

    // Scene bounds: everything, and casters only (the floor does not cast).
    const Bounds all = scene.bounds(0.0);
    EXPECT_EQ(all.lo, glm::vec3(-4.0f, 0.0f, -4.0f));
    EXPECT_NEAR(all.hi.y, 2.0005f, 1e-6f);
    const Bounds casters = scene.bounds(0.0, true);
    EXPECT_NEAR(casters.lo.x, -0.5f, 1e-6f);
    EXPECT_NEAR(casters.lo.y, 1.9995f, 1e-6f);
}

TEST(SquareOccluder, CameraSeesTheWholeRegionUnobstructed) {
    const Scene scene = loadScene("square-occluder");
    const Bounds occluder = worldBounds(objectNamed(scene, "occluder"));
    for (float aspect : {1.0f, 4.0f / 3.0f, 16.0f / 9.0f}) {
        SCOPED_TRACE(aspect);
        const glm::mat4 clipFromWorld =
            scene.camera.clipFromView(aspect) * scene.camera.viewFromWorld();
        glm::vec2 lo(1e9f), hi(-1e9f);
        for (float x : {-2.0f, 2.0f}) {
            for (float z : {-2.0f, 2.0f}) {
                const glm::vec4 clip = clipFromWorld * glm::vec4(x, 0.0f, z, 1.0f);
                ASSERT_GT(clip.w, 0.0f);
                const glm::vec3 ndc = glm::vec3(clip) / clip.w;
                EXPECT_LT(std::abs(ndc.x), 0.95f) << x << "," << z;
                EXPECT_LT(std::abs(ndc.y), 0.95f) << x << "," << z;
                EXPECT_GT(ndc.z, -1.0f);
                EXPECT_LT(ndc.z, 1.0f);
                lo = glm::min(lo, glm::vec2(ndc));
                hi = glm::max(hi, glm::vec2(ndc));
            }
        }
        // Enough resolution: the region spans a good part of the image both ways.
        EXPECT_GT(hi.x - lo.x, 0.8f);
        EXPECT_GT(hi.y - lo.y, 0.6f);
    }
    // Rays from the camera to floor points in [-2, 2]^2 miss the occluder (slab test).
    int hidden = 0, total = 0;
    for (int i = 0; i <= 40; ++i) {
        for (int j = 0; j <= 40; ++j) {
            const glm::vec3 p(-2.0f + 0.1f * static_cast<float>(i), 0.0f,
                              -2.0f + 0.1f * static_cast<float>(j));
            const glm::vec3 o = scene.camera.position, d = p - o;
            float t0 = 0.0f, t1 = 1.0f;
            for (int k = 0; k < 3; ++k) {
                const float ta = (occluder.lo[k] - o[k]) / d[k],
                            tb = (occluder.hi[k] - o[k]) / d[k];
                t0 = std::max(t0, std::min(ta, tb));
                t1 = std::min(t1, std::max(ta, tb));
            }
            hidden += t0 <= t1 ? 1 : 0;
            ++total;
        }
    }
    EXPECT_LT(static_cast<double>(hidden) / total, 0.02);
}

// --- primitives
// -----------------------------------------------------------------------------------

TEST(Primitives, BoxIsClosedWithTwelveTriangles) {
    const Mesh box = makeBox(glm::vec3(1.0f, 2.0f, 3.0f));
    EXPECT_EQ(box.triangleCount(), 12u);
    expectWellFormed(box, "box");
    EXPECT_TRUE(isClosed(box));
    Bounds b;
    for (const glm::vec3& p : box.positions) b.extend(p);
    EXPECT_EQ(b.lo, glm::vec3(-0.5f, -1.0f, -1.5f));
    EXPECT_EQ(b.hi, glm::vec3(0.5f, 1.0f, 1.5f));
    // Flat normals: each is an axis direction.
    for (const glm::vec3& n : box.normals) {
        EXPECT_FLOAT_EQ(std::abs(n.x) + std::abs(n.y) + std::abs(n.z), 1.0f);
    }
}

TEST(Primitives, SphereVerticesLieOnTheSphere) {
    const Mesh sphere = makeSphere(0.75f, 24);
    expectWellFormed(sphere, "sphere");
    EXPECT_TRUE(isClosed(sphere));
    for (size_t i = 0; i < sphere.positions.size(); ++i) {
        EXPECT_NEAR(glm::length(sphere.positions[i]), 0.75f, 1e-5f);
        EXPECT_NEAR(glm::dot(sphere.normals[i], sphere.positions[i] / 0.75f), 1.0f, 1e-5f);
    }
}

TEST(Primitives, CylinderDiskQuad) {
    const Mesh cylinder = makeCylinder(0.5f, 2.0f, 16);
    expectWellFormed(cylinder, "cylinder");
    EXPECT_TRUE(isClosed(cylinder));
    EXPECT_EQ(cylinder.triangleCount(), 16u * 4u);
    Bounds b;
    for (const glm::vec3& p : cylinder.positions) b.extend(p);
    EXPECT_NEAR(b.lo.y, -1.0f, 1e-6f);
    EXPECT_NEAR(b.hi.y, 1.0f, 1e-6f);
    EXPECT_NEAR(b.hi.x, 0.5f, 1e-6f);

    const Mesh disk = makeDisk(1.0f, 3);
    expectWellFormed(disk, "disk");
    EXPECT_EQ(disk.triangleCount(), 3u);
    for (const glm::vec3& n : disk.normals) EXPECT_EQ(n, glm::vec3(0, 1, 0));

    const Mesh quad = makeQuad(2.0f, 4.0f);
    expectWellFormed(quad, "quad");
    EXPECT_EQ(quad.triangleCount(), 2u);
}

TEST(Primitives, SmoothNormalsAndMirroredAppend) {
    Mesh box = makeBox(glm::vec3(1.0f));
    computeSmoothNormals(box);
    expectWellFormed(box, "box with smooth normals");
    // A mirroring transform flips the winding so faces still point outwards.
    Mesh mirrored;
    appendMesh(mirrored, makeSphere(1.0f, 12),
               glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f)));
    expectWellFormed(mirrored, "mirrored sphere");
}

// --- generators
// -----------------------------------------------------------------------------------

bool sameMesh(const Mesh& a, const Mesh& b) {
    return a.positions == b.positions && a.normals == b.normals && a.indices == b.indices;
}

TEST(Generators, PlantIsDeterministicAndSeeded) {
    PlantParams params;
    params.leaves = 120;
    const Mesh a = generatePlant(42, params), b = generatePlant(42, params),
               c = generatePlant(43, params);
    expectWellFormed(a, "plant");
    EXPECT_TRUE(sameMesh(a, b));
    EXPECT_FALSE(sameMesh(a, c));
    EXPECT_GE(a.triangleCount(), 2u * 120u);
    Bounds bounds;
    for (const glm::vec3& p : a.positions) bounds.extend(p);
    EXPECT_NEAR(bounds.lo.y, 0.0f, 1e-5f);  // the pot stands on y = 0
    EXPECT_LT(bounds.hi.y, params.height * 1.5f);
    EXPECT_GT(bounds.hi.y, params.height * 0.5f);
}

TEST(Generators, ComplexIsDeterministicAndStaysInItsRegion) {
    ComplexParams params;
    params.count = 50;
    const Mesh a = generateComplex(5, params), b = generateComplex(5, params),
               c = generateComplex(6, params);
    expectWellFormed(a, "complex");
    EXPECT_TRUE(sameMesh(a, b));
    EXPECT_FALSE(sameMesh(a, c));
    EXPECT_EQ(a.triangleCount(), 50u * 12u);
    for (const glm::vec3& p : a.positions) {
        EXPECT_LE(std::abs(p.x), params.extent + 1e-4f);
        EXPECT_LE(std::abs(p.z), params.extent + 1e-4f);
        EXPECT_GE(p.y, -1e-4f);
        EXPECT_LE(p.y, params.height + 1e-4f);
    }
}

TEST(Generators, ParamsFromSceneFile) {
    const Scene scene = loadScene(writeFile("gen.json", sceneWith(R"(
      {"name": "p", "type": "generator", "generator": "plant", "seed": 9, "params": {"leaves": 10}},
      {"name": "c", "type": "generator", "generator": "complex", "seed": 9, "params": {"count": 3}},
      {"name": "d", "type": "generator", "generator": "complex"})")));
    PlantParams plant;
    plant.leaves = 10;
    EXPECT_TRUE(sameMesh(objectNamed(scene, "p").mesh, generatePlant(9, plant)));
    EXPECT_EQ(objectNamed(scene, "c").mesh.triangleCount(), 36u);
    EXPECT_EQ(objectNamed(scene, "d").mesh.triangleCount(), 200u * 12u);  // defaults
}

// --- motion and transforms
// ------------------------------------------------------------------------

glm::vec3 apply(const glm::mat4& m, const glm::vec3& p) {
    return glm::vec3(m * glm::vec4(p, 1.0f));
}

void expectNear(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

TEST(Motion, RotateAboutAPivot) {
    Object o;
    o.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0, 1, 0));
    o.motion.type = Motion::Type::Rotate;
    o.motion.axis = glm::vec3(0, 1, 0);
    o.motion.pivot = glm::vec3(1, 0, 0);
    o.motion.degreesPerSecond = 90.0f;
    EXPECT_TRUE(o.moves());
    expectNear(apply(o.worldFromObjectAt(0.0), glm::vec3(2, 0, 0)), glm::vec3(2, 1, 0));
    // After 1 s: 90 degrees about +y through (1, 0, 0): (2, 1, 0) -> (1, 1, -1).
    expectNear(apply(o.worldFromObjectAt(1.0), glm::vec3(2, 0, 0)), glm::vec3(1, 1, -1));
    expectNear(apply(o.worldFromObjectAt(2.0), glm::vec3(2, 0, 0)), glm::vec3(0, 1, 0));
    // A full turn later, back where it started (and no precision loss at large t).
    expectNear(apply(o.worldFromObjectAt(4.0 * 1000.0 + 1.0), glm::vec3(2, 0, 0)),
               glm::vec3(1, 1, -1), 1e-4f);
}

TEST(Motion, KeyframesArePiecewiseLinearAndLoop) {
    Object o;
    o.worldFromObject = glm::scale(glm::mat4(1.0f), glm::vec3(2.0f));
    o.motion.type = Motion::Type::Keyframes;
    o.motion.keys = {
        {0.0f, glm::vec3(0, 0, 0)}, {1.0f, glm::vec3(2, 0, 0)}, {2.0f, glm::vec3(2, 4, 0)}};
    const glm::vec3 p(1, 0, 0);  // (2, 0, 0) after the scale
    expectNear(apply(o.worldFromObjectAt(0.0), p), glm::vec3(2, 0, 0));
    expectNear(apply(o.worldFromObjectAt(0.5), p), glm::vec3(3, 0, 0));
    expectNear(apply(o.worldFromObjectAt(1.0), p), glm::vec3(4, 0, 0));
    expectNear(apply(o.worldFromObjectAt(1.5), p), glm::vec3(4, 2, 0));
    expectNear(apply(o.worldFromObjectAt(2.5), p), glm::vec3(3, 0, 0));  // loops over 2 s
    expectNear(apply(o.worldFromObjectAt(-0.5), p), glm::vec3(4, 2, 0));
}

TEST(Motion, FromSceneFileAndTransformOrder) {
    const Scene scene = loadScene(writeFile("motion.json", sceneWith(R"(
      {"name": "spin", "type": "box", "size": [1, 1, 1],
       "motion": {"type": "rotate", "axis": [0, 2, 0], "degrees_per_second": 30}},
      {"name": "slide", "type": "box", "size": [1, 1, 1],
       "motion": {"type": "keyframes", "keys": [{"time": 0, "translate": [0, 0, 0]},
                                                {"time": 4, "translate": [4, 0, 0]}]}},
      {"name": "placed", "type": "box", "size": [1, 1, 1],
       "transform": {"translate": [10, 0, 0], "rotate_deg": [90, 90, 0], "scale": 2}})")));
    EXPECT_TRUE(scene.hasMotion());
    const Object& spin = objectNamed(scene, "spin");
    EXPECT_EQ(spin.motion.axis, glm::vec3(0, 1, 0));  // normalized
    expectNear(apply(spin.worldFromObjectAt(3.0), glm::vec3(1, 0, 0)), glm::vec3(0, 0, -1));
    const Object& slide = objectNamed(scene, "slide");
    expectNear(apply(slide.worldFromObjectAt(1.0), glm::vec3(0)), glm::vec3(1, 0, 0));
    // R = Rz * Ry * Rx: (0, 1, 0) -Rx(90)-> (0, 0, 1) -Ry(90)-> (1, 0, 0); scale 2; move +10 x.
    const Object& placed = objectNamed(scene, "placed");
    EXPECT_FALSE(placed.moves());
    expectNear(apply(placed.worldFromObjectAt(5.0), glm::vec3(0, 1, 0)), glm::vec3(12, 0, 0));
    // Bounds follow the motion.
    EXPECT_NEAR(worldBounds(slide, 2.0).hi.x - worldBounds(slide, 0.0).hi.x, 2.0f, 1e-5f);
    EXPECT_NE(scene.bounds(0.0).lo.x, scene.bounds(1.0).lo.x);
}

TEST(Lights, UpIsMadeOrthogonalAndPointLightsHaveNoSize) {
    const Scene scene = loadScene(writeFile(
        "lights.json",
        sceneWith(
            R"({"type": "box", "size": [1, 1, 1]})",
            R"({"type": "disk", "position": [0, 3, 0], "direction": [0, -2, 0], "up": [0, 1, -1], "radius": 0.3},
           {"type": "point", "position": [1, 3, 0], "direction": [0, 0, -1]},
           {"name": "s", "type": "square", "position": [0, 3, 0], "direction": [1, -1, 0], "width": 0,
            "color": [1, 0.5, 0.25], "intensity": 2, "casts_shadows": false, "technique": "pcss"})")));
    ASSERT_EQ(scene.lights.size(), 3u);
    const Light& disk = scene.lights[0];
    EXPECT_EQ(disk.shape, LightShape::Disk);
    EXPECT_EQ(disk.name, "light0");
    EXPECT_EQ(disk.direction, glm::vec3(0, -1, 0));
    expectNear(disk.up, glm::vec3(0, 0, -1));
    expectNear(disk.right(), glm::normalize(glm::cross(disk.direction, disk.up)));
    EXPECT_FLOAT_EQ(disk.size, 0.3f);
    const Light& point = scene.lights[1];
    EXPECT_EQ(point.shape, LightShape::Point);
    EXPECT_EQ(point.size, 0.0f);
    EXPECT_NEAR(glm::dot(point.up, point.direction), 0.0f, 1e-6f);  // default up was parallel
    const Light& square = scene.lights[2];
    EXPECT_TRUE(square.isPoint());  // width 0
    EXPECT_EQ(square.technique, "pcss");
    EXPECT_FALSE(square.castsShadows);
    EXPECT_EQ(square.color, glm::vec3(1, 0.5f, 0.25f));
    EXPECT_STREQ(lightShapeName(LightShape::Sphere), "sphere");
}

// --- glTF
// -----------------------------------------------------------------------------------------

std::string base64(const std::string& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const uint32_t v =
            (uint8_t(bytes[i]) << 16) | (uint8_t(bytes[i + 1]) << 8) | uint8_t(bytes[i + 2]);
        for (int s = 18; s >= 0; s -= 6) out += table[(v >> s) & 63];
    }
    if (i + 1 == bytes.size()) {
        const uint32_t v = uint8_t(bytes[i]) << 16;
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += "==";
    } else if (i + 2 == bytes.size()) {
        const uint32_t v = (uint8_t(bytes[i]) << 16) | (uint8_t(bytes[i + 1]) << 8);
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += table[(v >> 6) & 63];
        out += '=';
    }
    return out;
}

template <class T>
std::string bytesOf(const std::vector<T>& values) {
    std::string out(values.size() * sizeof(T), '\0');
    std::memcpy(out.data(), values.data(), out.size());
    return out;
}

// One triangle (positions float, indices uint8), no normals, given primitive mode; `uri` replaces
// the embedded buffer when not empty. The node translates by (0, 1, 0).
std::string triangleGltfJson(int mode, const std::string& uri = "") {
    const std::string positions = bytesOf(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 0, -1});
    const std::string indices = bytesOf(std::vector<uint8_t>{0, 1, 2, 0});
    const std::string blob = positions + indices;
    const std::string bufferUri =
        uri.empty() ? "data:application/octet-stream;base64," + base64(blob) : uri;
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
      "nodes": [{"mesh": 0, "translation": [0, 1, 0]}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": )" +
           std::to_string(mode) + R"(}]}],
      "buffers": [{"byteLength": )" +
           std::to_string(blob.size()) + R"(, "uri": ")" + bufferUri + R"("}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                      {"buffer": 0, "byteOffset": 36, "byteLength": 3}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, -1], "max": [1, 0, 0]},
                    {"bufferView": 1, "componentType": 5121, "count": 3, "type": "SCALAR"}]})";
}

TEST(Gltf, TorusModel) {
    const Mesh torus = loadGltfMesh(projectRoot() + "/assets/models/torus.gltf");
    expectWellFormed(torus, "torus");
    EXPECT_EQ(torus.triangleCount(), 480u);
    EXPECT_TRUE(isClosed(torus));
}

TEST(Gltf, GltfAndGlbWithoutNormals) {
    const Mesh fromGltf = loadGltfMesh(writeFile("triangle.gltf", triangleGltfJson(4)));
    expectWellFormed(fromGltf, "triangle.gltf");
    ASSERT_EQ(fromGltf.triangleCount(), 1u);
    expectNear(fromGltf.positions[1], glm::vec3(1, 1, 0));  // node translation applied
    expectNear(fromGltf.normals[0], glm::vec3(0, 1, 0));   // computed

    // The same model as .glb: header, JSON chunk (space-padded), BIN chunk (zero-padded).
    const std::string positions = bytesOf(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 0, -1});
    const std::string binChunk = positions + bytesOf(std::vector<uint8_t>{0, 1, 2, 0});
    std::string jsonChunk = triangleGltfJson(4);
    jsonChunk =
        jsonChunk.replace(jsonChunk.find(R"(, "uri": ")"),
                          jsonChunk.find(R"("}],)") + 1 - jsonChunk.find(R"(, "uri": ")"), "");
    while (jsonChunk.size() % 4) jsonChunk += ' ';
    const auto u32 = [](uint32_t v) { return bytesOf(std::vector<uint32_t>{v}); };
    const std::string glb = "glTF" + u32(2) +
                            u32(uint32_t(12 + 8 + jsonChunk.size() + 8 + binChunk.size())) +
                            u32(uint32_t(jsonChunk.size())) + "JSON" + jsonChunk +
                            u32(uint32_t(binChunk.size())) + std::string("BIN\0", 4) + binChunk;
    const Mesh fromGlb = loadGltfMesh(writeFile("triangle.glb", glb));
    EXPECT_EQ(fromGlb.positions, fromGltf.positions);
    EXPECT_EQ(fromGlb.indices, fromGltf.indices);
}

TEST(Gltf, NonTrianglePrimitiveIsAnError) {
    const std::string gltf = writeFile("lines.gltf", triangleGltfJson(1));
    const std::string message = errorOf([&] { loadGltfMesh(gltf); });
    EXPECT_NE(message.find(gltf), std::string::npos) << message;
    EXPECT_NE(message.find("TRIANGLES"), std::string::npos) << message;
}

TEST(Gltf, OutOfRangeIndexIsAnError) {
    std::string text = triangleGltfJson(4);
    text.replace(text.find(R"("count": 3, "type": "SCALAR")"), 10, R"("count": 4)");
    const std::string gltf = writeFile("short.gltf", text);
    const std::string message = errorOf([&] { loadGltfMesh(gltf); });
    EXPECT_NE(message.find(gltf), std::string::npos) << message;
}

// --- bad input: each names the file and the field or line ---------------------------------------

TEST(BadInput, MissingFile) {
    const std::string message = errorOf([] { loadScene("no-such-scene"); });
    EXPECT_NE(message.find("assets/scenes/no-such-scene.json: no such scene file (known scenes: "),
              std::string::npos) << message;
    EXPECT_NE(message.find("square-occluder"), std::string::npos) << message;
    const std::string path = (scratchDir() / "absent.json").string();
    EXPECT_NE(errorOf([&] { loadScene(path); }).find(path + ": no such scene file"),
              std::string::npos);
}

TEST(BadInput, MalformedJsonGivesLineAndColumn) {
    // The second comma on line 3 is at column 36.
    const std::string text =
        "{\n  \"name\": \"x\",\n  \"camera\": {\"position\": [0, 1, 2],, \"target\": [0, 0, "
        "0]}\n}\n";
    ASSERT_EQ(text.find(",,") + 1 - text.find("  \"camera\""), 35u);
    const std::string path = writeFile("malformed.json", text);
    const std::string message = errorOf([&] { loadScene(path); });
    EXPECT_EQ(message.rfind(path + ":3:36: malformed JSON: ", 0), 0u) << message;

    // Unterminated file: the error is at the end of input.
    const std::string path2 = writeFile("truncated.json", "{\n  \"name\": \"x\"");
    EXPECT_EQ(errorOf([&] { loadScene(path2); }).rfind(path2 + ":2:14: malformed JSON: ", 0), 0u)
        << errorOf([&] { loadScene(path2); });
}

TEST(BadInput, LiteralNaN) {
    const std::string path = writeFile("nan.json", "{\n  \"ambient\": NaN,\n  \"lights\": []\n}\n");
    const std::string message = errorOf([&] { loadScene(path); });
    EXPECT_EQ(message.rfind(path + ":2:14: malformed JSON: ", 0), 0u) << message;
}

TEST(BadInput, InfiniteNumber) {
    expectLoadError("inf.json",
                    sceneWith(R"({"type": "box", "size": [1, 1, 1], "albedo": [0.5, 1e999, 0.5]})"),
                    {"objects[0].albedo[1]: expected a finite number, got 1e999"});
    expectLoadError("neginf.json", sceneWith(R"({"type": "box", "size": [1, -1e999, 1]})"),
                    {"objects[0].size[1]: expected a finite number, got -1e999"});
}

TEST(BadInput, UnknownFieldAtTopLevel) {
    std::string text = sceneWith(R"({"type": "box", "size": [1, 1, 1]})");
    text.insert(1, "\"colour\": [1, 0, 0],");
    expectLoadError(
        "unknown-top.json", text,
        {": colour: expected one of the fields name, description, camera, ambient, lights, objects",
         "unknown field \"colour\""});
}

TEST(BadInput, UnknownFieldInsideAnObject) {
    expectLoadError(
        "unknown-object.json",
        sceneWith(
            R"({"type": "box", "size": [1, 1, 1]}, {"type": "sphere", "radius": 1, "colour": [1, 0, 0]})"),
        {"objects[1].colour: expected one of the fields", "albedo", "segments",
         "unknown field \"colour\""});
    // Fields of another type are unknown too, and so are fields inside nested objects.
    expectLoadError("unknown-width.json",
                    sceneWith(R"({"type": "box", "size": [1, 1, 1]})",
                              R"({"type": "disk", "position": [0, 3, 0], "width": 1})"),
                    {"lights[0].width: expected one of the fields", "radius"});
    expectLoadError(
        "unknown-nested.json",
        sceneWith(R"({"type": "box", "size": [1, 1, 1], "transform": {"rotate": [0, 1, 0]}})"),
        {"objects[0].transform.rotate: expected one of the fields translate, rotate_deg, scale"});
    expectLoadError(
        "unknown-param.json",
        sceneWith(R"({"type": "generator", "generator": "plant", "params": {"count": 5}})"),
        {"objects[0].params.count: expected one of the fields leaves, height, spread"});
}

TEST(BadInput, UnknownObjectAndLightType) {
    expectLoadError("teapot.json", sceneWith(R"({"type": "teapot"})"),
                    {"objects[0].type: expected one of \"plane\", \"quad\", \"box\"",
                     "got the string \"teapot\""});
    expectLoadError("area.json", sceneWith(R"({"type": "box", "size": [1, 1, 1]})",
                                           R"({"type": "area", "position": [0, 3, 0]})"),
                    {"lights[0].type: expected one of \"square\", \"point\"", "\"area\""});
    expectLoadError("no-type.json", sceneWith(R"({"size": [1, 1, 1]})"),
                    {"objects[0].type: expected one of", "nothing (the field is required)"});
}

TEST(BadInput, NegativeWidth) {
    expectLoadError("negative-width.json",
                    sceneWith(R"({"type": "box", "size": [1, 1, 1]})",
                              R"({"type": "square", "position": [0, 3, 0], "width": -1})"),
                    {"lights[0].width: expected a number >= 0, got -1"});
}

TEST(BadInput, AlbedoOutOfRange) {
    expectLoadError("albedo.json",
                    sceneWith(R"({"type": "box", "size": [1, 1, 1], "albedo": [0.5, 0.5, 1.5]})"),
                    {"objects[0].albedo[2]: expected a number in [0, 1], got 1.5"});
    expectLoadError(
        "albedo-short.json",
        sceneWith(R"({"type": "box", "size": [1, 1, 1], "albedo": [0.5, 0.5]})"),
        {"objects[0].albedo: expected an array of 3 numbers", "got an array of 2 elements"});
}

TEST(BadInput, DuplicateId) {
    expectLoadError(
        "duplicate-id.json",
        sceneWith(
            R"({"type": "box", "size": [1, 1, 1], "id": 7}, {"type": "box", "size": [1, 1, 1], "id": 7})"),
        {"objects[1].id: expected an id no other object uses, got 7", "objects[0]"});
    // A default id (the index) can collide with an explicit one.
    expectLoadError(
        "duplicate-default-id.json",
        sceneWith(
            R"({"type": "box", "size": [1, 1, 1], "id": 1}, {"type": "box", "size": [1, 1, 1]})"),
        {"objects[1].id: expected an id no other object uses, got 1 (the default"});
}

TEST(BadInput, GltfThatFailsToParse) {
    const std::string gltf = writeFile("garbage.gltf", "this is not { a glTF file");
    const std::string message = expectLoadError(
        "garbage-gltf.json", sceneWith(R"({"type": "gltf", "file": "garbage.gltf"})"),
        {"objects[0].file: "});
    EXPECT_NE(message.find(gltf), std::string::npos)
        << "message does not name the glTF: " << message;
}

TEST(BadInput, GltfWithMissingReferencedFile) {
    const std::string gltf =
        writeFile("missing-buffer.gltf", triangleGltfJson(4, "missing-buffer.bin"));
    const std::string message = expectLoadError(
        "missing-buffer.json", sceneWith(R"({"type": "gltf", "file": "missing-buffer.gltf"})"),
        {"objects[0].file: ", "missing-buffer.bin"});
    EXPECT_NE(message.find(gltf), std::string::npos) << message;
    // And a glTF file that does not exist at all.
    expectLoadError("missing-gltf.json", sceneWith(R"({"type": "gltf", "file": "nowhere.glb"})"),
                    {"objects[0].file: ", "nowhere.glb: no such glTF file"});
    // Lines instead of triangles, through a scene.
    writeFile("lines2.gltf", triangleGltfJson(1));
    expectLoadError("lines.json", sceneWith(R"({"type": "gltf", "file": "lines2.gltf"})"),
                    {"objects[0].file: ", "lines2.gltf", "TRIANGLES"});
}

TEST(BadInput, OtherRangesAndTypes) {
    const std::string box = R"({"type": "box", "size": [1, 1, 1]})";
    expectLoadError("segments.json", sceneWith(R"({"type": "sphere", "radius": 1, "segments": 2})"),
                    {"objects[0].segments: expected an integer in [3, 1024], got 2"});
    expectLoadError("segments-frac.json",
                    sceneWith(R"({"type": "sphere", "radius": 1, "segments": 3.5})"),
                    {"objects[0].segments: expected an integer in [3, 1024], got 3.5"});
    expectLoadError(
        "scale.json",
        sceneWith(R"({"type": "box", "size": [1, 1, 1], "transform": {"scale": [1, 0, 1]}})"),
        {"objects[0].transform.scale[1]: expected a non-zero number, got 0"});
    expectLoadError("size.json", sceneWith(R"({"type": "box", "size": [1, 0, 1]})"),
                    {"objects[0].size[1]: expected a number > 0, got 0"});
    expectLoadError("size-type.json", sceneWith(R"({"type": "quad", "size": "big"})"),
                    {"objects[0].size: expected an array of 2 numbers", "got the string \"big\""});
    expectLoadError(
        "direction.json",
        sceneWith(
            box,
            R"({"type": "square", "position": [0, 3, 0], "direction": [0, 0, 0], "width": 1})"),
        {"lights[0].direction: expected a non-zero vector"});
    expectLoadError(
        "up.json",
        sceneWith(box, R"({"type": "square", "position": [0, 3, 0], "up": [0, 2, 0], "width": 1})"),
        {"lights[0].up: expected a vector not parallel to direction"});
    expectLoadError("missing-width.json",
                    sceneWith(box, R"({"type": "square", "position": [0, 3, 0]})"),
                    {"lights[0].width: expected a number >= 0", "nothing (the field is required)"});
    expectLoadError("bool.json",
                    sceneWith(R"({"type": "box", "size": [1, 1, 1], "casts_shadows": 1})"),
                    {"objects[0].casts_shadows: expected true or false, got 1"});
    expectLoadError("negative-id.json",
                    sceneWith(R"({"type": "box", "size": [1, 1, 1], "id": -1})"),
                    {"objects[0].id: expected an integer in [0, "});
    expectLoadError("keys.json",
                    sceneWith(R"({"type": "box", "size": [1, 1, 1], "motion": {"type": "keyframes",
        "keys": [{"time": 1, "translate": [0, 0, 0]}, {"time": 1, "translate": [1, 0, 0]}]}})"),
                    {"objects[0].motion.keys[1].time: expected a time greater than the previous "
                     "key's (1), got 1"});
    expectLoadError(
        "leaves.json",
        sceneWith(R"({"type": "generator", "generator": "plant", "params": {"leaves": 0}})"),
        {"objects[0].params.leaves: expected an integer in [1, 20000], got 0"});
    expectLoadError(
        "float-range.json",
        sceneWith(
            R"({"type": "box", "size": [1, 1, 1], "transform": {"translate": [1e300, 0, 0]}})"),
        {"objects[0].transform.translate[0]: expected a number representable as a float",
         "got 1e+300"});
    expectLoadError(
        "huge-transform.json",
        sceneWith(R"({"type": "box", "size": [1e30, 1, 1], "transform": {"scale": 1e30}})"),
        {"objects[0].transform: expected a transform that keeps the object finite and invertible"});
    expectLoadError(
        "generator.json", sceneWith(R"({"type": "generator", "generator": "forest"})"),
        {"objects[0].generator: expected \"plant\" or \"complex\", got the string \"forest\""});

    // Camera: fov in (0, 180), 0 < near < far.
    std::string text = sceneWith(box);
    text.replace(text.find("\"target\": [0, 0, 0]"), 19, R"("target": [0, 0, 0], "fov_deg": 180)");
    expectLoadError("fov.json", text, {"camera.fov_deg: expected a number in (0, 180), got 180"});
    text = sceneWith(box);
    text.replace(text.find("\"target\": [0, 0, 0]"), 19,
                 R"("target": [0, 0, 0], "near": 10, "far": 5)");
    expectLoadError("near-far.json", text,
                    {"camera.far: expected a number greater than near (10), got 5"});
    text = sceneWith(box);
    text.replace(text.find("\"target\": [0, 0, 0]"), 19, "\"up\": [0, 1, 0]");
    expectLoadError("no-target.json", text,
                    {"camera.target: expected an array of 3 numbers, got nothing"});

    text = sceneWith(box);
    text.insert(1, "\"ambient\": 2,");
    expectLoadError("ambient.json", text, {": ambient: expected a number in [0, 1], got 2"});
    expectLoadError("top-array.json", "[1, 2]",
                    {"(top level): expected an object, got an array of 2 elements"});
    expectLoadError(
        "no-lights.json",
        R"({"camera": {"position": [0, 5, 5], "target": [0, 0, 0]}, "lights": [], "objects": []})",
        {"lights: expected an array of at least one light, got an array of 0 elements"});
    expectLoadError("duplicate-key.json", "{\"ambient\": 0.1, \"ambient\": 0.2}",
                    {"ambient: expected each field at most once"});
    expectLoadError("deep.json", std::string(200, '[') + std::string(200, ']'),
                    {"levels of nesting"});
}

TEST(BadInput, EmptySceneIsAllowed) {
    const Scene scene = loadScene(writeFile("empty.json", sceneWith("")));
    EXPECT_TRUE(scene.objects.empty());
    EXPECT_TRUE(scene.bounds(0.0).empty());
    EXPECT_EQ(scene.name, "empty");
}

// --- export
// ---------------------------------------------------------------------------------------

TEST(Export, WriteTrianglesOBJ) {
    const Scene scene = loadScene("square-occluder");
    const std::string path = (scratchDir() / "square-occluder.obj").string();
    writeTrianglesOBJ(scene, 0.0, path);
    std::ifstream in(path);
    std::string line;
    size_t faces = 0, vertices = 0, groups = 0;
    size_t maxIndex = 0;
    while (std::getline(in, line)) {
        if (line.rfind("f ", 0) == 0) {
            ++faces;
            std::istringstream s(line.substr(2));
            size_t a, b, c;
            s >> a >> b >> c;
            EXPECT_GE(std::min({a, b, c}), 1u);
            maxIndex = std::max({maxIndex, a, b, c});
        } else if (line.rfind("v ", 0) == 0) {
            ++vertices;
        } else if (line.rfind("o ", 0) == 0) {
            ++groups;
        }
    }
    EXPECT_EQ(faces, 2u + 12u);
    EXPECT_EQ(vertices, 4u + 24u);
    EXPECT_EQ(groups, 2u);
    EXPECT_EQ(maxIndex, vertices);

    const std::string message =
        errorOf([&] { writeTrianglesOBJ(scene, 0.0, "/nonexistent-dir/x.obj"); });
    EXPECT_NE(message.find("/nonexistent-dir/x.obj"), std::string::npos);
}

// ---- the real-mesh test set (assets/models/README.md) ---------------------------------------

// realMeshNames(), the table of scripts/fetch-meshes.sh and the mesh-NAME scenes name the same meshes.
TEST(RealMeshes, TheFetchScriptTheNamesAndTheScenesAgree) {
    std::ifstream script(projectRoot() + "/scripts/fetch-meshes.sh");
    ASSERT_TRUE(script.good());
    std::vector<std::string> fromScript;
    for (std::string line; std::getline(script, line);) {
        std::istringstream words(line);
        std::string name, registry;
        words >> name >> registry;  // the table's lines: "  \"NAME npm|deb package=version ..."
        if (name.size() > 1 && name[0] == '"' && (registry == "npm" || registry == "deb")) fromScript.push_back(name.substr(1));
    }
    std::sort(fromScript.begin(), fromScript.end());
    EXPECT_EQ(fromScript, realMeshNames());
    EXPECT_GE(realMeshNames().size(), 6u);
    std::vector<std::string> fromScenes;
    for (const std::string& scene : listScenes())
        if (!testing::realMeshOfScene(scene).empty()) fromScenes.push_back(testing::realMeshOfScene(scene));
    EXPECT_EQ(fromScenes, realMeshNames());
}

// random:SEED:mesh=NAME is random:SEED plus the mesh, standing on the ground near the middle; the same
// name gives the same scene.
TEST(RandomScene, MeshOptionAddsTheRealMesh) {
    if (!testing::sceneCanLoad("mesh-bunny")) GTEST_SKIP() << "assets/models/real/bunny.gltf is missing";
    const Scene plain = loadScene("random:42"), a = loadScene("random:42:mesh=bunny"), b = loadScene("random:42:mesh=bunny");
    ASSERT_EQ(a.objects.size(), plain.objects.size() + 1);
    for (size_t i = 0; i < plain.objects.size(); ++i) {
        EXPECT_EQ(a.objects[i].mesh.positions, plain.objects[i].mesh.positions) << i;
        EXPECT_EQ(a.objects[i].worldFromObject, plain.objects[i].worldFromObject) << i;
    }
    EXPECT_EQ(a.camera.position, plain.camera.position);
    EXPECT_EQ(a.lights[0].position, plain.lights[0].position);
    EXPECT_EQ(a.name, "random-42-bunny");

    const Object& bunny = a.objects.back();
    EXPECT_EQ(bunny.source, "gltf:" + realMeshPath("bunny"));
    EXPECT_EQ(bunny.mesh.triangleCount(), 3674u);
    EXPECT_EQ(bunny.id, int(plain.objects.size()));
    EXPECT_TRUE(bunny.castsShadows);
    EXPECT_EQ(bunny.worldFromObject, b.objects.back().worldFromObject);
    EXPECT_NE(bunny.worldFromObject, loadScene("random:43:mesh=bunny").objects.back().worldFromObject);
    Bounds world;
    for (const glm::vec3& p : bunny.mesh.positions) world.extend(glm::vec3(bunny.worldFromObject * glm::vec4(p, 1.0f)));
    EXPECT_NEAR(world.lo.y, 0.0f, 1e-4f);                                  // resting on the ground
    EXPECT_GE(world.hi.y, 0.4f);                                           // scaled 0.6 .. 1.2 from 1.5 units
    EXPECT_LE(std::max(world.hi.x - world.lo.x, world.hi.z - world.lo.z), 1.81f * 1.5f);
    EXPECT_LE(std::max({std::abs(world.lo.x), std::abs(world.hi.x), std::abs(world.lo.z), std::abs(world.hi.z)}), 6.0f);  // on the 12 x 12 ground
}

// Bad options are input errors that say what was expected.
TEST(RandomScene, MeshOptionErrors) {
    auto expectError = [](const std::string& name, const std::vector<std::string>& parts) {
        const std::string message = errorOf([&] { loadScene(name); });
        for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << name << ": " << message;
    };
    expectError("random:42:mesh=dragon", {"random:42:mesh=dragon", "mesh=dragon", "expected one of the real meshes",
                                          "bunny", "stanford-dragon", "assets/models/README.md"});
    expectError("random:42:mesh=", {"mesh=(nothing)", "expected one of the real meshes"});
    expectError("random:42:size=3", {"random:SEED:mesh=NAME", "'size=3'"});
    expectError("random:42:", {"random:SEED:mesh=NAME"});
    expectError("random:42:mesh=bunny:mesh=teapot", {"mesh= given twice"});
    expectError("random:x:mesh=bunny", {"random:SEED or random:SEED:mesh=NAME", "whole number"});

    // A known mesh whose glTF was never made: the path, and what makes it.
    const char* previous = std::getenv("SHADOWLAB_ROOT");
    const std::string saved = previous ? previous : "";
    const std::string empty = std::string(SHADOWLAB_TEST_TMP) + "/no-real-meshes";
    fs::create_directories(empty);
    setenv("SHADOWLAB_ROOT", empty.c_str(), 1);
    const std::string message = errorOf([] { loadScene("random:42:mesh=teapot"); });
    if (previous) setenv("SHADOWLAB_ROOT", saved.c_str(), 1); else unsetenv("SHADOWLAB_ROOT");
    for (const std::string& part : {empty + "/assets/models/real/teapot.gltf", std::string("no such glTF file"),
                                    std::string("scripts/fetch-meshes.sh")})
        EXPECT_NE(message.find(part), std::string::npos) << message;
}

TEST(Paths, ResolveScenePath) {
    EXPECT_EQ(resolveScenePath("square-occluder"),
              projectRoot() + "/assets/scenes/square-occluder.json");
    const std::string path = writeFile("by-path.json", sceneWith(""));
    EXPECT_EQ(resolveScenePath(path), path);
}

}  // namespace
}  // namespace shadowlab

// Robustness (issue 11, "found when tried as a new user would"): each finding has a test here that
// failed before its fix. Bad and heavy input must give exit code 2 and a message naming the file,
// line or field, never a crash, a hang or an exhausted machine.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include "error.h"
#include "scene/scene.h"
#include "support/cli_run.h"

namespace shadowlab {
namespace {

namespace fs = std::filesystem;
using test::run;

std::string tmp(const std::string& name) { return test::testPath("robustness", name); }

std::string writeFile(const std::string& name, const std::string& text) {
    const std::string path = tmp(name);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    return path;
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected InputError, got: " << e.what();
        return "";
    }
    ADD_FAILURE() << "expected InputError, nothing was thrown";
    return "";
}

#define EXPECT_CONTAINS(text, part) \
    EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (part) << "' not in: " << (text)

std::string base64(const std::string& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const uint32_t v = (uint8_t(bytes[i]) << 16) | (uint8_t(bytes[i + 1]) << 8) | uint8_t(bytes[i + 2]);
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

// A glTF with one triangle mesh (mesh 0), the given "nodes" array, scene 0 with `roots`, and extra
// top-level fields. `bufferUri` replaces the embedded buffer when not empty.
std::string gltfWith(const std::string& nodes, const std::string& roots, const std::string& extra = "",
                     const std::string& bufferUri = "", const std::string& primitiveExtra = "") {
    std::string blob(36 + 4, '\0');
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 0, -1};
    const uint8_t indices[4] = {0, 1, 2, 0};
    std::memcpy(blob.data(), positions, 36);
    std::memcpy(blob.data() + 36, indices, 4);
    const std::string uri = bufferUri.empty() ? "data:application/octet-stream;base64," + base64(blob) : bufferUri;
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": )" + roots + R"(}],
      "nodes": )" + nodes + R"(,
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1)" + primitiveExtra + R"(}]}],
      "buffers": [{"byteLength": 40, "uri": ")" + uri + R"("}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                      {"buffer": 0, "byteOffset": 36, "byteLength": 3}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, -1], "max": [1, 0, 0]},
                    {"bufferView": 1, "componentType": 5121, "count": 3, "type": "SCALAR"}])" +
           extra + "}";
}

const char* kSceneHead = R"({
  "camera": {"position": [0, 5, 5], "target": [0, 0, 0]},
  "lights": [{"type": "square", "position": [0, 4, 0], "width": 1}],
  "objects": [)";

std::string sceneWith(const std::string& objects) { return kSceneHead + objects + "]\n}\n"; }

// --- glTF node trees -----------------------------------------------------------------------------

TEST(GltfNodes, TenThousandDeepChainLoads) {
    // Before: SIGSEGV (stack overflow in the recursive node walk). Each node translates by 0.001 in
    // x, so the leaf's triangle lands at x = 10 (within float rounding of 10,000 additions).
    const int depth = 10000;
    std::string nodes = "[";
    for (int i = 0; i < depth; ++i) {
        nodes += i ? "," : "";
        nodes += "{\"translation\": [0.001, 0, 0]";
        if (i + 1 < depth) nodes += ", \"children\": [" + std::to_string(i + 1) + "]";
        else nodes += ", \"mesh\": 0";
        nodes += "}";
    }
    nodes += "]";
    const std::string path = writeFile("deep.gltf", gltfWith(nodes, "[0]"));
    // Run in a child process with a small stack, so that a recursive walk fails here for sure.
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        rlimit limit{512 * 1024, 512 * 1024};
        setrlimit(RLIMIT_STACK, &limit);
        try {
            const Mesh mesh = loadGltfMesh(path);
            _exit(mesh.triangleCount() == 1 && std::abs(mesh.positions[0].x - 10.0f) < 0.01f ? 0 : 3);
        } catch (...) {
            _exit(4);
        }
    }
    int status = 0;
    waitpid(child, &status, 0);
    ASSERT_TRUE(WIFEXITED(status)) << "the loader crashed (signal " << WTERMSIG(status) << ")";
    EXPECT_EQ(WEXITSTATUS(status), 0);
    // And in this process (the real stack) too.
    const Mesh mesh = loadGltfMesh(path);
    EXPECT_EQ(mesh.triangleCount(), 1u);
    EXPECT_NEAR(mesh.positions[1].x, 11.0f, 0.01f);
}

TEST(GltfNodes, ChildListedTwiceIsAnErrorNamingTheNode) {
    // Before: accepted, and 30 such nodes made the walk exponential (2^30 visits).
    std::string nodes = "[";
    const int n = 30;
    for (int i = 0; i < n; ++i) {
        nodes += i ? "," : "";
        if (i + 1 < n) nodes += "{\"children\": [" + std::to_string(i + 1) + ", " + std::to_string(i + 1) + "]}";
        else nodes += "{\"mesh\": 0}";
    }
    nodes += "]";
    const std::string path = writeFile("twice.gltf", gltfWith(nodes, "[0]"));
    const auto start = std::chrono::steady_clock::now();
    const std::string message = errorOf([&] { loadGltfMesh(path); });
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
    EXPECT_CONTAINS(message, path);
    EXPECT_CONTAINS(message, "nodes[1]");
    EXPECT_CONTAINS(message, "two parents");
}

TEST(GltfNodes, NodeWithTwoDifferentParentsOrAlsoARootIsAnError) {
    const std::string two = writeFile("two-parents.gltf",
                                      gltfWith(R"([{"children": [2]}, {"children": [2]}, {"mesh": 0}])", "[0, 1]"));
    const std::string message = errorOf([&] { loadGltfMesh(two); });
    EXPECT_CONTAINS(message, "nodes[2] has two parents (nodes[0] and nodes[1])");
    const std::string root = writeFile("root-child.gltf", gltfWith(R"([{"children": [1]}, {"mesh": 0}])", "[0, 1]"));
    EXPECT_CONTAINS(errorOf([&] { loadGltfMesh(root); }), "nodes[1]");
    const std::string cycle = writeFile("cycle.gltf", gltfWith(R"([{"children": [1]}, {"children": [0], "mesh": 0}])", "[0]"));
    EXPECT_CONTAINS(errorOf([&] { loadGltfMesh(cycle); }), "nodes[0]");
    // Through the command line: exit 2, naming the node.
    const std::string scene = writeFile("two-parents.json", sceneWith(R"({"type": "gltf", "file": "two-parents.gltf"})"));
    const test::Result r = run("scene --scene " + scene + " --dump-triangles " + tmp("t.obj"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_CONTAINS(r.output, "nodes[2] has two parents");
}

TEST(GltfNodes, SharedMeshInstancesStillWork) {
    // Two nodes may reference the same mesh (instancing is legal, unlike a shared child).
    const std::string path = writeFile("instances.gltf",
                                       gltfWith(R"([{"mesh": 0}, {"mesh": 0, "translation": [5, 0, 0]}])", "[0, 1]"));
    const Mesh mesh = loadGltfMesh(path);
    EXPECT_EQ(mesh.triangleCount(), 2u);
}

// --- glTF features shadowlab does not support ------------------------------------------------------

TEST(GltfFeatures, DracoIsNamed) {
    // Before: "invalid bufferView". A Draco primitive has no plain accessors for its data.
    const std::string draco = R"(, "extensionsUsed": ["KHR_draco_mesh_compression"],
      "extensionsRequired": ["KHR_draco_mesh_compression"])";
    const std::string ext =
        R"(, "extensions": {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}})";
    const std::string path = writeFile("draco.gltf", gltfWith(R"([{"mesh": 0}])", "[0]", draco, "", ext));
    const std::string message = errorOf([&] { loadGltfMesh(path); });
    EXPECT_CONTAINS(message, path);
    EXPECT_CONTAINS(message, "KHR_draco_mesh_compression");
    EXPECT_CONTAINS(message, "does not support");
    // Only used (not required): the primitive must carry uncompressed data, which is read; when
    // that fallback is unusable, the message says the primitive is Draco-compressed.
    const std::string usedOnly = writeFile("draco-used.gltf",
        gltfWith(R"([{"mesh": 0}])", "[0]", R"(, "extensionsUsed": ["KHR_draco_mesh_compression"])", "", ext));
    EXPECT_EQ(loadGltfMesh(usedOnly).triangleCount(), 1u);
    std::string noFallback = gltfWith(R"([{"mesh": 0}])", "[0]", R"(, "extensionsUsed": ["KHR_draco_mesh_compression"])", "", ext);
    noFallback.replace(noFallback.find(R"("bufferView": 0, "componentType": 5126)"), 16, R"("bufferView": 9,)");
    const std::string broken = writeFile("draco-nofallback.gltf", noFallback);
    EXPECT_CONTAINS(errorOf([&] { loadGltfMesh(broken); }), "KHR_draco_mesh_compression");
    // Any other required extension is named too.
    const std::string other = writeFile("meshopt.gltf", gltfWith(R"([{"mesh": 0}])", "[0]",
        R"(, "extensionsUsed": ["EXT_meshopt_compression"], "extensionsRequired": ["EXT_meshopt_compression"])"));
    EXPECT_CONTAINS(errorOf([&] { loadGltfMesh(other); }), "EXT_meshopt_compression");
}

TEST(GltfFeatures, SkinnedAndMorphedModelsWarn) {
    // Before: rendered in the rest pose without a word.
    const std::string skin = R"(, "skins": [{"joints": [1]}])";
    const std::string skinned = writeFile("skinned.gltf", gltfWith(R"([{"mesh": 0, "skin": 0}, {}])", "[0, 1]", skin));
    std::vector<std::string> warnings;
    const Mesh mesh = loadGltfMesh(skinned, SceneLimits{}, &warnings);
    EXPECT_EQ(mesh.triangleCount(), 1u);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_CONTAINS(warnings[0], "skin");
    EXPECT_CONTAINS(warnings[0], "rest pose");
    warnings.clear();
    const std::string morphed = writeFile("morphed.gltf",
        gltfWith(R"([{"mesh": 0}])", "[0]", "", "", R"(, "targets": [{"POSITION": 0}])"));
    loadGltfMesh(morphed, SceneLimits{}, &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_CONTAINS(warnings[0], "morph");
    // Through a scene and the command line: a warning on stderr, exit 0.
    const std::string scene = writeFile("skinned.json", sceneWith(R"({"type": "gltf", "file": "skinned.gltf"})"));
    const Scene loaded = loadScene(scene);
    ASSERT_EQ(loaded.warnings.size(), 1u);
    EXPECT_CONTAINS(loaded.warnings[0], scene + ":4: objects[0].file: ");  // the scene field, then the glTF
    EXPECT_CONTAINS(loaded.warnings[0], "skinned.gltf: nodes[0] has a skin");
    const test::Result r = run("scene --scene " + scene + " --dump-triangles " + tmp("s.obj"));
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_CONTAINS(r.output, "warning: ");
    EXPECT_CONTAINS(r.output, "rest pose");
}

TEST(GltfFeatures, BufferUriNamingADirectory) {
    // Before: "std::bad_alloc".
    fs::create_directories(tmp("bufferdir"));
    const std::string path = writeFile("dir-buffer.gltf", gltfWith(R"([{"mesh": 0}])", "[0]", "", "bufferdir"));
    const std::string message = errorOf([&] { loadGltfMesh(path); });
    EXPECT_CONTAINS(message, path);
    EXPECT_CONTAINS(message, "bufferdir");
    EXPECT_CONTAINS(message, "directory");
    EXPECT_EQ(message.find("bad_alloc"), std::string::npos) << message;
    // A FIFO is not a regular file either (reading it would block forever).
    fs::remove(tmp("fifo.bin"));
    ASSERT_EQ(mkfifo(tmp("fifo.bin").c_str(), 0600), 0);
    const std::string fifo = writeFile("fifo-buffer.gltf", gltfWith(R"([{"mesh": 0}])", "[0]", "", "fifo.bin"));
    EXPECT_CONTAINS(errorOf([&] { loadGltfMesh(fifo); }), "not a regular file");
}

// --- geometry limits --------------------------------------------------------------------------------

TEST(Limits, PrimitiveEstimatesAreExact) {
    // The estimate the limit uses is the count the builders produce.
    for (int segments : {3, 4, 5, 32, 1024}) {
        EXPECT_EQ(estimateSphereTriangles(segments), makeSphere(1.0f, segments).triangleCount()) << segments;
        EXPECT_EQ(estimateCylinderTriangles(segments), makeCylinder(1.0f, 1.0f, segments).triangleCount());
        EXPECT_EQ(estimateDiskTriangles(segments), makeDisk(1.0f, segments).triangleCount());
    }
    for (int leaves : {1, 40, 300, 20000}) {
        PlantParams p;
        p.leaves = leaves;
        EXPECT_EQ(estimatePlantTriangles(p), generatePlant(1, p).triangleCount()) << leaves;
    }
    ComplexParams c;
    c.count = 37;
    EXPECT_EQ(estimateComplexTriangles(c), generateComplex(1, c).triangleCount());
}

std::string manySpheres(int count, int segments) {
    std::string objects;
    for (int i = 0; i < count; ++i) {
        objects += i ? ",\n" : "";
        objects += R"({"type": "sphere", "radius": 0.1, "segments": )" + std::to_string(segments) +
                   R"(, "transform": {"translate": [)" + std::to_string(i % 50) + ", 1, " + std::to_string(i / 50) + "]}}";
    }
    return sceneWith(objects);
}

TEST(Limits, HugeSceneIsRefusedBeforeAllocating) {
    // Before: 2,000 spheres of 1024 segments (2.09e9 triangles) were killed by the kernel at 24 GB.
    const std::string path = writeFile("spheres.json", manySpheres(2000, 1024));
    const auto start = std::chrono::steady_clock::now();
    const test::Result r = run("scene --scene " + path + " --dump-triangles " + tmp("s.obj"));
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_CONTAINS(r.output, path);
    EXPECT_CONTAINS(r.output, "2093056000 triangles");  // 2000 x 2 x 1024 x 511
    EXPECT_CONTAINS(r.output, "GB");
    EXPECT_CONTAINS(r.output, "--max-triangles");
    EXPECT_FALSE(fs::exists(tmp("s.obj")));
}

TEST(Limits, TheFlagRaisesAndLowersTheLimit) {
    // 20 spheres of 64 segments: 20 x 2 x 64 x 31 = 79,360 triangles.
    const std::string path = writeFile("spheres.json", manySpheres(20, 64));
    EXPECT_EQ(loadScene(path).objects.size(), 20u);
    SceneLimits tight;
    tight.maxTriangles = 79359;
    EXPECT_CONTAINS(errorOf([&] { loadScene(path, tight); }), "79360 triangles");
    tight.maxTriangles = 79360;
    EXPECT_EQ(loadScene(path, tight).objects.size(), 20u);
    const test::Result low = run("scene --scene " + path + " --max-triangles 1000 --dump-triangles " + tmp("a.obj"));
    EXPECT_EQ(low.code, 2) << low.output;
    EXPECT_CONTAINS(low.output, "limit of 1000 triangles");
    const test::Result bad = run("scene --scene " + path + " --max-triangles lots --dump-triangles " + tmp("a.obj"));
    EXPECT_EQ(bad.code, 2) << bad.output;
    EXPECT_CONTAINS(bad.output, "--max-triangles");
}

TEST(Limits, GltfInstancesCountAgainstTheLimit) {
    // 1000 nodes instancing one mesh: counted per instance, before the vertices are read.
    std::string nodes = "[";
    for (int i = 0; i < 1000; ++i) nodes += std::string(i ? "," : "") + R"({"mesh": 0})";
    nodes += "]";
    std::string roots = "[";
    for (int i = 0; i < 1000; ++i) roots += (i ? "," : "") + std::to_string(i);
    roots += "]";
    const std::string path = writeFile("instances.gltf", gltfWith(nodes, roots));
    SceneLimits limits;
    limits.maxTriangles = 999;
    const std::string message = errorOf([&] { loadGltfMesh(path, limits); });
    EXPECT_CONTAINS(message, "1000 triangles");
    limits.maxTriangles = 1000;
    EXPECT_EQ(loadGltfMesh(path, limits).triangleCount(), 1000u);
}

TEST(Limits, HugeImageIsRefusedBeforeAllocating) {
    // 8192x8192 is a valid size, but its G-buffer and outputs need far more memory than a
    // classroom machine should give one render: estimated and refused unless raised.
    const test::Result r = run("render --scene square-occluder --size 8192x8192 --max-memory-mb 512 --out " + tmp("big.png"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_CONTAINS(r.output, "--max-memory-mb");
    EXPECT_CONTAINS(r.output, "MB");
}

// --- outputs: signals, conflicts, repeated flags ---------------------------------------------------

// Starts `shadowlab args` and returns its pid (stdout and stderr to `log`).
pid_t spawn(const std::vector<std::string>& args, const std::string& log) {
    const pid_t pid = fork();
    if (pid == 0) {
        std::vector<char*> argv;
        argv.push_back(const_cast<char*>(SHADOWLAB_BINARY));
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        FILE* out = std::fopen(log.c_str(), "w");
        if (out) {
            dup2(fileno(out), 1);
            dup2(fileno(out), 2);
        }
        execv(SHADOWLAB_BINARY, argv.data());
        _exit(127);
    }
    return pid;
}

int countTemporaries(const fs::path& dir) {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().find(".tmp-") != std::string::npos) ++n;
    return n;
}

void killWhileWriting(int signal) {
    // A render whose outputs take a while to write (four 1024x1024 PFMs and a PNG): wait until a
    // staged temporary exists, then send the signal. Before: the temporaries stayed behind.
    const fs::path dir = fs::path(tmp("x")).parent_path();
    for (const auto& e : fs::directory_iterator(dir)) fs::remove_all(e.path());
    const std::string d = dir.string() + "/";
    const pid_t pid = spawn({"render", "--scene", "square-occluder", "--technique", "hard", "--size", "1024x1024",
                             "--frames", "1", "--out", d + "o.png", "--visibility", d + "v.pfm", "--positions",
                             d + "p.pfm", "--ids", d + "i.pfm"},
                            tmp("log.txt"));
    ASSERT_GT(pid, 0);
    bool sawTemporary = false;
    int status = 0;
    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
        if (waitpid(pid, &status, WNOHANG) == pid) break;
        if (countTemporaries(dir) > 0) {
            sawTemporary = true;
            kill(pid, signal);
            waitpid(pid, &status, 0);
            break;
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    ASSERT_TRUE(sawTemporary) << "the render finished before a temporary was seen; make it slower";
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal) << "the process should die of the signal";
    EXPECT_EQ(countTemporaries(dir), 0) << "staged temporaries left behind after signal " << signal;
    EXPECT_FALSE(fs::exists(d + "o.png") && fs::exists(d + "i.pfm")) << "outputs committed despite the signal";
}

TEST(Outputs, SigtermRemovesStagedTemporaries) { killWhileWriting(SIGTERM); }
TEST(Outputs, SigintRemovesStagedTemporaries) { killWhileWriting(SIGINT); }

TEST(Outputs, TwoOutputsToOneFileAreRefused) {
    // Before: --positions p.pfm --ids p.pfm silently wrote one file.
    const std::string p = tmp("p.pfm");
    const test::Result r = run("render --scene square-occluder --size 8x8 --positions " + p + " --ids " + p);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_CONTAINS(r.output, "--positions");
    EXPECT_CONTAINS(r.output, "--ids");
    EXPECT_CONTAINS(r.output, "same file");
    EXPECT_FALSE(fs::exists(p));
    // The same file spelled differently is the same file.
    const std::string dir = fs::path(p).parent_path().string();
    const test::Result r2 = run("render --scene square-occluder --size 8x8 --visibility " + p + " --ids " + dir +
                                "/./p.pfm");
    EXPECT_EQ(r2.code, 2) << r2.output;
    EXPECT_CONTAINS(r2.output, "same file");
}

TEST(Outputs, RepeatedFlagIsRefused) {
    // Before: a repeated flag silently took the last value.
    const test::Result r = run("render --scene square-occluder --size 8x8 --size 16x16 --out " + tmp("a.png"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_CONTAINS(r.output, "--size");
    EXPECT_CONTAINS(r.output, "more than once");
    EXPECT_FALSE(fs::exists(tmp("a.png")));
    const test::Result t = run("render --scene square-occluder --technique hard --technique pcf --size 8x8");
    EXPECT_EQ(t.code, 2) << t.output;
    EXPECT_CONTAINS(t.output, "--technique");
    // --set is meant to be repeated.
    const test::Result s = run("render --scene square-occluder --technique pcf --set pcf_kernel=3 --set sm_size=256 "
                               "--size 8x8 --visibility " + tmp("v.pfm"));
    EXPECT_EQ(s.code, 0) << s.output;
}

TEST(Outputs, DevNullSceneSaysWhatIsWrong) {
    // Before: "no such scene file".
    const test::Result r = run("render --scene /dev/null --size 8x8");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_CONTAINS(r.output, "/dev/null");
    EXPECT_CONTAINS(r.output, "not a regular file");
    EXPECT_EQ(r.output.find("no such scene file"), std::string::npos) << r.output;
    const std::string dir = fs::path(tmp("x")).parent_path().string() + "/scenes.json";
    fs::create_directories(dir);
    const test::Result d = run("render --scene " + dir + " --size 8x8");
    EXPECT_EQ(d.code, 2) << d.output;
    EXPECT_CONTAINS(d.output, "is a directory");
    const std::string empty = writeFile("empty.json", "");
    const test::Result e = run("render --scene " + empty + " --size 8x8");
    EXPECT_EQ(e.code, 2) << e.output;
    EXPECT_CONTAINS(e.output, "empty");
}

// --- scene-file errors name the line ----------------------------------------------------------------

TEST(SceneErrors, NameTheLine) {
    const std::string text = "{\n  \"camera\": {\"position\": [0, 5, 5], \"target\": [0, 0, 0]},\n"
                             "  \"lights\": [{\"type\": \"square\", \"position\": [0, 4, 0], \"width\": 1}],\n"
                             "  \"objects\": [\n    {\"type\": \"box\", \"size\": [1, 1, 1]},\n"
                             "    {\"type\": \"box\", \"size\": [1, -1, 1]}\n  ]\n}\n";
    const std::string path = writeFile("line.json", text);
    const std::string message = errorOf([&] { loadScene(path); });
    EXPECT_CONTAINS(message, path + ":6: objects[1].size[1]: expected a number > 0, got -1");
}

// --- fuzz findings -------------------------------------------------------------------------------------

// Every input in tests/fuzz/regressions/<target>/ (crashes and hangs scripts/fuzz.sh found, and the
// findings above) loads or gives an InputError, quickly, through the same path as its fuzz target.
TEST(FuzzRegressions, EveryReproducerGivesACleanResult) {
    const fs::path root = fs::path(projectRoot()) / "tests" / "fuzz" / "regressions";
    size_t replayed = 0;
    SceneLimits limits;
    limits.maxTriangles = 200000;  // as in tests/fuzz/fuzz_common.h
    for (const char* target : {"scene", "gltf"}) {
        if (!fs::is_directory(root / target)) continue;
        for (const auto& entry : fs::directory_iterator(root / target)) {
            std::ifstream in(entry.path(), std::ios::binary);
            std::stringstream bytes;
            bytes << in.rdbuf();
            const std::string data = bytes.str();
            const bool glb = data.rfind("glTF", 0) == 0;
            const std::string copy = writeFile(std::string(target) == "scene" ? "fuzz.json" : glb ? "fuzz.glb" : "fuzz.gltf", data);
            const auto start = std::chrono::steady_clock::now();
            try {
                if (std::string(target) == "scene") loadScene(copy, limits);
                else loadGltfMesh(copy, limits);
            } catch (const InputError&) {
            } catch (const std::exception& e) {
                ADD_FAILURE() << entry.path() << ": not an InputError: " << e.what();
            }
            EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0) << entry.path();
            ++replayed;
        }
    }
    EXPECT_GE(replayed, 1u);
}

}  // namespace
}  // namespace shadowlab

// Soak (issue 11): every technique on every scene in turn, many frames, in one process. After the
// first round (programs compiled, caches filled) the live GL objects, the GPU memory the renderer
// counts and the resident memory must come back to their level after every further round, with no
// GL error. The suite runs a short version (2 rounds of 4 frames); scripts/soak.sh runs the full
// one (SHADOWLAB_SOAK_FRAMES=500, SHADOWLAB_SOAK_ROUNDS=3) and prints the figures.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

#include "gl_fixture.h"
#include "gl_util.h"
#include "renderer.h"
#include "scene.h"
#include "technique.h"

namespace shadowlab {
namespace {

int envInt(const char* name, int fallback) {
    const char* v = std::getenv(name);
    return v && *v ? std::atoi(v) : fallback;
}

// Resident memory in KB (/proc/self/statm, second field, pages).
long residentKB() {
    std::ifstream statm("/proc/self/statm");
    long size = 0, resident = 0;
    statm >> size >> resident;
    return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

// Live GL objects of each kind, by asking the driver about every name up to a bound (Mesa hands
// out small consecutive names).
struct LiveObjects {
    int textures = 0, buffers = 0, framebuffers = 0, vertexArrays = 0, programs = 0, queries = 0;
    bool operator==(const LiveObjects&) const = default;
};
LiveObjects liveObjects() {
    LiveObjects live;
    for (GLuint name = 1; name < 20000; ++name) {
        live.textures += glIsTexture(name) == GL_TRUE;
        live.buffers += glIsBuffer(name) == GL_TRUE;
        live.framebuffers += glIsFramebuffer(name) == GL_TRUE;
        live.vertexArrays += glIsVertexArray(name) == GL_TRUE;
        live.programs += glIsProgram(name) == GL_TRUE;
        live.queries += glIsQuery(name) == GL_TRUE;
    }
    return live;
}
std::string describe(const LiveObjects& l) {
    char text[256];
    std::snprintf(text, sizeof text, "textures %d buffers %d framebuffers %d vertex arrays %d programs %d queries %d",
                  l.textures, l.buffers, l.framebuffers, l.vertexArrays, l.programs, l.queries);
    return text;
}

// Few samples: the soak is about lifetimes, not quality.
std::vector<std::pair<std::string, std::string>> cheap(const std::string& technique) {
    if (technique == "reference") return {{"samples", "4"}};
    if (technique == "raytraced") return {{"rays", "2"}};
    return {};
}

class Soak : public testing::GLTest {};

TEST_F(Soak, EveryTechniqueOnEverySceneReturnsToItsLevel) {
    const int frames = envInt("SHADOWLAB_SOAK_FRAMES", 4);
    const int rounds = envInt("SHADOWLAB_SOAK_ROUNDS", 2);
    const int size = envInt("SHADOWLAB_SOAK_SIZE", 24);
    std::vector<Scene> scenes;
    for (const std::string& name : listScenes()) scenes.push_back(loadScene(name));
    ASSERT_GE(scenes.size(), 9u);
    std::vector<std::string> techniques;
    for (const TechniqueDesc* d : allTechniques()) techniques.push_back(d->id);

    LiveObjects firstLive;
    GpuMemoryStats firstGpu;
    long firstRss = 0;
    for (int round = 0; round < rounds; ++round) {
        for (const Scene& scene : scenes) {
            for (const std::string& technique : techniques) {
                if (technique == "template") continue;  // the copy-me example, not a technique to soak
                RenderOptions options;
                options.width = options.height = size;
                options.technique = technique;
                options.sets = cheap(technique);
                Renderer renderer(scene, options);
                for (int f = 0; f < frames; ++f) {
                    // A live change as a window makes it: a resize every third frame.
                    if (f % 3 == 2) renderer.resize(size + (f % 2), size);
                    renderer.renderFrame(f, {"image", "visibility"});
                }
                glFinish();
            }
        }
        const LiveObjects live = liveObjects();
        const GpuMemoryStats gpu = gpuMemory();
        const long rss = residentKB();
        std::printf("[soak] round %d: %s; counted GPU: %lld textures %lld buffers %.1f MB; resident %.1f MB\n", round,
                    describe(live).c_str(), (long long)gpu.textures, (long long)gpu.buffers, gpu.totalBytes() / 1e6,
                    rss / 1024.0);
        if (round == 0) {
            firstLive = live;
            firstGpu = gpu;
            firstRss = rss;
            continue;
        }
        EXPECT_EQ(live, firstLive) << "round " << round << ": " << describe(live) << " vs " << describe(firstLive);
        EXPECT_EQ(gpu.textures, firstGpu.textures) << "round " << round;
        EXPECT_EQ(gpu.buffers, firstGpu.buffers) << "round " << round;
        EXPECT_EQ(gpu.totalBytes(), firstGpu.totalBytes()) << "round " << round;
        // Resident memory: the allocator and the driver keep freed pages around, so allow 16 MB
        // (a leak of one frame's 24x24 buffers per render would be far more over a 500-frame round,
        // and any leaked GL object is caught exactly above).
        EXPECT_LE(rss - firstRss, 16 * 1024) << "round " << round << ": resident grew from " << firstRss / 1024
                                             << " MB to " << rss / 1024 << " MB";
    }
}

}  // namespace
}  // namespace shadowlab

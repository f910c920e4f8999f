// Soak (issue 11): every technique on every scene in turn, many frames, in one process. After the
// first round (programs compiled, caches filled) the live GL objects, the GPU memory the renderer
// counts and the resident memory must come back to their level after every further round, with no
// GL error. The suite runs a short version (3 rounds of 4 frames); scripts/soak.sh runs the full
// one (SHADOWLAB_SOAK_FRAMES=500, SHADOWLAB_SOAK_ROUNDS=3) and prints the figures.
// GL objects and counted GPU bytes are compared with the first round exactly; resident memory with
// the second: with a cold Mesa shader cache, llvmpipe's process sometimes keeps one more step of about
// 4 MB in the second round and is flat from then on (measured: 1 run of 6 with a fresh
// MESA_SHADER_CACHE_DIR, +4.1 MB in round 1, then within 0.1 MB over rounds 2-3; the other cold runs
// and every warm one flat within 0.3 MB), a one-off step, not a growth per round; CI failed twice on
// it when round 1 was the check (+4148 and +4220 KB).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <malloc.h>
#include <unistd.h>

#include "gl/util.h"
#include "graph/renderer.h"
#include "graph/technique.h"
#include "scene/scene.h"
#include "support/gl_fixture.h"
#include "support/real_meshes.h"

namespace shadowlab {
namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif

int envInt(const char* name, int fallback) {
    const char* v = std::getenv(name);
    return v && *v ? std::atoi(v) : fallback;
}

// Resident memory in KB (/proc/self/statm, second field, pages), after returning the allocator's
// free pages to the system (malloc_trim), so that freed memory does not count as grown.
long residentKB() {
    malloc_trim(0);
    std::ifstream statm("/proc/self/statm");
    long size = 0, resident = 0;
    statm >> size >> resident;
    return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

// Live GL objects of each kind, by asking the driver about every name it has handed out: Mesa
// gives each new object the largest name so far plus one, so a fresh probe object's name bounds
// them (a fixed bound is not enough: a 500-frame round with resizes creates 100,000 textures).
struct LiveObjects {
    int textures = 0, buffers = 0, framebuffers = 0, vertexArrays = 0, programs = 0, queries = 0;
    bool operator==(const LiveObjects&) const = default;
};
LiveObjects liveObjects() {
    GLuint texture = 0, buffer = 0, framebuffer = 0, vertexArray = 0, query = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glCreateBuffers(1, &buffer);
    glCreateFramebuffers(1, &framebuffer);
    glCreateVertexArrays(1, &vertexArray);
    glCreateQueries(GL_TIME_ELAPSED, 1, &query);
    const GLuint program = glCreateProgram();  // programs and shaders share one name space
    LiveObjects live;
    const auto count = [](GLuint bound, auto isA) {
        int n = 0;
        for (GLuint name = 1; name < bound; ++name) n += isA(name) == GL_TRUE;
        return n;
    };
    live.textures = count(texture, glIsTexture);
    live.buffers = count(buffer, glIsBuffer);
    live.framebuffers = count(framebuffer, glIsFramebuffer);
    live.vertexArrays = count(vertexArray, glIsVertexArray);
    live.programs = count(program, glIsProgram);
    live.queries = count(query, glIsQuery);
    glDeleteTextures(1, &texture);
    glDeleteBuffers(1, &buffer);
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteVertexArrays(1, &vertexArray);
    glDeleteQueries(1, &query);
    glDeleteProgram(program);
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
    const int rounds = envInt("SHADOWLAB_SOAK_ROUNDS", 3);
    ASSERT_GE(rounds, 3) << "the resident-memory check needs two rounds before the one it checks";
    const int size = envInt("SHADOWLAB_SOAK_SIZE", 24);
    const LiveObjects before = liveObjects();
    const GpuMemoryStats gpuBefore = gpuMemory();
    std::vector<Scene> scenes;
    for (const std::string& name : testing::loadableScenes()) scenes.push_back(loadScene(name));
    ASSERT_GE(scenes.size(), 9u);
    std::vector<std::string> techniques, drawHeavy;
    for (const TechniqueDesc* d : allTechniques()) {
        if (d->id == "template") continue;  // the copy-me example is not soaked
        // ssv issues two draws per wedge (thousands a frame on plant): llvmpipe's threaded
        // rasterizer then keeps a varying amount of memory from round to round (0 to ~40 MB
        // measured, not growing; flat with LP_NUM_THREADS=0), so its rounds run after the
        // resident-memory rounds, checked for GL objects and GPU bytes exactly (below).
        (d->id == "ssv" ? drawHeavy : techniques).push_back(d->id);
    }
    ASSERT_GE(techniques.size(), 4u);
    ASSERT_EQ(drawHeavy.size(), 1u);

    {
        // One live renderer per scene, as a window keeps one, switched from technique to technique.
        std::vector<std::unique_ptr<Renderer>> renderers;
        for (const Scene& scene : scenes) {
            RenderOptions options;
            options.width = options.height = size;
            renderers.push_back(std::make_unique<Renderer>(scene, options));
        }
        LiveObjects firstLive;
        GpuMemoryStats firstGpu;
        long firstRss = 0;
        int frame = 0;
        for (int round = 0; round < rounds; ++round) {
            for (auto& renderer : renderers) {
                for (const std::string& technique : techniques) {
                    renderer->setTechnique(technique);
                    for (const auto& [key, value] : cheap(technique)) renderer->setParam(key, value);
                    for (int f = 0; f < frames; ++f, ++frame) {
                        // A live change as a window makes it: a resize every third frame.
                        if (f % 3 == 2) renderer->resize(size + (f % 2), size);
                        renderer->renderFrame(frame, {"image", "visibility"});
                    }
                }
                renderer->resize(size, size);
                renderer->setTechnique("hard");  // every round ends in the same configuration
                renderer->renderFrame(frame++, {"image", "visibility"});
            }
            glFinish();
            const LiveObjects live = liveObjects();
            const GpuMemoryStats gpu = gpuMemory();
            const long rss = residentKB();
            std::printf("[soak] round %d (%d frames per technique and scene): %s; counted GPU: %lld textures, %lld "
                        "buffers, %.1f MB; resident %.1f MB\n",
                        round, frames, describe(live).c_str(), (long long)gpu.textures, (long long)gpu.buffers,
                        gpu.totalBytes() / 1e6, rss / 1024.0);
            if (round == 0) {
                firstLive = live;
                firstGpu = gpu;
            }
            if (round == 1) firstRss = rss;  // resident memory's level: after the second round (above)
            if (round == 0) continue;
            EXPECT_EQ(live, firstLive) << "round " << round << ": " << describe(live) << " vs " << describe(firstLive);
            EXPECT_EQ(gpu.textures, firstGpu.textures) << "round " << round;
            EXPECT_EQ(gpu.buffers, firstGpu.buffers) << "round " << round;
            EXPECT_EQ(gpu.totalBytes(), firstGpu.totalBytes()) << "round " << round;
            // Resident memory, after malloc_trim: flat to 0.3 MB over 8 rounds when measured; allow
            // 4 MB (any leaked GL object is caught exactly above; a leak of one 24x24 float image
            // per frame would be 1.2 MB per technique and scene over a 500-frame round).
            // (Under AddressSanitizer freed memory waits in its quarantine, up to 256 MB, so resident
            // memory says nothing there; LeakSanitizer checks leaks instead.)
            if (!kAddressSanitizer && round >= 2)
                EXPECT_LE(rss - firstRss, 4 * 1024) << "round " << round << ": resident grew from " << firstRss / 1024
                                                     << " MB to " << rss / 1024 << " MB";
        }
        // The draw-heavy techniques, the same way, two rounds: every GL object and byte of the first
        // (its programs now cached) comes back in the second.
        LiveObjects heavyLive;
        GpuMemoryStats heavyGpu;
        for (int round = 0; round < 2; ++round) {
            for (auto& renderer : renderers) {
                for (const std::string& technique : drawHeavy) {
                    renderer->setTechnique(technique);
                    for (int f = 0; f < frames; ++f, ++frame) {
                        if (f % 3 == 2) renderer->resize(size + (f % 2), size);
                        renderer->renderFrame(frame, {"image", "visibility"});
                    }
                }
                renderer->resize(size, size);
                renderer->setTechnique("hard");
                renderer->renderFrame(frame++, {"image", "visibility"});
            }
            glFinish();
            const LiveObjects live = liveObjects();
            const GpuMemoryStats gpu = gpuMemory();
            if (round == 0) {
                heavyLive = live;
                heavyGpu = gpu;
                continue;
            }
            EXPECT_EQ(live, heavyLive) << "draw-heavy round " << round << ": " << describe(live) << " vs " << describe(heavyLive);
            EXPECT_EQ(gpu.textures, heavyGpu.textures) << "draw-heavy round " << round;
            EXPECT_EQ(gpu.totalBytes(), heavyGpu.totalBytes()) << "draw-heavy round " << round;
        }
    }
    // And with the renderers gone, nothing of theirs is left (the program cache stays).
    const LiveObjects after = liveObjects();
    EXPECT_EQ(after.textures, before.textures);
    EXPECT_EQ(after.buffers, before.buffers);
    EXPECT_EQ(after.framebuffers, before.framebuffers);
    EXPECT_EQ(gpuMemory().totalBytes(), gpuBefore.totalBytes());
}

}  // namespace
}  // namespace shadowlab

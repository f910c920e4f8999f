// The GPU features the core builds on (issue "Core, stage two", item 2): each test renders or
// computes something and checks the numbers against a CPU reference computed here independently.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "error.h"
#include "gl/util.h"
#include "support/gl_fixture.h"

namespace shadowlab {
namespace {

using testing::GLTest;

class GpuFeatures : public GLTest {
protected:
    // The tests share one context: leave it as GL's defaults for whoever runs next.
    void TearDown() override {
        PipelineState::fullscreen().apply();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glBindVertexArray(0);
        glUseProgram(0);
        GLTest::TearDown();
    }
};

// Deterministic values in [0, 1) (a 32-bit LCG), so failures reproduce.
std::vector<float> randomValues(size_t n, uint32_t seed) {
    std::vector<float> values(n);
    for (float& v : values) {
        seed = seed * 1664525u + 1013904223u;
        v = float(seed >> 8) / float(1u << 24);
    }
    return values;
}

// ---- formats ---------------------------------------------------------------------------------------
TEST(GpuFormats, TableIsConsistent) {
    const Format all[] = {Format::R32F,   Format::RG32F,   Format::RGBA32F, Format::R32UI,
                          Format::RG32UI, Format::RGBA32UI, Format::R32I,   Format::RGBA8,
                          Format::RGBA16F, Format::DEPTH32F, Format::DEPTH32F_STENCIL8};
    for (Format f : all) {
        EXPECT_EQ(formatFromGL(glInternalFormat(f)), f) << formatName(f);
        EXPECT_EQ(formatTexelBytes(f) % size_t(formatChannels(f)), 0u) << formatName(f);
    }
    EXPECT_STREQ(formatName(Format::DEPTH32F_STENCIL8), "DEPTH32F_STENCIL8");
    EXPECT_EQ(formatTexelBytes(Format::DEPTH32F_STENCIL8), 8u);
    EXPECT_EQ(formatTexelBytes(Format::RGBA16F), 8u);
    EXPECT_EQ(formatChannels(Format::RG32UI), 2);
    EXPECT_TRUE(formatIsInteger(Format::R32I));
    EXPECT_FALSE(formatIsInteger(Format::RGBA8));
    EXPECT_TRUE(formatIsDepth(Format::DEPTH32F));
    EXPECT_FALSE(formatHasStencil(Format::DEPTH32F));
    EXPECT_TRUE(formatHasStencil(Format::DEPTH32F_STENCIL8));
    EXPECT_EQ(glInternalFormat(Format::DEPTH32F), GLenum(GL_DEPTH_COMPONENT32F));
    EXPECT_EQ(fullMipLevels(37, 23), 6);  // 37x23, 18x11, 9x5, 4x2, 2x1, 1x1
    EXPECT_EQ(fullMipLevels(1, 1), 1);
    EXPECT_EQ(fullMipLevels(16, 1), 5);
}

// ---- mip levels and read-back ------------------------------------------------------------------
// A min/max pyramid built level by level by a compute shader equals the CPU's, on odd sizes too.
TEST_F(GpuFeatures, MinMaxPyramidMatchesCpu) {
    const ShaderProgram& program = programCache().compute("tests/minmax_pyramid.comp");
    for (glm::ivec2 size : {glm::ivec2(37, 23), glm::ivec2(16, 16), glm::ivec2(1, 9)}) {
        SCOPED_TRACE(std::to_string(size.x) + "x" + std::to_string(size.y));
        Texture pyramid = Texture::create2D(size.x, size.y, Format::RG32F, 0);
        ASSERT_EQ(pyramid.levels(), fullMipLevels(size.x, size.y));
        // Level 0: min = max = the value. CPU levels are kept in GL row order (row 0 at the bottom).
        std::vector<float> values = randomValues(size_t(size.x) * size.y, 17u + uint32_t(size.x));
        std::vector<std::vector<glm::vec2>> cpu(1);
        Image level0(size.x, size.y, 2);
        for (int y = 0; y < size.y; ++y)
            for (int x = 0; x < size.x; ++x) {
                float v = values[size_t(y) * size.x + x];
                cpu[0].push_back(glm::vec2(v));
                level0.at(x, size.y - 1 - y, 0) = v;
                level0.at(x, size.y - 1 - y, 1) = v;
            }
        uploadTexture(pyramid, 0, 0, level0);
        for (int k = 1; k < pyramid.levels(); ++k) {
            int sw = pyramid.width(k - 1), sh = pyramid.height(k - 1);
            int w = pyramid.width(k), h = pyramid.height(k);
            ASSERT_EQ(w, std::max(1, size.x >> k));
            std::vector<glm::vec2> level(size_t(w) * h);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    int x1 = x == w - 1 ? sw - 1 : std::min(2 * x + 1, sw - 1);
                    int y1 = y == h - 1 ? sh - 1 : std::min(2 * y + 1, sh - 1);
                    glm::vec2 range(1e30f, -1e30f);
                    for (int sy = 2 * y; sy <= y1; ++sy)
                        for (int sx = 2 * x; sx <= x1; ++sx) {
                            glm::vec2 t = cpu[k - 1][size_t(sy) * sw + sx];
                            range = glm::vec2(std::min(range.x, t.x), std::max(range.y, t.y));
                        }
                    level[size_t(y) * w + x] = range;
                }
            cpu.push_back(level);
            bindImage(0, pyramid, k - 1, GL_READ_ONLY);
            bindImage(1, pyramid, k, GL_WRITE_ONLY);
            program.dispatch(GLuint((w + 7) / 8), GLuint((h + 7) / 8));
            memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);  // level k is the next dispatch's source
        }
        memoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
        for (int k = 0; k < pyramid.levels(); ++k) {
            Image got = readTextureLevel(pyramid, k);
            ASSERT_EQ(got.width, pyramid.width(k));
            ASSERT_EQ(got.height, pyramid.height(k));
            ASSERT_EQ(got.channels, 2);
            for (int y = 0; y < got.height; ++y)
                for (int x = 0; x < got.width; ++x) {
                    glm::vec2 want = cpu[k][size_t(y) * got.width + x];
                    ASSERT_EQ(got.at(x, got.height - 1 - y, 0), want.x) << "level " << k << " x " << x << " y " << y;
                    ASSERT_EQ(got.at(x, got.height - 1 - y, 1), want.y) << "level " << k << " x " << x << " y " << y;
                }
        }
    }
}

// Every level of RGBA32F and RG32F (2D and array) textures reads back what was uploaded, top row first.
TEST_F(GpuFeatures, ReadTextureLevelOfFloatLevelsAndLayers) {
    Texture rgba = Texture::create2D(5, 3, Format::RGBA32F, 0);
    ASSERT_EQ(rgba.levels(), 3);  // 5x3, 2x1, 1x1
    Texture rgArray = Texture::createArray(6, 4, 2, Format::RG32F, 2);
    std::vector<std::pair<const Texture*, std::pair<int, int>>> targets;
    for (int k = 0; k < rgba.levels(); ++k) targets.push_back({&rgba, {k, 0}});
    for (int k = 0; k < 2; ++k)
        for (int layer = 0; layer < 2; ++layer) targets.push_back({&rgArray, {k, layer}});
    std::vector<Image> uploaded;
    uint32_t seed = 5;
    for (auto& [texture, where] : targets) {
        auto [level, layer] = where;
        Image image(texture->width(level), texture->height(level), formatChannels(texture->textureFormat()));
        image.data = randomValues(image.data.size(), ++seed);
        uploadTexture(*texture, level, layer, image);
        uploaded.push_back(image);
    }
    for (size_t i = 0; i < targets.size(); ++i) {
        auto [level, layer] = targets[i].second;
        Image got = readTextureLevel(*targets[i].first, level, layer);
        EXPECT_EQ(got.data, uploaded[i].data) << targets[i].first->formatName() << " level " << level << " layer " << layer;
    }
    // The original read-back agrees with level 0.
    EXPECT_EQ(readTexture(rgba, 4).data, uploaded[0].data);
    EXPECT_EQ(rgArray.width(1), 3);
    EXPECT_EQ(rgArray.height(1), 2);
    EXPECT_TRUE(rgArray.isArray());
    EXPECT_EQ(rgArray.layers(), 2);
    EXPECT_EQ(rgArray.bytes(), size_t(8 * 2 * (6 * 4 + 3 * 2)));
    EXPECT_STREQ(rgArray.formatName().c_str(), "RG32F");

    // DEPTH32F round-trips exactly; RGBA8 stores k / 255 and gives it back as a float.
    Texture depth = Texture::create2D(4, 2, Format::DEPTH32F);
    Image depthImage(4, 2, 1);
    depthImage.data = randomValues(depthImage.data.size(), 41);
    uploadTexture(depth, 0, 0, depthImage);
    EXPECT_EQ(readTextureLevel(depth).data, depthImage.data);
    Texture bytes = Texture::create2D(4, 2, Format::RGBA8);
    Image byteImage(4, 2, 4);
    for (size_t i = 0; i < byteImage.data.size(); ++i) byteImage.data[i] = float(i * 7 % 256) / 255.0f;
    uploadTexture(bytes, 0, 0, byteImage);
    Image byteGot = readTextureLevel(bytes);
    for (size_t i = 0; i < byteImage.data.size(); ++i) ASSERT_NEAR(byteGot.data[i], byteImage.data[i], 1e-6f) << i;
}

// ---- array layers through framebuffers ---------------------------------------------------------
TEST_F(GpuFeatures, ArrayLayersWrittenThroughFramebuffers) {
    const int w = 8, h = 4, layers = 3;
    Texture array = Texture::createArray(w, h, layers, Format::RGBA32F, 2);
    const ShaderProgram& program = programCache().get("common/fullscreen.vert", "tests/pixel_pattern.frag");
    program.use();
    PipelineState::fullscreen().apply();
    for (int layer = 0; layer < layers; ++layer) {
        for (int level = 0; level < 2; ++level) {
            Framebuffer fbo({{&array, level, layer}}, std::nullopt);
            fbo.bind(array.width(level), array.height(level));
            program.set("color", glm::vec4(0.0f, 0.0f, float(layer + 1), float(10 * (level + 1))));
            drawFullscreenTriangle();
        }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    for (int layer = 0; layer < layers; ++layer)
        for (int level = 0; level < 2; ++level) {
            Image got = readTextureLevel(array, level, layer);
            ASSERT_EQ(got.width, array.width(level));
            for (int y = 0; y < got.height; ++y)
                for (int x = 0; x < got.width; ++x) {
                    int glRow = got.height - 1 - y;
                    ASSERT_EQ(got.at(x, y, 0), float(x)) << "layer " << layer << " level " << level;
                    ASSERT_EQ(got.at(x, y, 1), float(glRow)) << "layer " << layer << " level " << level;
                    ASSERT_EQ(got.at(x, y, 2), float(layer + 1));
                    ASSERT_EQ(got.at(x, y, 3), float(10 * (level + 1)));
                }
        }
}

// FramebufferCache (gl/texture.h), what every pass keeps: the same framebuffer while its attachments
// stay the same, a new one (built before the old is deleted, so its name differs) as soon as a
// texture, the colours' order, the depth, a level or a layer changes; GL reports the new attachment.
TEST_F(GpuFeatures, FramebufferCacheRebuildsExactlyWhenAnAttachmentChanges) {
    Texture a = Texture::create2D(8, 8, Format::R32F), b = Texture::create2D(8, 8, Format::R32F);
    Texture depth = Texture::create2D(8, 8, Format::DEPTH32F);
    Texture array = Texture::createArray(8, 8, 2, Format::R32F, 2);
    auto attached = [](const Framebuffer& f, GLenum point, GLenum what) {
        GLint v = -1;
        glGetNamedFramebufferAttachmentParameteriv(f.id(), point, what, &v);
        return v;
    };
    FramebufferCache cache;
    GLuint last = cache.get({&a}, nullptr).id();
    EXPECT_EQ(cache.get({&a}, nullptr).id(), last);  // nothing changed: no rebuild
    auto changes = [&](const Framebuffer& f, const char* what) {
        EXPECT_NE(f.id(), last) << what;
        last = f.id();
        return &f;
    };
    const Framebuffer* f = changes(cache.get({&b}, nullptr), "another texture");
    EXPECT_EQ(attached(*f, GL_COLOR_ATTACHMENT0, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME), GLint(b.id()));
    f = changes(cache.get({&b}, &depth), "a depth attachment");
    EXPECT_EQ(attached(*f, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME), GLint(depth.id()));
    changes(cache.get({&a, &b}, &depth), "a second colour");
    f = changes(cache.get({&b, &a}, &depth), "the colours' order");
    EXPECT_EQ(attached(*f, GL_COLOR_ATTACHMENT1, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME), GLint(a.id()));
    EXPECT_EQ(cache.get({&b, &a}, &depth).id(), last);
    changes(cache.get({{&array, 0, 0}}, std::nullopt), "an array's layer 0");
    f = changes(cache.get({{&array, 0, 1}}, std::nullopt), "layer 1");
    EXPECT_EQ(attached(*f, GL_COLOR_ATTACHMENT0, GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LAYER), 1);
    f = changes(cache.get({{&array, 1, 1}}, std::nullopt), "level 1");
    EXPECT_EQ(attached(*f, GL_COLOR_ATTACHMENT0, GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LEVEL), 1);
    EXPECT_EQ(cache.get({{&array, 1, 1}}, std::nullopt).id(), last);
}

// ---- integer images ------------------------------------------------------------------------------
TEST_F(GpuFeatures, IntegerImagesReadBackExactly) {
    const int w = 13, h = 7;
    Texture single = Texture::create2D(w, h, Format::R32UI);
    Texture quad = Texture::create2D(w, h, Format::RGBA32UI);
    Texture signedValues = Texture::create2D(w, h, Format::R32I);
    const ShaderProgram& program = programCache().compute("tests/write_integers.comp");
    program.set("size", glm::uvec2(w, h));
    bindImage(0, single, 0, GL_WRITE_ONLY);
    bindImage(1, quad, 0, GL_WRITE_ONLY);
    bindImage(2, signedValues, 0, GL_WRITE_ONLY);
    program.dispatch((w + 7) / 8, (h + 7) / 8);
    memoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);

    std::vector<uint32_t> singleRaw = readTextureUint(single);
    std::vector<uint32_t> quadRaw = readTextureUint(quad);
    std::vector<uint32_t> signedRaw = readTextureUint(signedValues);
    Image singleImage = readTextureLevel(single), quadImage = readTextureLevel(quad);
    Image signedImage = readTextureLevel(signedValues);
    ASSERT_EQ(quadImage.channels, 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            uint32_t i = uint32_t(x + y * w);
            uint32_t want = i == 0 ? 0xFFFFFFu : (i * 123456u) & 0xFFFFFFu;
            ASSERT_EQ(singleRaw[i], want);
            ASSERT_EQ(quadRaw[4 * i + 0], uint32_t(x));
            ASSERT_EQ(quadRaw[4 * i + 1], uint32_t(y));
            ASSERT_EQ(quadRaw[4 * i + 2], 123456u);
            ASSERT_EQ(quadRaw[4 * i + 3], 0xFFFFFFu - i);
            ASSERT_EQ(int32_t(signedRaw[i]), -1000 * int32_t(i) - 1);
            // Float read-back: exact below 2^24, top row first.
            int top = h - 1 - y;
            ASSERT_EQ(singleImage.at(x, top), float(want));
            ASSERT_EQ(quadImage.at(x, top, 3), float(0xFFFFFFu - i));
            ASSERT_EQ(quadImage.at(x, top, 2), 123456.0f);
            ASSERT_EQ(signedImage.at(x, top), float(-1000 * int32_t(i) - 1));
        }
    EXPECT_EQ(singleImage.at(0, h - 1), 16777215.0f);
}

// ---- stencil, per-face ops -----------------------------------------------------------------------
// Shadow-volume counting: front faces increment, back faces decrement (wrapping), on one
// DEPTH32F_STENCIL8 attachment. Two front-facing full-screen triangles and three back-facing passes
// over the left half leave 2 on the right and 2 - 3 = -1 = 255 on the left.
TEST_F(GpuFeatures, StencilCountsFrontAndBackFacesSeparately) {
    const int size = 16;
    Texture color = Texture::create2D(size, size, Format::R32F);
    Texture depthStencil = Texture::create2D(size, size, Format::DEPTH32F_STENCIL8);
    Framebuffer fbo({{&color}}, Framebuffer::Attachment{&depthStencil});
    const glm::vec2 vertices[] = {
        {-1, -1}, {3, -1}, {-1, 3},                 // counter-clockwise (front), whole viewport
        {-1, -1}, {-1, 1}, {0, -1}, {0, -1}, {-1, 1}, {0, 1},  // clockwise (back), left half
    };
    Buffer vertexBuffer(sizeof(vertices), vertices);
    VertexArray vao;
    vao.bindVertexBuffer(0, vertexBuffer, 0, sizeof(glm::vec2));
    vao.attribute(0, 0, 2, GL_FLOAT, 0);
    EXPECT_EQ(vao.bytes(), 0u);

    fbo.bind(size, size);
    PipelineState::fullscreen().apply();  // clears write every bit of colour, depth and stencil
    const float zero = 0.0f, clearDepth = 0.25f;
    glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, &zero);
    glClearNamedFramebufferfi(fbo.id(), GL_DEPTH_STENCIL, 0, clearDepth, 0);

    PipelineState count;
    count.stencilTest = true;
    count.front.depthPass = GL_INCR_WRAP;
    count.back.depthPass = GL_DECR_WRAP;
    count.colorMask[0] = count.colorMask[1] = count.colorMask[2] = count.colorMask[3] = false;
    count.apply();
    const ShaderProgram& program = programCache().get("tests/position.vert", "tests/constant.frag");
    program.use();
    program.set("color", glm::vec4(1.0f));
    vao.bind();
    for (int i = 0; i < 2; ++i) glDrawArrays(GL_TRIANGLES, 0, 3);
    for (int i = 0; i < 3; ++i) glDrawArrays(GL_TRIANGLES, 3, 6);
    PipelineState::fullscreen().apply();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    std::vector<uint8_t> stencil = readStencil(depthStencil);
    ASSERT_EQ(stencil.size(), size_t(size * size));
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) ASSERT_EQ(int(stencil[size_t(y) * size + x]), x < size / 2 ? 255 : 2) << x << "," << y;
    Image depth = readTextureLevel(depthStencil);
    EXPECT_EQ(depth.channels, 1);
    EXPECT_TRUE(std::all_of(depth.data.begin(), depth.data.end(), [&](float d) { return d == clearDepth; }));
    Image written = readTextureLevel(color);  // colour mask off: the colour stayed cleared
    EXPECT_TRUE(std::all_of(written.data.begin(), written.data.end(), [](float c) { return c == 0.0f; }));
}

// ---- compaction and indirect dispatch --------------------------------------------------------------
// Pixels above a threshold are compacted with an atomic counter; a one-thread pass turns the count
// into a DispatchIndirectCommand; the indirect dispatch then runs over the compacted pixels alone.
TEST_F(GpuFeatures, CompactionFeedsIndirectDispatch) {
    const int w = 64, h = 48;
    const float threshold = 0.7f;
    const GLuint groupSize = 64;
    Texture values = Texture::create2D(w, h, Format::R32F);
    Texture results = Texture::create2D(w, h, Format::R32F);
    Image valueImage(w, h, 1);
    valueImage.data = randomValues(valueImage.data.size(), 99);
    uploadTexture(values, 0, 0, valueImage);
    const float untouched = -1.0f;
    glClearTexImage(results.id(), 0, GL_RED, GL_FLOAT, &untouched);

    Buffer counter(sizeof(uint32_t)), compacted(sizeof(uint32_t) * w * h), work(2 * sizeof(uint32_t));
    Buffer dispatchArgs(sizeof(DispatchIndirectCommand));
    counter.clear();
    work.clear();

    const ShaderProgram& compact = programCache().compute("tests/compact_above_threshold.comp");
    compact.set("threshold", threshold);
    bindImage(0, values, 0, GL_READ_ONLY);
    counter.bindBase(GL_ATOMIC_COUNTER_BUFFER, 0);
    bindStorage(1, compacted);
    compact.dispatch(w / 8, h / 8);
    memoryBarrier(GL_ATOMIC_COUNTER_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);

    const ShaderProgram& writeArgs = programCache().compute("tests/write_dispatch_args.comp");
    writeArgs.set("groupSize", unsigned(groupSize));
    bindStorage(2, counter);
    bindStorage(3, dispatchArgs);
    writeArgs.dispatch(1);
    memoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);

    const ShaderProgram& process = programCache().compute("tests/process_compacted.comp");
    bindImage(1, results, 0, GL_WRITE_ONLY);
    bindStorage(4, work);
    process.dispatchIndirect(dispatchArgs);
    memoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

    // CPU reference, in GL row order.
    std::vector<uint32_t> cpuPixels;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (valueImage.at(x, h - 1 - y) > threshold) cpuPixels.push_back(uint32_t(x) | (uint32_t(y) << 16));
    const uint32_t n = uint32_t(cpuPixels.size());
    ASSERT_GT(n, 0u);
    ASSERT_LT(n, uint32_t(w * h));
    EXPECT_EQ(counter.read<uint32_t>()[0], n);
    std::vector<uint32_t> args = dispatchArgs.read<uint32_t>();
    EXPECT_EQ(args, (std::vector<uint32_t>{(n + groupSize - 1) / groupSize, 1, 1}));
    std::vector<uint32_t> gpuPixels = compacted.read<uint32_t>();
    gpuPixels.resize(n);
    std::sort(gpuPixels.begin(), gpuPixels.end());
    std::sort(cpuPixels.begin(), cpuPixels.end());
    EXPECT_EQ(gpuPixels, cpuPixels);
    std::vector<uint32_t> ran = work.read<uint32_t>();
    EXPECT_EQ(ran[0], n);                                    // invocations that had a pixel
    EXPECT_EQ(ran[1], (n + groupSize - 1) / groupSize);      // groups: only as many as the count asked
    Image got = readTextureLevel(results);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float v = valueImage.at(x, y);
            ASSERT_EQ(got.at(x, y), v > threshold ? 2.0f * v + 1.0f : untouched) << x << "," << y;
        }
}

// ---- indirect draw -------------------------------------------------------------------------------
// A compute shader writes the vertex count of a DrawArraysIndirectCommand: one full-screen triangle
// per value above a threshold. Additive blending then leaves that number in every pixel.
TEST_F(GpuFeatures, IndirectDrawCountFromCompute) {
    const float threshold = 0.5f;
    std::vector<float> values = randomValues(200, 3);
    Buffer valueBuffer(values.size() * sizeof(float), values.data());
    DrawArraysIndirectCommand initial{0, 1, 0, 0};
    Buffer drawArgs(sizeof(initial), &initial);
    const ShaderProgram& count = programCache().compute("tests/count_draw_vertices.comp");
    count.set("threshold", threshold);
    bindStorage(0, valueBuffer);
    bindStorage(1, drawArgs);
    count.dispatch(GLuint((values.size() + 63) / 64));
    memoryBarrier(GL_COMMAND_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

    uint32_t triangles = uint32_t(std::count_if(values.begin(), values.end(), [&](float v) { return v > threshold; }));
    ASSERT_GT(triangles, 0u);
    std::vector<uint32_t> args = drawArgs.read<uint32_t>();
    EXPECT_EQ(args, (std::vector<uint32_t>{3 * triangles, 1, 0, 0}));

    Texture target = Texture::create2D(8, 8, Format::R32F);
    Framebuffer fbo({{&target}}, std::nullopt);
    fbo.bind(8, 8);
    const float zero = 0.0f;
    glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, &zero);
    PipelineState::additiveBlend().apply();
    const ShaderProgram& draw = programCache().get("tests/stacked_triangles.vert", "tests/constant.frag");
    draw.use();
    draw.set("color", glm::vec4(1.0f));
    VertexArray empty;  // positions come from gl_VertexID
    empty.bind();
    drawArraysIndirect(GL_TRIANGLES, drawArgs);
    Image got = readTextureLevel(target);
    for (float v : got.data) ASSERT_EQ(v, float(triangles));
}

// ---- uniform name check ----------------------------------------------------------------------------
TEST_F(GpuFeatures, UniformNameCheck) {
    ASSERT_TRUE(uniformNameCheck()) << "the GL fixture turns the check on";
    const ShaderProgram& program = programCache().get("common/fullscreen.vert", "tests/uniform_check.frag");
    // An undeclared name (a typo) throws and names the files and the uniform.
    try {
        program.set("colour", glm::vec4(1.0f));
        FAIL() << "an undeclared uniform was accepted";
    } catch (const InternalError& e) {
        std::string message = e.what();
        EXPECT_NE(message.find("'colour'"), std::string::npos) << message;
        EXPECT_NE(message.find("common/fullscreen.vert + tests/uniform_check.frag"), std::string::npos) << message;
    }
    EXPECT_THROW(program.set("commentedOut", 1.0f), InternalError);
    EXPECT_THROW(program.set("alsoCommentedOut", 1.0f), InternalError);
    EXPECT_THROW(program.set("lightPositionsX[0]", glm::vec3(0.0f)), InternalError);
    // Declared but removed by the compiler: a no-op, not an error.
    EXPECT_EQ(program.location("unusedScale"), -1);
    EXPECT_NO_THROW(program.set("unusedScale", 2.0f));
    EXPECT_NO_THROW(program.set("onlyUnderIfdef", 2.0f));  // its #ifdef is off
    // Array elements are checked by their base name; the second declarator of a line counts.
    EXPECT_NO_THROW(program.set("lightPositions[3]", glm::vec3(0.5f, 0.25f, 0.125f)));
    EXPECT_NO_THROW(program.set("lightTint", glm::vec3(10.0f, 20.0f, 30.0f)));
    // The mat3, ivec2 and uint setters reach the shader.
    glm::mat3 tint(1.0f);
    tint[0][1] = 2.0f;  // column 0, row 1: tint * (1, 0, 0) = (1, 2, 0)
    program.set("tint", tint);
    program.set("color", glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    program.set("shift", glm::ivec2(3, 4));
    program.set("count", 5u);
    Texture target = Texture::create2D(1, 1, Format::RGBA32F);
    Framebuffer fbo({{&target}}, std::nullopt);
    fbo.bind(1, 1);
    program.use();
    drawFullscreenTriangle();
    Image got = readTextureLevel(target);
    EXPECT_EQ(got.data, (std::vector<float>{11.5f, 22.25f, 30.125f, 534.0f}));
    // With the check off, an undeclared name is ignored as GL ignores location -1.
    setUniformNameCheck(false);
    EXPECT_NO_THROW(program.set("colour", glm::vec4(1.0f)));
    setUniformNameCheck(true);
}

TEST(GpuUniformDeclarations, ScannerFindsEveryDeclarator) {
    std::set<std::string> names = declaredUniformNames(
        "layout(binding = 0) uniform sampler2D shadowMap;\n"
        "uniform highp vec3 a[MAX_LIGHTS], b = vec3(1.0, 2.0, 3.0), c[2];\n"
        "uniform float[3] weights;\n"
        "uniform Block { float insideBlock; } block;\n"
        "/* uniform float x; */ // uniform float y;\n"
        "float uniformish; uniform int last;");
    EXPECT_EQ(names, (std::set<std::string>{"shadowMap", "a", "b", "c", "weights", "last"}));
}

// A compute shader goes through the include expander: errors name the included file and line.
TEST_F(GpuFeatures, ComputeCompileErrorNamesIncludedFile) {
    int errorsBefore = glDebugState().errors;
    std::string message;
    try {
        ShaderProgram::compute("tests/broken.comp");
    } catch (const InternalError& e) {
        message = e.what();
    }
    glDebugState().errors = errorsBefore;  // KHR_debug reports the compile error too: it was the point
    EXPECT_NE(message.find("shader tests/broken.comp does not compile"), std::string::npos) << message;
    EXPECT_NE(message.find("tests/broken_include.glsl:3("), std::string::npos) << message;
}

// ---- program cache ---------------------------------------------------------------------------------
TEST_F(GpuFeatures, ProgramCacheCompilesEachProgramOnce) {
    ProgramCache& cache = programCache();
    EXPECT_EQ(&cache, &programCache());
    int compiled = cache.compileCount();
    size_t size = cache.size();
    const ShaderProgram& a = cache.get("common/fullscreen.vert", "tests/constant.frag", {"CACHE_TEST_A"});
    const ShaderProgram& b = cache.get("common/fullscreen.vert", "tests/constant.frag", {"CACHE_TEST_A"});
    EXPECT_EQ(&a, &b);
    EXPECT_EQ(cache.compileCount(), compiled + 1);
    const ShaderProgram& c = cache.get("common/fullscreen.vert", "tests/constant.frag", {"CACHE_TEST_B"});
    EXPECT_NE(&a, &c);
    const ShaderProgram& d = cache.compute("tests/minmax_pyramid.comp", {"CACHE_TEST_A"});
    const ShaderProgram& e = cache.compute("tests/minmax_pyramid.comp", {"CACHE_TEST_A"});
    EXPECT_EQ(&d, &e);
    EXPECT_EQ(cache.compileCount(), compiled + 3);
    EXPECT_EQ(cache.size(), size + 3);
}

// ---- pipeline state --------------------------------------------------------------------------------
TEST_F(GpuFeatures, PipelineStateApplyLeavesNothingBehind) {
    PipelineState busy = PipelineState::additiveBlend();
    busy.depthTest = true;
    busy.depthFunc = GL_GREATER;
    busy.depthWrite = false;
    busy.stencilTest = true;
    busy.back.func = GL_EQUAL;
    busy.back.depthFail = GL_INCR_WRAP;
    busy.cull = true;
    busy.cullFace = GL_FRONT;
    busy.colorMask[1] = false;
    busy.clipZeroToOne = true;
    busy.depthClamp = true;
    busy.apply();
    auto integer = [](GLenum what) {
        GLint v = 0;
        glGetIntegerv(what, &v);
        return v;
    };
    EXPECT_TRUE(glIsEnabled(GL_BLEND));
    EXPECT_TRUE(glIsEnabled(GL_DEPTH_CLAMP));
    EXPECT_EQ(integer(GL_STENCIL_BACK_FUNC), GL_EQUAL);
    EXPECT_EQ(integer(GL_STENCIL_BACK_PASS_DEPTH_FAIL), GL_INCR_WRAP);
    EXPECT_EQ(integer(GL_CLIP_DEPTH_MODE), GL_ZERO_TO_ONE);

    PipelineState::fullscreen().apply();
    for (GLenum capability : {GL_BLEND, GL_DEPTH_TEST, GL_STENCIL_TEST, GL_CULL_FACE, GL_DEPTH_CLAMP})
        EXPECT_FALSE(glIsEnabled(capability)) << capability;
    EXPECT_EQ(integer(GL_DEPTH_FUNC), GL_LESS);
    EXPECT_EQ(integer(GL_DEPTH_WRITEMASK), GL_TRUE);
    EXPECT_EQ(integer(GL_STENCIL_BACK_FUNC), GL_ALWAYS);
    EXPECT_EQ(integer(GL_STENCIL_BACK_PASS_DEPTH_FAIL), GL_KEEP);
    EXPECT_EQ(integer(GL_BLEND_SRC_RGB), GL_ONE);
    EXPECT_EQ(integer(GL_BLEND_DST_RGB), GL_ZERO);
    EXPECT_EQ(integer(GL_CULL_FACE_MODE), GL_BACK);
    EXPECT_EQ(integer(GL_CLIP_DEPTH_MODE), GL_NEGATIVE_ONE_TO_ONE);
    GLboolean mask[4] = {GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE};
    glGetBooleanv(GL_COLOR_WRITEMASK, mask);
    for (GLboolean m : mask) EXPECT_EQ(m, GL_TRUE);

    nlohmann::json reversed = PipelineState::depthGreaterReversed().describe();
    EXPECT_EQ(reversed["depthFunc"], "GL_GREATER");
    EXPECT_EQ(reversed["clipZeroToOne"], true);
    EXPECT_EQ(busy.describe()["stencilBack"]["depthFail"], "GL_INCR_WRAP");
    EXPECT_EQ(PipelineState::additiveBlend().describe()["blendDst"], "GL_ONE");
}

// ---- memory counters -------------------------------------------------------------------------------
TEST_F(GpuFeatures, GpuMemoryCountersReturnAfterObjectsDie) {
    const GpuMemoryStats before = gpuMemory();
    {
        Texture pyramid = Texture::create2D(37, 23, Format::RG32F, 0);
        Texture array = Texture::createArray(8, 8, 3, Format::RGBA16F, 2);
        Texture old(4, 4, GL_R32F);  // the original constructor counts too
        Buffer buffer(1000);
        const size_t pyramidBytes = 8 * (37 * 23 + 18 * 11 + 9 * 5 + 4 * 2 + 2 * 1 + 1 * 1);
        EXPECT_EQ(pyramid.bytes(), pyramidBytes);
        EXPECT_EQ(array.bytes(), size_t(8 * 3 * (64 + 16)));
        GpuMemoryStats during = gpuMemory();
        EXPECT_EQ(during.textures, before.textures + 3);
        EXPECT_EQ(during.textureBytes, before.textureBytes + int64_t(pyramidBytes + array.bytes() + 64));
        EXPECT_EQ(during.buffers, before.buffers + 1);
        EXPECT_EQ(during.bufferBytes, before.bufferBytes + 1000);

        Texture moved = std::move(pyramid);  // a move counts nothing
        Buffer movedBuffer = std::move(buffer);
        EXPECT_EQ(gpuMemory().textureBytes, during.textureBytes);
        EXPECT_EQ(gpuMemory().bufferBytes, during.bufferBytes);
        moved = std::move(old);  // the pyramid is released by the assignment
        EXPECT_EQ(gpuMemory().textures, before.textures + 2);
        EXPECT_EQ(gpuMemory().textureBytes, during.textureBytes - int64_t(pyramidBytes));
        movedBuffer = Buffer(24);
        EXPECT_EQ(gpuMemory().bufferBytes, before.bufferBytes + 24);
    }
    const GpuMemoryStats after = gpuMemory();
    EXPECT_EQ(after.textures, before.textures);
    EXPECT_EQ(after.textureBytes, before.textureBytes);
    EXPECT_EQ(after.buffers, before.buffers);
    EXPECT_EQ(after.bufferBytes, before.bufferBytes);
}

}  // namespace
}  // namespace shadowlab

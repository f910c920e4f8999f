// `ssv`: soft shadow volumes with penumbra wedges (assarsson2004 slides; Assarsson and
// Akenine-Moeller 2003 for what the slides leave out). Four passes:
//  1. silhouettes (CPU): silhouette edges from the light centre, the hard shadow volume and one
//     penumbra wedge per edge (ssv.h, geometry.cpp), as meshes;
//  2. hard_volumes: the camera's depth from the G-buffer, then the volume counted in the stencil
//     with z-fail, capped, under an infinite far plane; the count read into a float image;
//  3. wedges: per wedge, the stencil culling of the slides (the wedge's own z-fail count marks the
//     pixels whose point lies inside it), then its back faces, where marked, add the edge's signed
//     coverage into a float V-buffer (additive blending);
//  4. visibility: count x light area + the coverages, as v, times the light's front fraction.
#include "ssv/ssv.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/buffer.h"
#include "gl/texture.h"
#include "gl/util.h"
#include "graph/frame.h"
#include "hsm/hsm.h"
#include "shared/shared.h"
#include "visibility/shadow_map.h"

namespace shadowlab {

namespace {

ResourceDesc meshResource(const std::string& name, const std::string& doc) {
    ResourceDesc d;
    d.name = name;
    d.kind = ResourceKind::Mesh;
    d.doc = doc;
    return d;
}

// Where the wedges' bottom planes lie: beyond every point of the scene seen from the light.
float wedgeFarDistance(const Bounds& bounds, const glm::vec3& centre) {
    float far = 0.0f;
    for (int k = 0; k < 8; ++k) {
        glm::vec3 corner((k & 1) ? bounds.hi.x : bounds.lo.x, (k & 2) ? bounds.hi.y : bounds.lo.y,
                         (k & 4) ? bounds.hi.z : bounds.lo.z);
        far = std::max(far, glm::length(corner - centre));
    }
    return 1.05f * far + 1e-3f;
}

float capOffsetFor(const Bounds& bounds) { return 2e-5f * glm::length(bounds.hi - bounds.lo) + 1e-6f; }

// The camera's projection with its far plane at infinity (Everitt and Kilgard 2002), nudged by
// epsilon so that points at infinity land just inside the far clip plane rather than on it.
glm::mat4 infiniteClipFromView(const Camera& camera, float aspect) {
    const float f = 1.0f / std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
    const float eps = 1e-6f;
    glm::mat4 m(0.0f);
    m[0][0] = f / aspect;
    m[1][1] = f;
    m[2][2] = eps - 1.0f;
    m[2][3] = -1.0f;
    m[3][2] = (eps - 2.0f) * camera.nearPlane;
    return m;
}

// The V-buffer at a reduced resolution (parameter vbuffer_divisor k; the slides' load balancing,
// "scale the size of the output V-buffer"): texel i of the reduced buffer is the frame's pixel
// g = k i + floor(k / 2), and the hard volumes and wedges are rasterized in a viewport of the reduced
// size with the projection moved by a fraction of a pixel so that each texel's ray passes through
// the centre of its pixel g (its depth and its G-buffer point are then that pixel's, exactly). k = 1
// is the frame itself (the adjustment is the identity).
struct VBuffer {
    int k = 1, width = 1, height = 1;
    glm::mat4 clipAdjust{1.0f};  // clip space of the frame -> clip space of the reduced viewport
};
VBuffer vbufferOf(PassContext& ctx) {
    VBuffer v;
    v.k = std::max(1, ctx.paramInt("vbuffer_divisor"));
    const int w = ctx.width(), h = ctx.height(), k = v.k;
    v.width = std::max(1, (w - 1 - k / 2) / k + 1);
    v.height = std::max(1, (h - 1 - k / 2) / k + 1);
    const double d = (k % 2 == 0) ? 0.5 : 0.0;  // full-frame pixels between texel i's natural ray and pixel g's centre
    const double ax = double(w) / (double(k) * v.width), ay = double(h) / (double(k) * v.height);
    v.clipAdjust[0][0] = float(ax);
    v.clipAdjust[1][1] = float(ay);
    v.clipAdjust[3][0] = float(ax - 1.0 - 2.0 * d / (double(k) * v.width));
    v.clipAdjust[3][1] = float(ay - 1.0 - 2.0 * d / (double(k) * v.height));
    return v;
}
// The reduced viewport. (The passes that draw into it run whole, never in refineFrame's bands:
// PassDesc::wholeFrame.)
class VBufferViewport {
public:
    explicit VBufferViewport(const VBuffer& v) { glViewport(0, 0, v.width, v.height); }
};

// A vertex stream of vec4s (attribute 0) that grows as needed.
class Vec4Stream {
public:
    void upload(const std::vector<glm::vec4>& data) {
        const size_t bytes = std::max<size_t>(16, data.size() * sizeof(glm::vec4));
        if (buffer_.bytes() < bytes) {
            buffer_ = Buffer(bytes * 2);
            vao_.bindVertexBuffer(0, buffer_, 0, sizeof(glm::vec4));
            vao_.attribute(0, 0, 4, GL_FLOAT, 0);
        }
        if (!data.empty()) buffer_.upload(data.data(), data.size() * sizeof(glm::vec4));
    }
    void bind() const { vao_.bind(); }
    const Buffer& buffer() const { return buffer_; }

private:
    Buffer buffer_;
    VertexArray vao_;
};

glm::vec3 toLightFrame(const glm::mat4& viewFromWorld, const glm::vec3& world) {
    const glm::vec4 v = viewFromWorld * glm::vec4(world, 1.0f);
    return {v.x, v.y, -v.z};
}

// ---- 1. silhouettes, volume and wedges ------------------------------------------------------------

class SilhouettePass : public Pass {
public:
    void execute(PassContext& ctx) override {
        const Scene& scene = ctx.scene();
        if (scene_ != &scene) {
            casters_ = buildSsvCasters(scene);
            scene_ = &scene;
        }
        const double t = ctx.sceneTime(true);
        const Bounds& bounds = ctx.sceneBounds();
        const std::vector<Light> subLights = ssvSubLights(ctx.light(), int(ctx.param("split")));
        MeshData& edges = ctx.mesh("silhouettes");
        MeshData& wedges = ctx.mesh("wedges");
        MeshData& volume = ctx.mesh("shadow_volume");
        edges = MeshData{};
        wedges = MeshData{};
        volume = MeshData{};
        edges.verticesPerPrimitive = 2;
        std::vector<float> weight, object, kind, boundary, edgeSub;
        std::vector<float> edgeOf, face, wedgeSub;
        std::vector<float> vkind, vedge, infinity, volumeSub;
        std::vector<std::string> warnings;
        // Sub-light by sub-light (one, or the four quarters of the 2x2 splitting), in order: each
        // mesh's primitives of sub-light k are contiguous, with attribute sub_light = k.
        for (size_t k = 0; k < subLights.size(); ++k) {
            const SsvLight light = SsvLight::from(subLights[k]);
            const float far = wedgeFarDistance(bounds, light.centre);
            const SsvGeometry g = buildSsvGeometry(scene, casters_, t, light, far, capOffsetFor(bounds), &bounds);
            const uint32_t firstEdge = uint32_t(edges.primitiveCount());
            // Silhouette edges: lines, with their weight and whether their wedge is drawn.
            for (size_t i = 0; i < g.edges.size(); ++i) {
                const uint32_t base = uint32_t(edges.positions.size());
                edges.positions.push_back(g.edges[i].a);
                edges.positions.push_back(g.edges[i].b);
                edges.indices.push_back(base);
                edges.indices.push_back(base + 1);
                weight.push_back(g.edges[i].weight);
                object.push_back(float(scene.objects[size_t(g.edges[i].object)].id));
                kind.push_back(float(int(g.wedges[i].kind)));
                boundary.push_back(g.edges[i].boundary ? 1.0f : 0.0f);
                edgeSub.push_back(float(k));
            }
            // Wedges: 8 triangles each, in edge order (Wedge kind only).
            for (size_t i = 0; i < g.wedges.size(); ++i) {
                const SsvWedge& w = g.wedges[i];
                if (w.kind != SsvWedge::Kind::Wedge) continue;
                const uint32_t base = uint32_t(wedges.positions.size());
                wedges.positions.insert(wedges.positions.end(), w.corners.begin(), w.corners.end());
                for (int q = 0; q < 8; ++q) {
                    wedges.indices.insert(wedges.indices.end(),
                                          {base + w.triangles[q].x, base + w.triangles[q].y, base + w.triangles[q].z});
                    edgeOf.push_back(float(firstEdge + i));
                    face.push_back(float(w.faceOfTriangle[q]));
                    wedgeSub.push_back(float(k));
                }
            }
            // The hard volume: points at infinity exported at farDistance along their ray from the
            // sub-light's centre; `at_infinity` says which corners the GPU put at infinity (bit q:
            // corner q).
            const uint32_t base = uint32_t(volume.positions.size());
            for (const glm::vec4& v : g.volume.vertices)
                volume.positions.push_back(v.w == 0.0f ? light.centre + far * glm::vec3(v) : glm::vec3(v));
            for (size_t i = 0; i < g.volume.triangles.size(); ++i) {
                const glm::uvec3 tri = g.volume.triangles[i];
                volume.indices.insert(volume.indices.end(), {base + tri.x, base + tri.y, base + tri.z});
                vkind.push_back(float(g.volume.kind[i]));
                vedge.push_back(g.volume.edge[i] < 0 ? -1.0f : float(firstEdge + uint32_t(g.volume.edge[i])));
                int mask = 0;
                for (int q = 0; q < 3; ++q)
                    if (g.volume.vertices[tri[q]].w == 0.0f) mask |= 1 << q;
                infinity.push_back(float(mask));
                volumeSub.push_back(float(k));
            }
            if (k == 0) warnings = g.warnings;
        }
        edges.primitiveAttributes = {{"weight", weight},         {"object", object}, {"wedge_kind", kind},
                                     {"boundary", boundary}, {"sub_light", edgeSub}};
        wedges.primitiveAttributes = {{"edge", edgeOf}, {"face", face}, {"sub_light", wedgeSub}};
        volume.primitiveAttributes = {
            {"kind", vkind}, {"edge", vedge}, {"at_infinity", infinity}, {"sub_light", volumeSub}};
        for (const std::string& w : warnings)
            if (warned_.insert(w).second) std::fprintf(stderr, "shadowlab: warning: ssv: %s\n", w.c_str());
    }

private:
    const Scene* scene_ = nullptr;
    std::vector<SsvCaster> casters_;
    std::set<std::string> warned_;
};

// ---- 2. the hard shadow volume, z-fail -------------------------------------------------------------

// The sub-lights the passes run for (ssvSubLights of the frame's light and `split`).
std::vector<Light> subLightsOf(PassContext& ctx) { return ssvSubLights(ctx.light(), int(ctx.param("split"))); }

// The light frame of a sub-light: the light's own frame moved to the sub-light's centre (the same
// axes: the quarters of a square light lie in its plane).
glm::mat4 subLightViewFromWorld(const LightView& view, const Light& light, const Light& sub) {
    return view.viewFromWorld * glm::translate(glm::mat4(1.0f), light.position - sub.position);
}

// The first primitive of each sub-light in a mesh whose attribute `sub_light` is contiguous, and
// the end: sub-light k's primitives are [first[k], first[k + 1]).
std::vector<size_t> subLightRanges(const MeshData& mesh, size_t subLights) {
    const std::vector<float>* sub = nullptr;
    for (const auto& a : mesh.primitiveAttributes)
        if (a.first == "sub_light") sub = &a.second;
    std::vector<size_t> first(subLights + 1, mesh.primitiveCount());
    for (size_t k = 0; k < subLights; ++k) {
        size_t i = 0;
        while (i < mesh.primitiveCount() && sub && (*sub)[i] < float(k)) ++i;
        first[k] = i;
    }
    return first;
}

// The volume's vertices for the GPU: (x, y, z, 1), or (direction, 0) at infinity from the centre
// of the triangle's sub-light.
void volumeVertices(const MeshData& volume, const std::vector<Light>& subLights, std::vector<glm::vec4>& out) {
    out.clear();  // the caller's, kept from frame to frame (no large allocation per frame)
    out.reserve(volume.indices.size());
    const std::vector<float>& infinity = volume.primitiveAttributes[2].second;
    const std::vector<float>& sub = volume.primitiveAttributes[3].second;
    for (size_t i = 0; i < volume.indices.size(); ++i) {
        const glm::vec3 p = volume.positions[volume.indices[i]];
        const glm::vec3 centre = subLights[size_t(sub[i / 3])].position;
        const bool atInfinity = (int(infinity[i / 3]) >> (i % 3)) & 1;
        out.push_back(atInfinity ? glm::vec4(glm::normalize(p - centre), 0.0f) : glm::vec4(p, 1.0f));
    }
}

PipelineState zFailState() {
    PipelineState s = PipelineState::fullscreen();
    s.depthTest = true;
    s.depthFunc = GL_LESS;
    s.depthWrite = false;
    s.stencilTest = true;
    s.front.depthFail = GL_DECR_WRAP;  // a front face behind the point: one volume fewer
    s.back.depthFail = GL_INCR_WRAP;   // a back face behind the point: one volume more
    for (bool& c : s.colorMask) c = false;
    return s;
}

class HardVolumePass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& depth = ctx.texture("volume_depth");
        Texture& count = ctx.texture("hard_count");
        const Framebuffer& depthFbo = depthFbo_.get({}, &depth);
        const Framebuffer& countFbo = countFbo_.get({&count}, nullptr);
        const Camera& camera = ctx.camera();
        const VBuffer vb = vbufferOf(ctx);
        const glm::mat4 clipFromWorld =
            vb.clipAdjust * infiniteClipFromView(camera, float(ctx.width()) / float(ctx.height())) * camera.viewFromWorld();
        // The camera's depth of every G-buffer point, under the infinite projection.
        depthFbo.bind(ctx.width(), ctx.height());
        const VBufferViewport viewport(vb);
        PipelineState write = PipelineState::fullscreen();
        write.depthTest = true;
        write.depthFunc = GL_ALWAYS;
        for (bool& c : write.colorMask) c = false;
        write.apply();
        glClearNamedFramebufferfi(depthFbo.id(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
        const ShaderProgram& depthProgram = ctx.programs().get("common/fullscreen.vert", "ssv/depth.frag");
        depthProgram.use();
        ctx.bindGBuffer(depthProgram);
        depthProgram.set("clipFromWorld", clipFromWorld);
        depthProgram.set("vbufferDivisor", vb.k);
        drawFullscreenTriangle();
        // Per sub-light: its volume counted in the stencil (z-fail), the count read as a float
        // into channel k of hard_count (stencil texturing: the 8-bit wrapped count read as signed).
        const MeshData& volume = ctx.mesh("shadow_volume");
        const std::vector<Light> subLights = subLightsOf(ctx);
        const std::vector<size_t> first = subLightRanges(volume, subLights.size());
        volumeVertices(volume, subLights, scratch_);
        const std::vector<glm::vec4>& vertices = scratch_;
        vertices_.upload(vertices);
        const ShaderProgram& program = ctx.programs().get("ssv/volume.vert", "ssv/empty.frag");
        const ShaderProgram& read = ctx.programs().get("common/fullscreen.vert", "ssv/count.frag");
        countFbo.bind(ctx.width(), ctx.height());
        glViewport(0, 0, vb.width, vb.height);
        const float zero[4] = {0, 0, 0, 0};
        glClearNamedFramebufferfv(countFbo.id(), GL_COLOR, 0, zero);
        for (size_t k = 0; k < subLights.size(); ++k) {
            depthFbo.bind(ctx.width(), ctx.height());
            glViewport(0, 0, vb.width, vb.height);
            PipelineState::fullscreen().apply();
            glClearNamedFramebufferiv(depthFbo.id(), GL_STENCIL, 0, std::array<GLint, 1>{0}.data());
            if (first[k + 1] > first[k]) {
                zFailState().apply();
                program.use();
                program.set("clipFromWorld", clipFromWorld);
                vertices_.bind();
                glDrawArrays(GL_TRIANGLES, GLint(3 * first[k]), GLsizei(3 * (first[k + 1] - first[k])));
                glBindVertexArray(0);
            }
            PipelineState readState = PipelineState::fullscreen();
            for (int c = 0; c < 4; ++c) readState.colorMask[c] = c == int(k);
            readState.apply();
            countFbo.bind(ctx.width(), ctx.height());
            glViewport(0, 0, vb.width, vb.height);
            glTextureParameteri(depth.id(), GL_DEPTH_STENCIL_TEXTURE_MODE, GL_STENCIL_INDEX);
            read.use();
            glBindTextureUnit(4, depth.id());
            read.set("stencilCount", 4);
            drawFullscreenTriangle();
            glTextureParameteri(depth.id(), GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
            glBindTextureUnit(4, 0);
        }
        PipelineState::fullscreen().apply();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    FramebufferCache depthFbo_, countFbo_;
    Vec4Stream vertices_;
    std::vector<glm::vec4> scratch_;  // the volume's vertices, reused frame to frame
};

// ---- 3. the wedges ----------------------------------------------------------------------------------

class WedgePass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& depth = ctx.texture("volume_depth");
        Texture& coverage = ctx.texture("wedge_coverage");
        const Framebuffer& fbo = fbo_.get({&coverage}, &depth);
        fbo.bind(ctx.width(), ctx.height());
        const VBuffer vb = vbufferOf(ctx);
        const VBufferViewport viewport(vb);
        PipelineState::fullscreen().apply();
        const float zero[4] = {0, 0, 0, 0};
        glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, zero);
        glClearNamedFramebufferiv(fbo.id(), GL_STENCIL, 0, std::array<GLint, 1>{0}.data());
        const Light& light = ctx.light();
        const bool penumbra = ctx.paramBool("penumbra");
        const MeshData& edges = ctx.mesh("silhouettes");
        const MeshData& wedges = ctx.mesh("wedges");
        if (light.isPoint() || !penumbra || edges.indices.empty()) {
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            return;  // a point light has no penumbra: the hard volume is the answer
        }
        const LightView& view = ctx.lightView();
        const std::vector<Light> subLights = subLightsOf(ctx);
        const std::vector<size_t> first = subLightRanges(edges, subLights.size());
        // The edges in their sub-light's frame for the shader: (a, weight), (b, 0).
        std::vector<glm::vec4>& edgeData = edgeScratch_;  // reused frame to frame
        edgeData.clear();
        const std::vector<float>& weight = edges.primitiveAttributes[0].second;
        const std::vector<float>& kind = edges.primitiveAttributes[2].second;
        for (size_t k = 0; k < subLights.size(); ++k) {
            const glm::mat4 frame = subLightViewFromWorld(view, light, subLights[k]);
            for (size_t i = first[k]; i < first[k + 1]; ++i) {
                edgeData.push_back(glm::vec4(toLightFrame(frame, edges.positions[edges.indices[2 * i]]), weight[i]));
                edgeData.push_back(glm::vec4(toLightFrame(frame, edges.positions[edges.indices[2 * i + 1]]), 0.0f));
            }
        }
        edgeBuffer_.upload(edgeData);
        edgeBuffer_.buffer().bindBase(GL_SHADER_STORAGE_BUFFER, 0);
        // The wedges' triangles, 24 vertices per wedge, each with its edge index.
        std::vector<glm::vec4>& vertices = vertexScratch_;
        vertices.clear();
        vertices.reserve(wedges.indices.size());
        const std::vector<float>& edgeOf = wedges.primitiveAttributes[0].second;
        for (size_t i = 0; i < wedges.indices.size(); ++i)
            vertices.push_back(glm::vec4(wedges.positions[wedges.indices[i]], edgeOf[i / 3]));
        vertices_.upload(vertices);

        const Camera& camera = ctx.camera();
        const glm::mat4 clipFromWorld =
            vb.clipAdjust * infiniteClipFromView(camera, float(ctx.width()) / float(ctx.height())) * camera.viewFromWorld();
        const ShaderProgram& mark = ctx.programs().get("ssv/wedge.vert", "ssv/empty.frag");
        const ShaderProgram& shade = ctx.programs().get("ssv/wedge.vert", "ssv/wedge.frag");
        const ShaderProgram& everywhere = ctx.programs().get("ssv/wedge.vert", "ssv/wedge.frag", {"EVERYWHERE"});
        for (const ShaderProgram* p : {&mark, &shade}) p->set("clipFromWorld", clipFromWorld);
        for (const ShaderProgram* p : {&shade, &everywhere}) {
            ctx.bindGBuffer(*p);
            p->set("lightShape", bpLightShape(light));
            p->set("vbufferDivisor", vb.k);
        }
        // Mark: the wedge's own z-fail count, 1 where the pixel's point is inside it.
        PipelineState markState = zFailState();
        // Shade: the back faces (each pixel of a convex wedge's outline once), where marked, add
        // the coverage into the sub-light's channel; every pixel they cover is reset to 0 for the
        // next wedge.
        PipelineState shadeState = PipelineState::additiveBlend();
        shadeState.stencilTest = true;
        for (PipelineState::StencilFace* f : {&shadeState.front, &shadeState.back}) {
            f->func = GL_EQUAL;
            f->ref = 1;
            f->stencilFail = GL_ZERO;
            f->depthPass = GL_ZERO;
        }
        shadeState.cull = true;
        shadeState.cullFace = GL_FRONT;
        PipelineState everywhereState = PipelineState::additiveBlend();
        vertices_.bind();
        size_t drawn = 0;
        for (size_t k = 0; k < subLights.size(); ++k) {
            for (int c = 0; c < 4; ++c) shadeState.colorMask[c] = everywhereState.colorMask[c] = c == int(k);
            for (const ShaderProgram* p : {&shade, &everywhere}) {
                p->set("lightViewFromWorld", subLightViewFromWorld(view, light, subLights[k]));
                p->set("lightHalfSize", bpLightHalfSize(subLights[k]));
            }
            for (size_t i = first[k]; i < first[k + 1]; ++i) {
                if (kind[i] == float(int(SsvWedge::Kind::None))) continue;
                if (kind[i] == float(int(SsvWedge::Kind::Everywhere))) {
                    // No wedge could be built: evaluate the edge at every pixel (its coverage is 0
                    // outside its penumbra anyway).
                    everywhereState.apply();
                    everywhere.use();
                    everywhere.set("everywhereEdge", int(i));
                    glDrawArrays(GL_TRIANGLES, 0, 3);
                    continue;
                }
                markState.apply();
                mark.use();
                glDrawArrays(GL_TRIANGLES, GLint(24 * drawn), 24);
                shadeState.apply();
                shade.use();
                glDrawArrays(GL_TRIANGLES, GLint(24 * drawn), 24);
                ++drawn;
            }
        }
        glBindVertexArray(0);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    FramebufferCache fbo_;
    Vec4Stream edgeBuffer_, vertices_;
    std::vector<glm::vec4> edgeScratch_, vertexScratch_;  // reused frame to frame
};

// ---- 4. visibility ----------------------------------------------------------------------------------

class VisibilityPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& visibility = ctx.texture("visibility");
        const Framebuffer& fbo = fbo_.get({&visibility}, nullptr);
        const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "ssv/visibility.frag");
        program.use();
        ctx.bindGBuffer(program);
        const Light& light = ctx.light();
        const std::vector<Light> subLights = subLightsOf(ctx);
        glBindTextureUnit(4, ctx.texture("hard_count").id());
        program.set("hardCount", 4);
        glBindTextureUnit(5, ctx.texture("wedge_coverage").id());
        program.set("wedgeCoverage", 5);
        program.set("lightShape", bpLightShape(light));
        program.set("pointLight", light.isPoint() ? 1 : 0);
        program.set("subLightCount", int(subLights.size()));
        program.set("frontShape", light.isPoint() ? int(LightShape::Point) : int(light.shape));
        for (size_t k = 0; k < subLights.size(); ++k)
            program.set(("subLightCentre[" + std::to_string(k) + "]").c_str(), subLights[k].position);
        program.set("lightRight", light.isPoint() ? glm::vec3(0.0f) : light.right());
        program.set("lightUp", light.up);
        program.set("subLightSize", light.isPoint() ? 0.0f : subLights[0].size);
        const VBuffer vb = vbufferOf(ctx);
        program.set("vbufferDivisor", vb.k);
        program.set("vbufferSize", glm::ivec2(vb.width, vb.height));
        fbo.bind(ctx.width(), ctx.height());
        drawFullscreenTriangle();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    FramebufferCache fbo_;
};

// ---- the per-pixel record ------------------------------------------------------------------------

InternalDesc ssvPixelRecord() {
    InternalDesc r;
    r.name = "pixel";
    r.kind = InternalDesc::Kind::Record;
    r.doc = "the picked pixel's hard count and the wedges containing it, each edge projected and clipped on the light "
            "with its signed coverage (--pixel x,y)";
    r.schema = {{"background", "true when no geometry covers the pixel (then no other field)"},
                {"receiver_light_frame", "the point in the light frame (x right, y up, z depth)"},
                {"light_geometry", "shape (square or disk) and area of the light in light coordinates (4 or pi)"},
                {"sub_lights", "per sub-light (one; four with split 2, each a quarter of the square light): centre (world), "
                               "hard_count (shadow volumes containing the point: the stencil's z-fail count), "
                               "coverage_sum (the sum of its edges' signed coverages: the V-buffer's wedge part), "
                               "front_fraction (the fraction of the sub-light in front of the receiver's tangent plane) "
                               "and visibility ((1 - (hard_count x area + coverage_sum) / area), clamped, x front_fraction)"},
                {"edges", "the silhouette edges whose wedge contains the point (or that have no wedge and are evaluated "
                          "everywhere) and reach the light: index, sub_light, world end points world_a -> world_b, weight, "
                          "wedge kind, the edge projected on the sub-light a -> b (its light coordinates, before the light "
                          "clip) and clipped to it, orientation, signed_area (the occluded light area it adds: its "
                          "coverage times its weight)"},
                {"hard_count", "split 1: the light's hard count (as in sub_lights)"},
                {"initial_area", "split 1: hard_count x light area, the V-buffer's hard part"},
                {"front_fraction", "split 1: the light's front fraction (as in sub_lights)"},
                {"vbuffer", "the V-buffer's divisor k, its size and the texel read (GL rows from the bottom); with k > 1 "
                            "the hard counts are that texel's (the pixel nearest the picked one that the reduced buffer "
                            "holds) while the image interpolates four texels, so visibility_from_record is the V-buffer at "
                            "full resolution and the image differs by the load balancing's error"},
                {"visibility_from_record", "the mean of the sub-lights' visibility"},
                {"visibility", "this light's visibility at the pixel (the image)"}};
    r.reads = {"gbuffer", "light", "silhouettes", "hard_count", "wedge_coverage", "visibility", "param:penumbra",
               "param:split", "param:vbuffer_divisor"};
    r.record = [](PassContext& ctx, glm::ivec2 pixel) {
        nlohmann::json j;
        const int row = ctx.height() - 1 - pixel.y;
        glm::vec4 position(0.0f), normal(0.0f), counts(0.0f);
        resetPackState();
        glGetTextureSubImage(ctx.gbuffer().position->id(), 0, pixel.x, row, 0, 1, 1, 1, GL_RGBA, GL_FLOAT,
                             sizeof position, &position);
        glGetTextureSubImage(ctx.gbuffer().normal->id(), 0, pixel.x, row, 0, 1, 1, 1, GL_RGBA, GL_FLOAT, sizeof normal,
                             &normal);
        if (position.w == 0.0f) {
            j["background"] = true;
            return j;
        }
        // The V-buffer texel of the pixel (vbuffer_divisor k > 1: the nearest of the reduced buffer,
        // whose pixel is k i + k / 2; the image interpolates between four).
        const VBuffer vb = vbufferOf(ctx);
        const int tx = std::clamp(int(std::lround(double(pixel.x - vb.k / 2) / vb.k)), 0, vb.width - 1);
        const int ty = std::clamp(int(std::lround(double(row - vb.k / 2) / vb.k)), 0, vb.height - 1);
        glGetTextureSubImage(ctx.texture("hard_count").id(), 0, tx, ty, 0, 1, 1, 1, GL_RGBA, GL_FLOAT, sizeof counts,
                             &counts);
        const Light& light = ctx.light();
        const LightView& view = ctx.lightView();
        const glm::vec3 world(position);
        const int shape = bpLightShape(light);
        const std::vector<Light> subLights = subLightsOf(ctx);
        const MeshData& edges = ctx.mesh("silhouettes");
        const std::vector<size_t> first = subLightRanges(edges, subLights.size());
        const std::vector<float>& weight = edges.primitiveAttributes[0].second;
        nlohmann::json list = nlohmann::json::array(), subs = nlohmann::json::array();
        float mean = 0.0f;
        for (size_t k = 0; k < subLights.size(); ++k) {
            const Light& sub = subLights[k];
            const glm::mat4 frame = subLightViewFromWorld(view, light, sub);
            const glm::vec3 p = toLightFrame(frame, world);
            const glm::vec3 nv = glm::mat3(frame) * glm::vec3(normal);
            const glm::vec3 n(nv.x, nv.y, -nv.z);
            const float half = bpLightHalfSize(sub);
            const SsvLight slight = SsvLight::from(sub);
            const float far = wedgeFarDistance(ctx.sceneBounds(), slight.centre);
            float sum = 0.0f;
            if (!light.isPoint() && ctx.paramBool("penumbra")) {
                for (size_t i = first[k]; i < first[k + 1]; ++i) {
                    const glm::vec3 a = edges.positions[edges.indices[2 * i]], b = edges.positions[edges.indices[2 * i + 1]];
                    const SsvWedge w = buildWedge(slight, a, b, far, &ctx.sceneBounds());
                    if (w.kind == SsvWedge::Kind::None) continue;
                    if (w.kind == SsvWedge::Kind::Wedge && !w.contains(world)) continue;
                    const glm::vec3 la = toLightFrame(frame, a), lb = toLightFrame(frame, b);
                    const float area = weight[i] * shared::ssvEdgeCoverage(shape, p, n, la, lb, half);
                    const glm::vec4 e = shared::ssvProjectedEdge(p, n, la, lb, half);
                    const glm::vec2 range = shared::clipSegmentToLight(shape, glm::vec2(e.x, e.y), glm::vec2(e.z, e.w));
                    sum += area;
                    if (range.x > range.y && area == 0.0f) continue;  // inside the wedge, off the light
                    const glm::vec2 d = glm::vec2(e.z, e.w) - glm::vec2(e.x, e.y);
                    const glm::vec2 ca = glm::vec2(e.x, e.y) + d * range.x, cb = glm::vec2(e.x, e.y) + d * range.y;
                    list.push_back({{"index", i},
                                    {"sub_light", k},
                                    {"world_a", {a.x, a.y, a.z}},
                                    {"world_b", {b.x, b.y, b.z}},
                                    {"weight", weight[i]},
                                    {"wedge", w.kind == SsvWedge::Kind::Wedge ? "wedge" : "everywhere"},
                                    {"a", {e.x, e.y}},
                                    {"b", {e.z, e.w}},
                                    {"clipped", {ca.x, ca.y, cb.x, cb.y}},
                                    {"orientation", shared::edgeTurn(ca, cb) > 0.0f ? "ccw" : "cw"},
                                    {"signed_area", area}});
                }
            }
            const float count = counts[int(k)];
            const float front = shared::lightFractionInFront(light.isPoint() ? shared::LIGHT_SHAPE_POINT : int(light.shape),
                                                             sub.position, light.right(), light.up, sub.size, world,
                                                             glm::vec3(normal));
            const float v = light.isPoint() ? (count != 0.0f ? 0.0f : front) : shared::ssvVisibility(count, sum, shape) * front;
            mean += v / float(subLights.size());
            if (k == 0) j["receiver_light_frame"] = {p.x, p.y, p.z};
            subs.push_back({{"centre", {sub.position.x, sub.position.y, sub.position.z}},
                            {"hard_count", count},
                            {"coverage_sum", sum},
                            {"front_fraction", front},
                            {"visibility", v}});
        }
        j["light_geometry"] = {{"shape", shape == shared::BP_LIGHT_SQUARE ? "square" : "disk"},
                               {"area", shared::bpLightArea(shape)}};
        j["sub_lights"] = subs;
        j["vbuffer"] = {{"divisor", vb.k}, {"texel", {tx, ty}}, {"size", {vb.width, vb.height}}};
        if (subLights.size() == 1) {  // the fields the backprojection view reads, for the one light
            j["hard_count"] = subs[0]["hard_count"];
            j["initial_area"] = subs[0]["hard_count"].get<float>() * shared::bpLightArea(shape);
            j["front_fraction"] = subs[0]["front_fraction"];
        }
        j["edges"] = list;
        j["visibility_from_record"] = mean;
        j["visibility"] = ctx.pixelValue("visibility", pixel);
        return j;
    };
    return r;
}

}  // namespace

namespace {

// `--stats`: per caster, what buildTopology found and repaired and how the shadow volume treats it
// (README.md, "Open and imperfect meshes").
CounterDesc ssvTopologyCounter() {
    CounterDesc c;
    c.name = "topology";
    c.doc = "per caster: triangles, duplicates left out, triangles turned round, boundary and non-manifold edges, "
            "components (solids capped on their dark side, sheets capped on both), openings closed by fans";
    c.reads = {"silhouettes"};
    c.count = [](PassContext& ctx) {
        nlohmann::json objects = nlohmann::json::array();
        for (const SsvCaster& caster : buildSsvCasters(ctx.scene())) {
            const MeshTopology& t = caster.topology;
            size_t solids = 0;
            for (const MeshTopology::Component& comp : t.components) solids += comp.solid();
            objects.push_back({{"object", ctx.scene().objects[size_t(caster.object)].name},
                               {"triangles", t.triangles.size()},
                               {"degenerate_left_out", t.degenerateTriangles.size() - t.duplicateTriangles.size()},
                               {"duplicates_left_out", t.duplicateTriangles.size()},
                               {"turned_round", t.reorientedTriangles.size()},
                               {"boundary_edges", t.boundaryEdges()},
                               {"non_manifold_edges", t.nonManifoldEdges()},
                               {"solid_components", solids},
                               {"sheet_components", t.components.size() - solids},
                               {"openings_closed", t.fillCentres.size()}});
        }
        return nlohmann::json{{"objects", objects}};
    };
    return c;
}

}  // namespace

const TechniqueDesc& ssvTechnique() {
    static const TechniqueDesc desc = [] {
        TechniqueDesc d;
        d.id = "ssv";
        d.name = "Soft shadow volumes (penumbra wedges)";
        d.citation = "Assarsson 2004, A soft shadow volume algorithm (SIGGRAPH 2004 course slides); Assarsson and "
                     "Akenine-Moeller 2003";
        d.summary = "hard shadow volumes from the light centre counted in the stencil (z-fail), then one penumbra wedge "
                    "per silhouette edge adding or subtracting the edge's analytic coverage of the light in a float "
                    "V-buffer";
        d.soft = true;
        ParamDesc penumbra{"penumbra", "", ParamDesc::Type::Bool, "", 1.0, 0, 1, 1,
                           "1: the wedges add the penumbra; 0: hard shadow volumes from the light centre only (the "
                           "slides' first pass, shown alone)",
                           ""};
        ParamDesc split{"split", "", ParamDesc::Type::Int, "", 1.0, 1, 2, 1,
                        "light splitting (the slides' 'Light splitting'): 1 the whole light, 2 the square light as 2x2 "
                        "quarters, each with its own silhouettes, volume and wedges, v their mean (less single-silhouette "
                        "error; a disk or sphere light is not split)",
                        ""};
        ParamDesc divisor{"vbuffer_divisor", "", ParamDesc::Type::Int, "", 1.0, 1, 4, 1,
                          "the V-buffer at 1/k of the frame's resolution in each direction, upsampled bilinearly (the "
                          "slides' load balancing: 'smaller resolution -> faster rendering', with its errors and "
                          "flicker); 1: the frame's",
                          ""};
        ParamDesc target{"load_balance_ms", "", ParamDesc::Type::Float, "ms", 0.0, 0, 10000, 1,
                         "the slides' reactive load balancing: after each frame, vbuffer_divisor one step up when the "
                         "technique's passes took more than 1.2x this, one step down when the step down is predicted "
                         "(the cost per pixel, (k / (k - 1))^2 more) under 0.8x it; 0: off",
                         ""};
        d.params = {penumbra, split, divisor, target};
        // The reactive rule (assarsson2004, "Load balancing... use a simple reactive algorithm"): the
        // V-buffer's resolution follows the frame's cost, one step a frame, with hysteresis (1.2 and
        // 0.8 around the target) so that a steady cost settles; a changing one flickers, as the
        // slides warn ("Will get flickering...").
        d.adapt = [](const ParamValues& params, double ms) -> std::optional<std::pair<std::string, std::string>> {
            const double target = params.get("load_balance_ms");
            if (target <= 0.0) return std::nullopt;
            const int k = int(params.get("vbuffer_divisor"));
            if (ms > 1.2 * target && k < 4) return std::make_pair(std::string("vbuffer_divisor"), std::to_string(k + 1));
            if (k > 1 && ms * double(k * k) / double((k - 1) * (k - 1)) < 0.8 * target)
                return std::make_pair(std::string("vbuffer_divisor"), std::to_string(k - 1));
            return std::nullopt;
        };

        PassDesc silhouettes;
        silhouettes.name = "silhouettes";
        silhouettes.doc = "silhouette edges from the light centre (winged edges), the hard shadow volume and one penumbra "
                          "wedge per edge, on the CPU (assarsson2004, 'Wedge construction: in practice')";
        silhouettes.reads = {"scene.casters", "light", "param:split"};
        silhouettes.creates = {
            meshResource("silhouettes", "silhouette edges from the light centre, oriented, with weight and wedge kind"),
            meshResource("wedges", "penumbra wedges: 8 triangles each, attribute edge and face (0 front, 1 back, 2 side, "
                                   "3 bottom)"),
            meshResource("shadow_volume", "hard shadow volume: caps (0 near, 1 far) and sides (2), edge index; corners at "
                                          "infinity exported at the wedges' far distance (at_infinity bits)")};
        silhouettes.create = [] { return std::make_unique<SilhouettePass>(); };

        PassDesc hard;
        hard.name = "hard_volumes";
        hard.doc = "the camera's depth from the G-buffer, the shadow volume counted in the stencil with z-fail (capped, "
                   "infinite far plane), the count read back as a float";
        hard.reads = {"gbuffer", "camera", "light", "shadow_volume", "param:split", "param:vbuffer_divisor"};
        hard.creates = {ResourceDesc::texture("volume_depth", Format::DEPTH32F_STENCIL8, SizeRule::frame(),
                                              "camera depth (infinite far plane) and the stencil the volumes count in"),
                        ResourceDesc::texture("hard_count", Format::RGBA32F, SizeRule::frame(),
                                              "number of hard shadow volumes containing each pixel's point (channel k: "
                                              "sub-light k)")};
        hard.wholeFrame = true;  // a handful of draws, but wedges below: see PassDesc::wholeFrame
        hard.create = [] { return std::make_unique<HardVolumePass>(); };

        PassDesc wedge;
        wedge.name = "wedges";
        wedge.doc = "per wedge: its z-fail count marks the points inside it (the slides' stencil culling), then its back "
                    "faces add the edge's signed coverage where marked, into a float V-buffer";
        wedge.reads = {"gbuffer", "camera", "light", "silhouettes", "wedges", "param:penumbra", "param:split",
                       "param:vbuffer_divisor"};
        wedge.modifies = {"volume_depth"};
        wedge.creates = {ResourceDesc::texture("wedge_coverage", Format::RGBA32F, SizeRule::frame(),
                                               "the wedges' signed coverages summed (light-coordinate area; channel k: "
                                               "sub-light k)")};
        wedge.wholeFrame = true;  // two draws per wedge: in bands each band would draw them all again
        wedge.create = [] { return std::make_unique<WedgePass>(); };

        PassDesc visibility;
        visibility.name = "visibility";
        visibility.doc = "v = 1 - (hard count x light area + coverage sum) / light area, clamped, times the light's front "
                         "fraction";
        visibility.reads = {"gbuffer", "light", "hard_count", "wedge_coverage", "param:split", "param:vbuffer_divisor",
                            "param:load_balance_ms"};
        visibility.creates = {visibilityResource()};
        visibility.create = [] { return std::make_unique<VisibilityPass>(); };

        d.passes = {silhouettes, hard, wedge, visibility};
        d.internals = {
            {"silhouettes", InternalDesc::Kind::Lines, "silhouettes", {}, "silhouette edges from the light centre"},
            {"wedges", InternalDesc::Kind::Mesh, "wedges", {}, "penumbra wedges, exactly as drawn"},
            {"shadow_volume", InternalDesc::Kind::Mesh, "shadow_volume", {}, "the hard shadow volume, as drawn"},
        };
        // The V-buffer's two parts: with split 1 one channel each; with split 2 one per quarter.
        auto firstChannel = [](Image& img) {
            Image one(img.width, img.height, 1);
            for (size_t p = 0; p < one.pixelCount(); ++p) one.data[p] = img.data[p * size_t(img.channels)];
            img = std::move(one);
        };
        const std::vector<std::string> quarters = {"quarter_0", "quarter_1", "quarter_2", "quarter_3"};
        InternalDesc coverage{"wedge_coverage", InternalDesc::Kind::Image, "wedge_coverage", {"coverage"},
                              "the wedges' signed coverage sum (light-coordinate area of 4 or pi: positive where the "
                              "edges hide light the hard shadow sees, negative where they uncover light it hides)",
                              "split == 1"};
        coverage.signedValues = true;
        coverage.convert = firstChannel;
        InternalDesc coverageQuarters{"wedge_coverage_quarters", InternalDesc::Kind::Image, "wedge_coverage", quarters,
                                      "the wedges' signed coverage sum of each quarter of the light (2x2 splitting), in "
                                      "the quarter's light coordinates",
                                      "split == 2"};
        coverageQuarters.signedValues = true;
        InternalDesc count{"hard_count", InternalDesc::Kind::Image, "hard_count", {"count"},
                           "hard shadow volumes (from the light centre) containing each point", "split == 1"};
        count.convert = firstChannel;
        InternalDesc countQuarters{"hard_count_quarters", InternalDesc::Kind::Image, "hard_count", quarters,
                                   "hard shadow volumes from each quarter's centre containing each point (2x2 splitting)",
                                   "split == 2"};
        d.internals.insert(d.internals.end(), {coverage, coverageQuarters, count, countQuarters});
        d.internals.push_back(ssvPixelRecord());
        d.counters = {ssvTopologyCounter()};
        return d;
    }();
    return desc;
}

}  // namespace shadowlab

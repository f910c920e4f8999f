// `pvmf`: penumbra volume mask filtering (cournia2005 chapter 5). The dissertation's five passes
// (sec. 5.5) and the CPU geometry between them:
//  1. shadow_map: the light-centre shadow map (sec. 5.2's depth tests read it);
//  2. volumes (CPU): the silhouette edges from the light centre and, per edge, a simplified outer and
//     inner volume from its end points moved towards the light (sec. 5.1; pvmfQuad in pvm/geometry.cpp);
//  3. mask: the volumes rendered from the light into the penumbra volume mask, the nearest volume's
//     depth and its edge distance d_e (sec. 5.1);
//  4. select + filter: the pixels inside a volume or failing the shadow test listed, and only those
//     filtered by an n_pcf x n_pcf jittered percentage-closer filter of width w_pcf (sec. 5.2);
//  5. blur_h, blur_v: the object-id-aware separable blur of the listed pixels (sec. 5.3).
// The core's shade pass composites the v-buffer with the lighting (sec. 5.4). The math is shared
// with the tests in shaders/shared/penumbra_mask.glsl.
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <set>

#include "gl/buffer.h"
#include "gl/program.h"
#include "gl/texture.h"
#include "gl/util.h"
#include "graph/frame.h"
#include "pvm/pvm.h"
#include "pvm/volume_draw.h"
#include "shared/shared.h"
#include "visibility/shadow_map.h"

namespace shadowlab {

namespace {

constexpr int kCountSlots = 8;  // pvmf.counts: see shaders/pvmf/select.comp

float lightRadiusOf(const Light& light) {
    return light.isPoint() ? 0.0f : shared::pvmLightRadius(int(light.shape), light.size);
}

ResourceDesc meshResource(const std::string& name, const std::string& doc) {
    ResourceDesc d;
    d.name = name;
    d.kind = ResourceKind::Mesh;
    d.doc = doc;
    return d;
}

// ---- 2. silhouettes and the simplified volumes ----------------------------------------------------

class VolumesPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        const Scene& scene = ctx.scene();
        if (scene_ != &scene) {
            casters_ = buildSsvCasters(scene);
            scene_ = &scene;
        }
        const Light& light = ctx.light();
        const float r = lightRadiusOf(light);
        const float se = float(ctx.param("s_e"));
        const PvmGeometry g = buildPvmGeometry(scene, casters_, ctx.sceneTime(true), light.position, r);
        const float w = pvmExtrusionLength(ctx.sceneBounds(), light.position);
        MeshData& volumes = ctx.mesh("penumbra_volumes");
        writePvmMeshes(scene, g,
                       [&](const PvmEdge& e, float side) { return pvmfQuad(e, light.position, r, se, side, w); },
                       ctx.mesh("silhouettes"), volumes);
        // d_e per volume triangle, the mask's second channel (sec. 5.1).
        const std::vector<float>& edgeOf = volumes.primitiveAttributes[0].second;
        std::vector<float> edgeDistance;
        edgeDistance.reserve(edgeOf.size());
        for (float e : edgeOf) {
            const PvmEdge& edge = g.edges[size_t(e)];
            edgeDistance.push_back(shared::pvmfEdgeDistance(edge.a, edge.b, light.position));
        }
        volumes.primitiveAttributes.push_back({"edge_distance", std::move(edgeDistance)});
        for (const std::string& warning : g.warnings)
            if (warned_.insert(warning).second) std::fprintf(stderr, "shadowlab: warning: pvmf: %s\n", warning.c_str());
    }

private:
    const Scene* scene_ = nullptr;
    std::vector<SsvCaster> casters_;
    std::set<std::string> warned_;
};

// ---- 3. the mask: nearest volume depth and its edge distance --------------------------------------

class MaskPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& mask = ctx.texture("pvmf_mask");
        Texture& zbuffer = ctx.texture("pvmf_zbuffer");
        const Framebuffer& fbo = fbo_.get({&mask}, &zbuffer);
        // Per vertex (pvm/volume.vert's layout): the position, then d_e in the first attribute's w.
        const MeshData& volumes = ctx.mesh("penumbra_volumes");
        const std::vector<float>& edgeDistance = volumes.primitiveAttributes[3].second;
        std::vector<glm::vec4>& vertices = draw_.begin(volumes.indices.size());
        for (size_t i = 0; i < volumes.indices.size(); ++i) {
            vertices.push_back(glm::vec4(volumes.positions[volumes.indices[i]], 1.0f));
            vertices.push_back(glm::vec4(0.0f, 0.0f, 0.0f, edgeDistance[i / 3]));
            vertices.push_back(glm::vec4(0.0f));
        }
        const int size = mask.width();
        fbo.bind(size, size);
        const float none[4] = {FLT_MAX, 0.0f, 0.0f, 0.0f}, depthClear = 0.0f;
        glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, none);
        glClearNamedFramebufferfv(fbo.id(), GL_DEPTH, 0, &depthClear);
        draw_.draw(ctx, "pvmf/mask.frag");
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    FramebufferCache fbo_;
    VolumeDraw draw_;
};

// The uniforms select.comp and filter.comp share: the G-buffer, the shadow-map look-up, the front
// fraction and the mask.
void setLookupUniforms(PassContext& ctx, const ShaderProgram& program) {
    const Light& light = ctx.light();
    const Texture& map = ctx.texture(shadowTestMap(ctx));
    setShadowLookupUniforms(program, ctx.lightView(), map.width(), light);
    setLightFrontUniforms(program, light);
    program.set("biasConstTexels", float(ctx.param("bias_const")));
    program.set("biasSlopeTexels", float(ctx.param("bias_slope")));
    ctx.bindGBuffer(program);
    glBindTextureUnit(3, map.id());
    program.set("shadowMap", 3);
    glBindTextureUnit(4, ctx.texture("pvmf_mask").id());
    program.set("maskMap", 4);
}

// ---- 4a. select: the pixels the filter runs on -----------------------------------------------------

class SelectPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        const GLuint counts = ctx.buffer("pvmf.counts");
        glClearNamedBufferData(counts, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, counts);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, ctx.buffer("pvmf.pixels"));
        const ShaderProgram& classify = ctx.programs().compute("pvmf/select.comp", {"PVMF_STEP 1"});
        classify.use();
        setLookupUniforms(ctx, classify);
        classify.set("frameSize", glm::ivec2(ctx.width(), ctx.height()));
        bindImage(0, ctx.texture("visibility_raw"), 0, GL_WRITE_ONLY);
        classify.dispatch(GLuint((ctx.width() + 7) / 8), GLuint((ctx.height() + 7) / 8));
        memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        const ShaderProgram& args = ctx.programs().compute("pvmf/select.comp", {"PVMF_STEP 2"});
        args.use();
        args.dispatch(1);
        memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                      GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        for (GLuint unit = 0; unit < 2; ++unit) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, unit, 0);
    }
};

// Dispatches `program` over the listed pixels (select.comp's arguments in pvmf.counts[1..3]).
void dispatchListed(PassContext& ctx, const ShaderProgram& program) {
    (void)program;
    const GLuint counts = ctx.buffer("pvmf.counts");
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, counts);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, ctx.buffer("pvmf.pixels"));
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, counts);
    glDispatchComputeIndirect(GLintptr(1 * sizeof(GLuint)));
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    for (GLuint unit = 0; unit < 2; ++unit) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, unit, 0);
    memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
}

// ---- 4b. filter: w_pcf from the mask, n_pcf x n_pcf jittered depth tests --------------------------

class FilterPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& kernels = ctx.texture("pvmf_kernel");
        const float notListed[4] = {-1.0f, -1.0f, -1.0f, 0.0f};
        glClearTexImage(kernels.id(), 0, GL_RGBA, GL_FLOAT, notListed);
        const ShaderProgram& program = ctx.programs().compute("pvmf/filter.comp");
        program.use();
        setLookupUniforms(ctx, program);
        program.set("sp", float(ctx.param("s_p")));
        program.set("lightRadius", lightRadiusOf(ctx.light()));
        program.set("npcf", ctx.paramInt("n_pcf"));
        program.set("nDo", ctx.paramInt("n_do"));
        program.set("seed", GLuint(ctx.paramInt("seed")));
        bindImage(0, ctx.texture("visibility_raw"), 0, GL_WRITE_ONLY);
        bindImage(1, kernels, 0, GL_WRITE_ONLY);
        dispatchListed(ctx, program);
    }
};

// ---- 5. the object-id-aware separable blur ---------------------------------------------------------

class BlurPass : public Pass {
public:
    BlurPass(std::string source, std::string target, glm::ivec2 axis)
        : source_(std::move(source)), target_(std::move(target)), axis_(axis) {}
    void execute(PassContext& ctx) override {
        const Texture& source = ctx.texture(source_);
        Texture& target = ctx.texture(target_);
        // Unlisted pixels keep their value: the target starts as a copy of the source.
        glCopyImageSubData(source.id(), GL_TEXTURE_2D, 0, 0, 0, 0, target.id(), GL_TEXTURE_2D, 0, 0, 0, 0,
                           source.width(), source.height(), 1);
        memoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        const ShaderProgram& program = ctx.programs().compute("pvmf/blur.comp");
        program.use();
        ctx.bindGBuffer(program);
        setLightFrontUniforms(program, ctx.light());
        program.set("axis", axis_);
        program.set("nblur", shared::pvmfBlurTaps(ctx.paramInt("n_blur"), ctx.height()));
        program.set("frameSize", glm::ivec2(ctx.width(), ctx.height()));
        bindImage(0, source, 0, GL_READ_ONLY);
        bindImage(1, target, 0, GL_WRITE_ONLY);
        dispatchListed(ctx, program);
    }

private:
    std::string source_, target_;
    glm::ivec2 axis_;
};

glm::vec4 texelOf(const Texture& texture, glm::ivec2 t) {
    glm::vec4 v(0.0f);
    resetPackState();
    glGetTextureSubImage(texture.id(), 0, t.x, t.y, 0, 1, 1, 1, GL_RGBA, GL_FLOAT, sizeof v, &v);
    return v;
}

// The directional receiver-plane bias of a tap at `offset` texels (shaders/pcss/pcss_common.glsl's
// tapPlane and tapBias, on the same shared functions), for the record.
float tapBiasOf(const LightView& view, float size, const glm::vec3& p, const glm::vec3& n, const glm::vec4& coord,
                float texelWorld, float cosTheta, float bias, glm::vec2 offset) {
    const glm::vec3 pv = glm::vec3(view.viewFromWorld * glm::vec4(p, 1.0f));
    const glm::vec3 nv = glm::normalize(glm::mat3(view.viewFromWorld) * n);
    const glm::vec3 inv =
        shared::planeInverseDepth(pv, nv, glm::vec2(coord) * 2.0f - 1.0f, view.tanHalfFov, 1.0f);
    const float iso = shared::receiverPlaneBias(texelWorld, cosTheta, 1.0f) * glm::length(offset);
    const float invZ = inv.x + glm::dot(glm::vec2(inv.y, inv.z) * (2.0f / size), offset);
    const float extra = invZ <= 0.0f ? iso : glm::clamp(coord.z - 1.0f / invZ, 0.0f, iso);
    return bias + extra;
}

// The picked pixel: whether it was listed, d_o, d_r, w_pcf and the samples taken (sec. 5.2), as the
// filter computed them, and its visibility before and after the blur.
InternalDesc pvmfPixelRecord() {
    InternalDesc r;
    r.name = "pixel";
    r.kind = InternalDesc::Kind::Record;
    r.doc = "the picked pixel's mask look-up and filter (--pixel x,y): in a volume or not, d_o, d_r, w_pcf and the "
            "jittered samples of sec. 5.2, the visibility before and after the blur of sec. 5.3";
    r.schema = {{"background", "true when no geometry covers the pixel (then no other field)"},
                {"receiver", "the receiver's world position"},
                {"receiver_depth", "its light-view depth z (world units)"},
                {"map_texel", "the mask / shadow-map texel it projects to (x, y from the bottom); null outside the "
                              "light's frustum or behind the receiver's tangent plane"},
                {"mask_depth", "the mask's nearest volume depth there (null: no volume)"},
                {"in_volume", "mask_depth < receiver_depth: inside a simplified volume (sec. 5.1)"},
                {"shadow_test", "the shadow-map test at the receiver (1 lit, 0 shadowed)"},
                {"listed", "filtered (in a volume or failing the shadow test); else lit, never filtered"},
                {"d_r", "the receiver's distance from the light centre"},
                {"d_o", "the mean edge distance d_e over the n_do x n_do mask texels about map_texel that hold a "
                        "volume (null: none, the shadow test stands)"},
                {"mask_texels", "how many of those texels hold a volume"},
                {"w_pcf", "the filter's width, sec. 5.2's equation, in shadow-map texture coordinates (capped at 1)"},
                {"w_pcf_texels", "the same in shadow-map texels"},
                {"samples", "the n_pcf x n_pcf jittered taps: offset (texels from the receiver's projection), texel, "
                            "stored depth, lit (with the tap's receiver-plane bias)"},
                {"front_fraction", "the fraction of the light in front of the receiver's tangent plane"},
                {"visibility_from_record", "what the fields give: (the samples' mean, or the shadow test, or 1) x "
                                           "front_fraction"},
                {"visibility_before_blur", "the filter's output at the pixel (visibility_raw)"},
                {"visibility", "this light's visibility at the pixel after the blur"}};
    r.reads = {"gbuffer", "light", "pvmf_mask", "shadow_map", "shadow_map_second_depth", "param:second_depth",
               "param:bias_const", "param:bias_slope", "param:s_p", "param:n_pcf", "param:n_do", "param:seed",
               "visibility_raw", "visibility"};
    r.record = [](PassContext& ctx, glm::ivec2 pixel) {
        nlohmann::json j;
        const std::optional<RecordReceiver> receiver = beginReceiverRecord(ctx, pixel, j);
        if (!receiver) return j;
        const Light& light = ctx.light();
        const LightView& view = ctx.lightView();
        const glm::vec3 p = receiver->p, n = receiver->n;
        const glm::vec4 coord = receiver->coord;
        const float front = receiver->front;
        const float dr = glm::length(p - light.position);
        j["d_r"] = dr;
        for (const char* f : {"map_texel", "mask_depth", "shadow_test", "d_o", "mask_texels", "w_pcf", "w_pcf_texels",
                              "samples"})
            j[f] = nullptr;
        j["in_volume"] = false;
        j["listed"] = false;
        float v = 1.0f;
        if (front > 0.0f && coord.w != 0.0f) {
            const Texture& map = ctx.texture(shadowTestMap(ctx));
            const Texture& mask = ctx.texture("pvmf_mask");
            const int size = map.width();
            const glm::ivec2 t = glm::clamp(glm::ivec2(glm::floor(glm::vec2(coord) * float(size))), glm::ivec2(0),
                                            glm::ivec2(size - 1));
            j["map_texel"] = {t.x, t.y};
            const glm::vec4 m = texelOf(mask, t);
            j["mask_depth"] = m.x > 1e30f ? nlohmann::json(nullptr) : nlohmann::json(m.x);
            const bool inVolume = m.x < coord.z;
            const float texelWorld = shared::shadowTexelWorldSize(coord.z, view.tanHalfFov, float(size));
            const float cosTheta = std::abs(glm::dot(n, glm::normalize(light.position - p)));
            const float bias = shared::shadowDepthBias(texelWorld, float(ctx.param("bias_const")),
                                                       float(ctx.param("bias_slope")), cosTheta);
            const float test = shared::shadowDepthTest(coord.z, texelOf(map, t).x, bias);
            j["in_volume"] = inVolume;
            j["shadow_test"] = test;
            const bool listed = inVolume || test == 0.0f;
            j["listed"] = listed;
            if (listed) {
                const int h = ctx.paramInt("n_do") / 2;
                float sum = 0.0f, found = 0.0f;
                for (int dy = -h; dy <= h; ++dy)
                    for (int dx = -h; dx <= h; ++dx) {
                        const float de =
                            texelOf(mask, glm::clamp(t + glm::ivec2(dx, dy), glm::ivec2(0), glm::ivec2(size - 1))).y;
                        if (de > 0.0f) sum += de, found += 1.0f;
                    }
                j["mask_texels"] = int(found);
                if (found == 0.0f) {
                    v = test;
                } else {
                    const float dO = sum / found;
                    const float w =
                        std::min(shared::pvmfFilterWidth(float(ctx.param("s_p")), dr, dO, lightRadiusOf(light),
                                                         view.tanHalfFov),
                                 1.0f);
                    const float width = w * float(size);
                    j["d_o"] = dO;
                    j["w_pcf"] = w;
                    j["w_pcf_texels"] = width;
                    const uint32_t npcf = uint32_t(ctx.paramInt("n_pcf"));
                    const uint32_t seed = shared::pvmfPixelSeed(uint32_t(ctx.paramInt("seed")), uint32_t(pixel.x),
                                                                uint32_t(ctx.height() - 1 - pixel.y));  // the GL pixel, as the filter
                    nlohmann::json samples = nlohmann::json::array();
                    float lit = 0.0f;
                    for (uint32_t i = 0; i < npcf * npcf; ++i) {
                        const glm::vec2 offset = shared::pvmfSampleOffset(i, npcf, seed) * width;
                        const glm::ivec2 tt = glm::clamp(glm::ivec2(glm::floor(glm::vec2(coord) * float(size) + offset)),
                                                         glm::ivec2(0), glm::ivec2(size - 1));
                        const float stored = texelOf(map, tt).x;
                        const float b = tapBiasOf(view, float(size), p, n, coord, texelWorld, cosTheta, bias, offset);
                        const float s = shared::shadowDepthTest(coord.z, stored, b);
                        lit += s;
                        samples.push_back({{"offset", {offset.x, offset.y}},
                                           {"texel", {tt.x, tt.y}},
                                           {"stored_depth", stored > 1e30f ? nlohmann::json(nullptr) : nlohmann::json(stored)},
                                           {"lit", s}});
                    }
                    j["samples"] = samples;
                    v = lit / float(npcf * npcf);
                }
            }
        }
        j["visibility_from_record"] = front == 0.0f ? 0.0f : v * front;
        j["visibility_before_blur"] = ctx.pixelValue("visibility_raw", pixel);
        j["visibility"] = ctx.pixelValue("visibility", pixel);
        return j;
    };
    return r;
}

CounterDesc maskCounter() {
    CounterDesc c;
    c.name = "mask";
    c.doc = "what the mask restricted (cournia2005 sec. 5.2, 5.5): geometry pixels, the pixels filtered and blurred "
            "(inside a volume, or only failing the shadow test) and their fraction of the geometry";
    c.reads = {"pvmf.counts"};
    c.count = [](PassContext& ctx) {
        std::vector<uint32_t> counts(kCountSlots);
        glGetNamedBufferSubData(ctx.buffer("pvmf.counts"), 0, GLsizeiptr(counts.size() * 4), counts.data());
        return nlohmann::json{{"geometry_pixels", counts[4]},
                              {"listed_pixels", counts[0]},
                              {"in_volume_pixels", counts[5]},
                              {"shadow_test_only_pixels", counts[6]},
                              {"masked_fraction", counts[4] ? double(counts[0]) / double(counts[4]) : 0.0}};
    };
    return c;
}

}  // namespace

const TechniqueDesc& pvmfTechnique() {
    static const TechniqueDesc desc = [] {
        using T = ParamDesc::Type;
        TechniqueDesc d;
        d.id = "pvmf";
        d.name = "Penumbra volume mask filtering";
        d.citation = "Cournia 2005, Penumbra volume maps and penumbra volume mask filtering (dissertation), chapter 5";
        d.summary = "simplified per-edge penumbra volumes rendered from the light into a mask (depth and edge distance); "
                    "only the pixels inside a volume or in shadow are filtered, by jittered percentage-closer samples "
                    "over a width from the mask's edge distance, then blurred within each object";
        d.soft = true;
        d.params = shadowMapParams();
        for (ParamDesc& p : d.params)
            if (p.key == "sm_size") {
                p.defaultValue = 512;
                p.doc = "shadow-map and mask resolution (width = height); 512 as sec. 5.5";
            }
        d.params.push_back({"s_e", "s_e", T::Float, "", 0.1, 0.0, 1.0, 0.01,
                            "how far the edge end points move towards the light, a fraction of d_e (sec. 5.1): the "
                            "volumes start nearer the light so that they overestimate the penumbra; 0.1 keeps them "
                            "close to the edge",
                            ""});
        d.params.push_back({"s_p", "s_p", T::Float, "", 1.7725, 0.1, 10.0, 0.05,
                            "scale of the filter width w_pcf (sec. 5.2); sqrt(pi): the square filter has the area of "
                            "the light's disk",
                            ""});
        d.params.push_back({"n_pcf", "n_pcf", T::Int, "", 7, 1, 16, 1,
                            "the filter takes n_pcf x n_pcf jittered samples (sec. 5.2); 7 as sec. 5.5", ""});
        d.params.push_back({"n_blur", "n_blur", T::Int, "taps at 512 px", 12, 0, 64, 1,
                            "the blur's width: taps from -n_blur/2 to n_blur/2 along each axis (sec. 5.3) on sec. 5.5's "
                            "512 x 512 visibility buffer, scaled with the frame's height (pvmfBlurTaps: 3 at 128 px, "
                            "25 at 1080 px); 12 as sec. 5.5; 0: no blur",
                            ""});
        ParamDesc nDo{"n_do", "", T::Int, "texels", 5, 1, 15, 1,
                      "the mask texels averaged for d_o: n_do x n_do about the receiver's projection (sec. 5.2 averages "
                      "the mask's edge distances near the receiver without saying over how many)",
                      ""};
        nDo.constraint = ParamDesc::Constraint::Odd;
        d.params.push_back(nDo);
        d.params.push_back({"seed", "", T::Int, "", 1, 0, 1000000, 1,
                            "seed of the per-pixel jitter (sec. 5.2): the same seed gives the same samples", ""});

        PassDesc volumes;
        volumes.name = "volumes";
        volumes.doc = "silhouette edges from the light centre (winged edges) and per edge an outer and an inner simplified "
                      "volume from its end points moved towards the light by s_e d_e (sec. 5.1), on the CPU";
        volumes.reads = {"scene.casters", "light", "param:s_e"};
        volumes.creates = {
            meshResource("silhouettes", "silhouette edges from the light centre, clockwise seen from the light"),
            meshResource("penumbra_volumes", "the outer (side 0) and inner (side 1) simplified volume quadrilaterals, "
                                             "two triangles each, with their edge and its distance d_e, exactly as drawn")};
        volumes.soft = true;
        volumes.create = [] { return std::make_unique<VolumesPass>(); };

        PassDesc mask;
        mask.name = "mask";
        mask.doc = "the simplified volumes rendered from the light into the penumbra volume mask: the nearest volume's "
                   "light-view depth and its edge distance d_e (sec. 5.1)";
        mask.reads = {"light", "penumbra_volumes", "param:sm_size"};
        mask.creates = {
            ResourceDesc::texture("pvmf_mask", Format::RG32F, SizeRule::shadowMap(),
                                  "penumbra volume mask: (light-view z of the nearest volume, FLT_MAX: none; its edge "
                                  "distance d_e, 0: none)"),
            ResourceDesc::texture("pvmf_zbuffer", Format::DEPTH32F, SizeRule::shadowMap(),
                                  "reversed-depth z-buffer of the mask render (scratch)")};
        mask.state = PipelineState::depthGreaterReversed();
        mask.soft = true;
        mask.create = [] { return std::make_unique<MaskPass>(); };

        PassDesc select;
        select.name = "select";
        select.doc = "every pixel classified against the mask and the shadow map (sec. 5.2): those inside a volume or "
                     "in shadow listed for the filter and the blur, the others lit (their front fraction)";
        select.reads = {"gbuffer", "light", "pvmf_mask", "param:bias_const", "param:bias_slope"};
        for (const std::string& r : shadowTestReads()) select.reads.push_back(r);
        ResourceDesc counts;
        counts.name = "pvmf.counts";
        counts.kind = ResourceKind::StorageBuffer;
        counts.size = SizeRule::fixed(kCountSlots, 1);
        counts.elementBytes = 4;
        counts.doc = "[0] pixels listed, [1-3] the filter's and the blur's dispatch, [4] geometry pixels, [5] listed "
                     "inside a volume, [6] listed only by the shadow test";
        ResourceDesc pixels = counts;
        pixels.name = "pvmf.pixels";
        pixels.size = SizeRule::frame();
        pixels.doc = "the listed pixels, x | y << 16, in the order the atomic counter gave them";
        pixels.unordered = true;
        select.creates = {
            counts, pixels,
            ResourceDesc::texture("visibility_raw", Format::R32F, SizeRule::frame(),
                                  "the visibility before the blur: the filter's estimate on listed pixels, the front "
                                  "fraction elsewhere")};
        select.soft = true;
        select.wholeFrame = true;
        select.create = [] { return std::make_unique<SelectPass>(); };

        PassDesc filter;
        filter.name = "filter";
        filter.doc = "on the listed pixels: d_o from the mask's edge distances, w_pcf (sec. 5.2's equation) and n_pcf x "
                     "n_pcf jittered depth tests over it, times the front fraction";
        filter.reads = {"gbuffer", "light", "pvmf_mask", "pvmf.counts", "pvmf.pixels", "param:bias_const",
                        "param:bias_slope", "param:s_p", "param:n_pcf", "param:n_do", "param:seed"};
        for (const std::string& r : shadowTestReads()) filter.reads.push_back(r);
        filter.modifies = {"visibility_raw"};
        filter.creates = {ResourceDesc::texture("pvmf_kernel", Format::RGBA32F, SizeRule::frame(),
                                                "per listed pixel: (w_pcf in texels, d_o (-1: none), d_r, samples); -1 "
                                                "where not listed")};
        filter.soft = true;
        filter.wholeFrame = true;
        filter.create = [] { return std::make_unique<FilterPass>(); };

        PassDesc blurH;
        blurH.name = "blur_h";
        blurH.doc = "the object-id-aware box blur of the listed pixels, horizontal (sec. 5.3)";
        blurH.reads = {"gbuffer", "light", "visibility_raw", "pvmf.counts", "pvmf.pixels", "param:n_blur"};
        blurH.creates = {ResourceDesc::texture("visibility_h", Format::R32F, SizeRule::frame(),
                                               "the visibility blurred horizontally")};
        blurH.soft = true;
        blurH.wholeFrame = true;
        blurH.create = [] { return std::make_unique<BlurPass>("visibility_raw", "visibility_h", glm::ivec2(1, 0)); };

        PassDesc blurV = blurH;
        blurV.name = "blur_v";
        blurV.doc = "the object-id-aware box blur of the listed pixels, vertical, into the v-buffer (sec. 5.3)";
        blurV.reads = {"gbuffer", "light", "visibility_h", "pvmf.counts", "pvmf.pixels", "param:n_blur"};
        blurV.creates = {visibilityResource()};
        blurV.create = [] { return std::make_unique<BlurPass>("visibility_h", "visibility", glm::ivec2(0, 1)); };

        d.passes = {shadowMapPass(), volumes, mask, select, filter, blurH, blurV};
        d.internals = shadowMapInternals();
        InternalDesc silhouettes{"silhouettes", InternalDesc::Kind::Lines, "silhouettes", {},
                                 "silhouette edges from the light centre, clockwise seen from the light"};
        InternalDesc volumeMesh{"penumbra_volumes", InternalDesc::Kind::Mesh, "penumbra_volumes", {},
                                "outer (side 0) and inner (side 1) simplified volume quads, exactly as drawn"};
        InternalDesc maskImage{"pvmf_mask", InternalDesc::Kind::Image, "pvmf_mask", {"depth", "edge_distance"},
                               "penumbra volume mask: light-view z of the nearest volume (inf: none) and its edge "
                               "distance d_e (0: none)"};
        maskImage.convert = farMarkerToInfinity;
        InternalDesc raw{"visibility_raw", InternalDesc::Kind::Image, "visibility_raw", {"visibility"},
                         "the visibility before the blur (sec. 5.2's filter on listed pixels)"};
        InternalDesc kernel{"pvmf_kernel", InternalDesc::Kind::Image, "pvmf_kernel",
                            {"w_pcf_texels", "d_o", "d_r", "samples"},
                            "per listed pixel the filter: its width in texels, d_o, d_r and the samples taken (-1: "
                            "not listed)"};
        d.internals.insert(d.internals.end(), {silhouettes, volumeMesh, maskImage, raw, kernel, pvmfPixelRecord()});
        d.counters = {maskCounter()};
        return d;
    }();
    return desc;
}

}  // namespace shadowlab

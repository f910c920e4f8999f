// `spsm`: sub-pixel shadow maps (lecocq2014). Pass 1 renders the casters from the light's centre
// with conservative rasterization, keeping per texel the closest triangle packed in 128 bits;
// pass 2 decides each receiver from the stored triangles of its texel and neighbourhood, and
// reconstructs the shadow edge where none covers it. techniques/spsm/README.md has the design.
#include "spsm/spsm.h"

#include <cmath>
#include <cstring>
#include <map>

#include "visibility/shadow_map.h"

namespace shadowlab {

namespace {

constexpr GLenum kConservativeNV = 0x9346;     // GL_CONSERVATIVE_RASTERIZATION_NV
constexpr GLenum kConservativeIntel = 0x83FE;  // GL_CONSERVATIVE_RASTERIZATION_INTEL

bool hasExtension(const char* name) {
    GLint count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &count);
    for (GLint i = 0; i < count; ++i) {
        const char* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
        if (e && std::strcmp(e, name) == 0) return true;
    }
    return false;
}

// The driver's conservative-rasterization enable, or 0 when it has none.
GLenum hardwareConservativeCap() {
    if (hasExtension("GL_NV_conservative_raster")) return kConservativeNV;
    if (hasExtension("GL_INTEL_conservative_rasterization")) return kConservativeIntel;
    return 0;
}

void setSpsmSpaceUniforms(const ShaderProgram& program, const LightView& view, int size) {
    program.set("lightViewFromWorld", view.viewFromWorld);
    program.set("smSize", float(size));
    program.set("tanHalfFov", view.tanHalfFov);
    program.set("nearZ", view.nearZ);
}

// Pass 1: the closest triangle per texel (conservative rasterization, the footprint's nearest depth).
class BuildPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& map = ctx.texture("spsm");
        Texture& zbuffer = ctx.texture("spsm_zbuffer");
        const Framebuffer& fbo = fbo_.get({&map}, &zbuffer);
        bool conservative = ctx.paramBool("conservative");
        GLenum hardware = conservative ? hardwareConservativeCap() : 0;
        std::vector<std::string> defines;
        if (conservative) defines.push_back(hardware ? "HARDWARE_CONSERVATIVE" : "CONSERVATIVE");
        const ShaderProgram& program =
            ctx.programs().get("spsm/build.vert", "spsm/build.frag", defines, "spsm/build.geom");
        program.use();
        setSpsmSpaceUniforms(program, ctx.lightView(), map.width());
        fbo.bind(map.width(), map.height());
        const GLuint none[4] = {0u, 0u, 0u, 0u};
        const float zero = 0.0f;
        glClearNamedFramebufferuiv(fbo.id(), GL_COLOR, 0, none);
        glClearNamedFramebufferfv(fbo.id(), GL_DEPTH, 0, &zero);
        if (hardware) glEnable(hardware);
        ctx.drawScene(program, true);
        if (hardware) glDisable(hardware);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    FramebufferCache fbo_;
};

// Pass 2: the look-up in five steps (shaders/spsm/lookup.comp): every pixel against its texel's
// triangle (step 1, a fullscreen draw of lookup_texel.frag into the visibility and the branch
// images), the undecided ones appended to list 1; list 1 against the neighbourhood, the still
// undecided appended to list 2; list 2 by the reconstructed edge (steps 2 and 4 write the indirect
// dispatches' arguments).
class LookupPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        const GLuint counts = ctx.buffer("spsm.counts");
        glClearNamedBufferData(counts, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, counts);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, ctx.buffer("spsm.list1"));
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, ctx.buffer("spsm.list2"));
        const Texture& map = ctx.texture("spsm");
        Texture& visibility = ctx.texture("visibility");
        Texture& branches = ctx.texture("spsm_branch");
        auto setCommon = [&](const ShaderProgram& program) {
            setShadowLookupUniforms(program, ctx.lightView(), map.width(), ctx.light());
            program.set("biasConstTexels", float(ctx.param("bias_const")));
            program.set("biasSlopeTexels", float(ctx.param("bias_slope")));
            ctx.bindGBuffer(program);
            glBindTextureUnit(3, map.id());
            program.set("spsmMap", 3);
        };
        // Neighbourhood 1 without reconstruction: the texel's triangle alone (step 1 decides every
        // pixel; a ray it does not decide is lit, Dai et al.'s rule): the look-up's least work, what
        // the paper's first test costs with nothing after it (the bench's floor row).
        const bool texelAlone = ctx.paramInt("neighbourhood") == 1 && !ctx.paramBool("reconstruction");
        // Step 1: a fullscreen draw (under refineFrame's bands its scissor keeps the band's pixels,
        // and the lists hold only theirs).
        {
            const Framebuffer& fbo = fbo_.get({&visibility, &branches}, nullptr);
            const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "spsm/lookup_texel.frag", {});
            program.use();
            setCommon(program);
            program.set("listUndecided", texelAlone ? 0 : 1);
            fbo.bind(ctx.width(), ctx.height());
            drawFullscreenTriangle();
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        }
        const int lastStep = texelAlone ? 1 : ctx.paramBool("reconstruction") ? 5 : 3;
        for (int step = 2; step <= lastStep; ++step) {
            const ShaderProgram& program =
                ctx.programs().compute("spsm/lookup.comp", {"LOOKUP_STEP " + std::to_string(step)});
            program.use();
            if (step == 2 || step == 4) {
                program.dispatch(1);
                memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
                continue;
            }
            setCommon(program);
            bindImage(0, visibility, 0, GL_WRITE_ONLY);
            bindImage(1, branches, 0, GL_WRITE_ONLY);
            if (step == 3) {
                program.set("neighbourhood", ctx.paramInt("neighbourhood"));
                program.set("reconstruction", ctx.paramBool("reconstruction") ? 1 : 0);
            }
            glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, counts);
            glDispatchComputeIndirect(GLintptr((step == 3 ? 1 : 5) * sizeof(GLuint)));
            glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
            memoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        }
        for (GLuint unit = 0; unit < 3; ++unit) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, unit, 0);
        memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                      GL_FRAMEBUFFER_BARRIER_BIT);
    }

private:
    FramebufferCache fbo_;
};

// The light-view point of SPSM-space texel coordinate x at depth z, and in world space.
glm::vec3 worldPoint(const LightView& view, int size, glm::vec2 x, float z) {
    glm::vec3 dir = shared::spsmRayDirection(x, float(size), view.tanHalfFov);
    return glm::vec3(glm::inverse(view.viewFromWorld) * glm::vec4(dir * z, 1.0f));
}

// For the internals: the distinct stored triangles as a world-space mesh, and per texel the index
// of its triangle in that mesh (-1: empty).
class StoredTrianglesPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        const Texture& map = ctx.texture("spsm");
        int size = map.width();
        std::vector<uint32_t> words = readTextureUint(map);
        MeshData& mesh = ctx.mesh("spsm_triangles");
        mesh = MeshData();
        std::vector<float> texels, area;
        std::map<std::array<uint32_t, 4>, int> index;
        Image ids(size, size, 1);
        const LightView& view = ctx.lightView();
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                size_t k = (size_t(y) * size_t(size) + size_t(x)) * 4;
                std::array<uint32_t, 4> w{words[k], words[k + 1], words[k + 2], words[k + 3]};
                float& id = ids.at(x, size - 1 - y, 0);  // Image rows from the top
                if (w == std::array<uint32_t, 4>{0, 0, 0, 0}) {
                    id = -1.0f;
                    continue;
                }
                auto it = index.find(w);
                if (it == index.end()) {
                    int n = int(index.size());
                    it = index.emplace(w, n).first;
                    shared::SpsmTriangle t = shared::spsmUnpack(glm::uvec4(w[0], w[1], w[2], w[3]), float(size));
                    for (glm::vec2 v : {t.a, t.b, t.c}) {
                        float z = shared::spsmDepthAt(t, v);
                        mesh.positions.push_back(worldPoint(view, size, v, std::min(z, view.farZ * 4.0f)));
                        mesh.indices.push_back(uint32_t(mesh.positions.size() - 1));
                    }
                    texels.push_back(0.0f);
                    area.push_back(0.5f * std::abs(shared::spsmEdgeFunction(t.a, t.b, t.c)));
                }
                id = float(it->second);
                texels[size_t(it->second)] += 1.0f;
            }
        }
        std::vector<float> ordinal(texels.size());
        for (size_t i = 0; i < ordinal.size(); ++i) ordinal[i] = float(i);
        mesh.primitiveAttributes = {{"id", ordinal}, {"texels", texels}, {"area_texels", area}};
        uploadTexture(ctx.texture("spsm_triangle_id"), 0, 0, ids);
    }
};

// Which texels' triangles a receiver's look-up reads, and what it decides (lookup.comp, on the CPU).
uint32_t wordAt(const std::vector<uint32_t>& words, int size, glm::ivec2 t, int c) {
    return words[(size_t(t.y) * size_t(size) + size_t(t.x)) * 4 + size_t(c)];
}
glm::uvec4 texelAt(const std::vector<uint32_t>& words, int size, glm::ivec2 t) {
    return glm::uvec4(wordAt(words, size, t, 0), wordAt(words, size, t, 1), wordAt(words, size, t, 2),
                      wordAt(words, size, t, 3));
}

}  // namespace

const std::array<SpsmBranch, 9>& spsmBranches() {
    static const std::array<SpsmBranch, 9> b{{
        {"background", "no geometry"},
        {"on_triangle", "the texel's stored triangle covers p's projection at or behind p: lit"},
        {"hit", "the ray from p to the light meets the texel's stored triangle: shadowed"},
        {"neighbour_hit", "the ray meets a stored triangle of the neighbourhood: shadowed"},
        {"neighbour_cover", "a neighbour's triangle covers p's projection at or behind p, none is hit: lit"},
        {"reconstructed_edge", "no stored triangle covers p's projection: the shadow edge rebuilt from the 3x3 "
                               "neighbours' vertices decides"},
        {"fallback", "no edge to rebuild (uniform 3x3 comparisons, no tangent or vertex): the depth comparison "
                     "with p's own texel; with reconstruction off, lit (no stored triangle met)"},
        {"empty", "no caster touches p's texel (conservative rasterization), or p is outside the light's frustum: lit"},
        {"facing_away", "p faces away from the light centre: 0 (the tangent-plane convention)"},
    }};
    return b;
}

std::string spsmConservativeMethod() {
    GLenum cap = hardwareConservativeCap();
    if (cap == kConservativeNV) return "GL_NV_conservative_raster";
    if (cap == kConservativeIntel) return "GL_INTEL_conservative_rasterization";
    return "geometry shader";
}

SpsmLookup spsmLookup(const std::vector<uint32_t>& words, int size, glm::vec2 x, float z, float bias, int neighbourhood,
                      bool reconstruction) {
    using namespace shared;
    SpsmLookup r;
    int last = size - 1;
    glm::ivec2 t = glm::clamp(glm::ivec2(glm::floor(x)), glm::ivec2(0), glm::ivec2(last));
    r.texel = t;
    float sz = float(size);
    glm::uvec4 w = texelAt(words, size, t);
    if (spsmEmpty(w)) {
        r.branch = 7;
        return r;
    }
    r.tested.push_back(t);
    int test = spsmTriangleTest(spsmUnpack(w, sz), x, z, bias);
    r.results.push_back(test);
    if (test == 1 || test == 2) {
        r.branch = test;
        r.visibility = test == 1 ? 1.0f : 0.0f;
        return r;
    }
    int radius = neighbourhood / 2;
    bool hit = false, covered = false;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            glm::ivec2 q = t + glm::ivec2(dx, dy);
            if ((dx == 0 && dy == 0) || q.x < 0 || q.y < 0 || q.x > last || q.y > last) continue;
            glm::uvec4 n = texelAt(words, size, q);
            if (spsmEmpty(n)) continue;
            int k = spsmTriangleTest(spsmUnpack(n, sz), x, z, bias);
            r.tested.push_back(q);
            r.results.push_back(k);
            hit = hit || k == 2;
            covered = covered || k == 1;
        }
    if (hit || covered) {
        r.branch = hit ? 3 : 4;
        r.visibility = hit ? 0.0f : 1.0f;
        return r;
    }
    SpsmTriangle tris[9];
    unsigned occluding = 0;
    for (int k = 0; k < 9; ++k) {
        glm::ivec2 q = glm::clamp(t + glm::ivec2(k % 3 - 1, k / 3 - 1), glm::ivec2(0), glm::ivec2(last));
        glm::uvec4 n = texelAt(words, size, q);
        tris[k] = spsmUnpack(n, sz);
        if (!spsmEmpty(n) && spsmOccludesByDepth(tris[k], glm::vec2(q) + 0.5f, z, bias)) occluding |= 1u << k;
    }
    r.occluding = occluding;
    if (reconstruction && occluding != 0u && occluding != 511u) {
        SpsmEdge e = spsmReconstructEdge(tris, occluding, x, glm::vec2(t) + 0.5f);
        r.edge = e;
        r.reconstructed = true;
        if (e.decided == 1) {
            r.branch = 5;
            r.visibility = 1.0f - e.shadowed;
            return r;
        }
    }
    r.branch = 6;
    r.visibility = reconstruction && ((occluding >> 4u) & 1u) ? 0.0f : 1.0f;
    return r;
}

namespace {

nlohmann::json vec2Json(glm::vec2 v) { return {v.x, v.y}; }

InternalDesc spsmPixelRecord() {
    InternalDesc r;
    r.name = "pixel";
    r.kind = InternalDesc::Kind::Record;
    r.doc = "the picked pixel's look-up: its texel, the stored triangles it tested and what each said, the "
            "reconstructed edge (--pixel x,y)";
    r.schema = {{"background", "true when no geometry covers the pixel (then no other field)"},
                {"spsm_position", "p's projection x in SPSM space (texel coordinates, y from the bottom)"},
                {"receiver_depth", "p's light-view depth z (world units)"},
                {"bias", "the shadow map's depth bias at p (world units); each triangle test adds that triangle's packing error"},
                {"texel", "the texel x falls in"},
                {"branch", "the look-up step that decided (background, on_triangle, hit, neighbour_hit, neighbour_cover, "
                           "reconstructed_edge, fallback, empty, facing_away)"},
                {"tested", "per stored triangle intersected, in order: texel, vertices (SPSM space), depth at x "
                           "(null: the plane is not in front along the ray) and result (miss, behind_or_on, hit)"},
                {"occluding", "the 3x3 depth comparisons of the reconstruction (rows from the bottom, true = in front "
                              "of p), null when the look-up ended before"},
                {"edge", "the reconstructed edge: normal (towards the shadow), tangent, linked vertices left and right, "
                         "d_edge and d_p along the normal from the texel centre, kept vertices; null when none"},
                {"visibility", "this light's visibility at the pixel (the GPU's)"},
                {"cpu_visibility", "the same look-up run on the CPU from the stored triangles (equal to visibility)"}};
    r.reads = {"gbuffer", "light", "spsm", "visibility", "spsm_branch", "param:bias_const", "param:bias_slope",
               "param:neighbourhood", "param:reconstruction", "param:sm_size"};
    r.record = [](PassContext& ctx, glm::ivec2 pixel) {
        int row = ctx.height() - 1 - pixel.y;
        glm::vec4 position(0.0f), normal(0.0f);
        resetPackState();
        glGetTextureSubImage(ctx.gbuffer().position->id(), 0, pixel.x, row, 0, 1, 1, 1, GL_RGBA, GL_FLOAT,
                             sizeof position, &position);
        glGetTextureSubImage(ctx.gbuffer().normal->id(), 0, pixel.x, row, 0, 1, 1, 1, GL_RGBA, GL_FLOAT, sizeof normal,
                             &normal);
        nlohmann::json j;
        if (position.w == 0.0f) {
            j["background"] = true;
            return j;
        }
        const LightView& view = ctx.lightView();
        const Texture& map = ctx.texture("spsm");
        int size = map.width();
        glm::vec3 p(position), n(normal);
        glm::vec4 coord = shared::shadowMapCoord(view.viewFromWorld, view.clipFromView, p);
        float texelWorld = shared::shadowTexelWorldSize(coord.z, view.tanHalfFov, float(size));
        float cosTheta = std::abs(glm::dot(n, glm::normalize(ctx.light().position - p)));
        float bias = shared::shadowDepthBias(texelWorld, float(ctx.param("bias_const")), float(ctx.param("bias_slope")),
                                             cosTheta);
        glm::vec2 x = glm::vec2(coord) * float(size);
        j["spsm_position"] = vec2Json(x);
        j["receiver_depth"] = coord.z;
        j["bias"] = bias;
        std::vector<uint32_t> words = readTextureUint(map);
        SpsmLookup l;
        if (!shared::inFrontOfTangentPlane(p, n, ctx.light().position)) {
            l.branch = 8;
            l.visibility = 0.0f;
        } else if (coord.w == 0.0f) {
            l.branch = 7;
        } else {
            l = spsmLookup(words, size, x, coord.z, bias, ctx.paramInt("neighbourhood"), ctx.paramBool("reconstruction"));
        }
        j["texel"] = {l.texel.x, l.texel.y};
        j["branch"] = spsmBranches()[size_t(l.branch)].name;
        j["tested"] = nlohmann::json::array();
        static const char* results[] = {"miss", "behind_or_on", "hit"};
        for (size_t i = 0; i < l.tested.size(); ++i) {
            shared::SpsmTriangle t = shared::spsmUnpack(texelAt(words, size, l.tested[i]), float(size));
            float z = shared::spsmDepthAt(t, x);
            j["tested"].push_back({{"texel", {l.tested[i].x, l.tested[i].y}},
                                   {"vertices", {vec2Json(t.a), vec2Json(t.b), vec2Json(t.c)}},
                                   {"depth_at_x", z < 1e29f ? nlohmann::json(z) : nlohmann::json(nullptr)},
                                   {"result", results[l.results[i]]}});
        }
        bool reached = l.branch == 5 || l.branch == 6;
        if (reached) {
            nlohmann::json rows = nlohmann::json::array();
            for (int dy = 0; dy < 3; ++dy) {
                nlohmann::json rowJ = nlohmann::json::array();
                for (int dx = 0; dx < 3; ++dx) rowJ.push_back(bool((l.occluding >> unsigned(dy * 3 + dx)) & 1u));
                rows.push_back(rowJ);
            }
            j["occluding"] = rows;
        } else {
            j["occluding"] = nullptr;
        }
        if (l.reconstructed && l.edge.decided == 1) {
            j["edge"] = {{"normal", vec2Json(l.edge.normal)},
                         {"tangent", vec2Json(glm::vec2(-l.edge.normal.y, l.edge.normal.x))},
                         {"left", vec2Json(l.edge.left)},
                         {"right", vec2Json(l.edge.right)},
                         {"d_edge", l.edge.dEdge},
                         {"d_p", l.edge.dPoint},
                         {"kept_vertices", l.edge.kept},
                         {"shadowed", l.edge.shadowed != 0.0f}};
        } else {
            j["edge"] = nullptr;
        }
        j["visibility"] = ctx.pixelValue("visibility", pixel);
        j["cpu_visibility"] = l.visibility;
        return j;
    };
    return r;
}

ResourceDesc meshResource(const std::string& name, const std::string& doc) {
    ResourceDesc d;
    d.name = name;
    d.kind = ResourceKind::Mesh;
    d.doc = doc;
    return d;
}

}  // namespace

const TechniqueDesc& spsmTechnique() {
    static const TechniqueDesc desc = [] {
        using T = ParamDesc::Type;
        TechniqueDesc d;
        d.id = "spsm";
        d.name = "Sub-pixel shadow map";
        d.citation = "lecocq2014, Sub-pixel shadow mapping (I3D 2014 poster); Hasselgren et al. 2005 (conservative "
                     "rasterization); Dai et al. 2008 as neighbourhood 5 or 7 without reconstruction";
        d.summary = "hard shadows with sub-pixel edges: the closest triangle per texel (conservative rasterization, "
                    "128 bits), ray/triangle tests in the texel and its neighbours, the shadow edge rebuilt from their "
                    "vertices; an area light is taken at its centre";
        d.soft = false;
        std::vector<ParamDesc> sm = shadowMapParams();
        ParamDesc size = sm[0];
        size.defaultValue = 512;
        size.doc = "SPSM resolution (width = height); 512 as the paper (16 bytes a texel: 4 MB)";
        ParamDesc biasConst = sm[1];
        biasConst.defaultValue = 0.5;
        biasConst.doc = "constant depth bias in world-size texels at the receiver; the tests compare with the stored "
                        "plane at p's own projection, so half a texel suffices (each tested triangle's packing error "
                        "is added on top)";
        ParamDesc biasSlope = sm[2];
        biasSlope.defaultValue = 0.5;
        biasSlope.doc = "slope-scaled bias: texels times tan(theta) (receivers at grazing incidence)";
        d.params = {size, biasConst, biasSlope};
        d.params.push_back({"conservative", "", T::Bool, "", 1, 0, 1, 1,
                            "conservative rasterization of the build (the paper): every texel a triangle touches gets "
                            "it; off: the rasterizer's centre samples, which miss the edge texels",
                            ""});
        ParamDesc k{"neighbourhood", "", T::Int, "texels", 3, 1, 7, 2,
                    "k x k texels whose triangles the ray is intersected with: 3 as the paper; 5 and 7 with "
                    "reconstruction off are Dai et al. 2008's larger neighbourhoods; 1: the texel's own triangle "
                    "alone (off: the first step and nothing after it, the look-up's least cost)",
                    ""};
        k.constraint = ParamDesc::Constraint::Odd;
        d.params.push_back(k);
        d.params.push_back({"reconstruction", "", T::Bool, "", 1, 0, 1, 1,
                            "rebuild the shadow edge from the 3x3 neighbours' vertices where no stored triangle "
                            "covers p (the paper); off: a ray that meets no stored triangle is lit (Dai et al. 2008)",
                            ""});

        PassDesc build;
        build.name = "build";
        build.doc = "the casters from the light's centre, conservatively rasterized (geometry shader, or the driver's "
                    "extension): per texel the triangle nearest over the texel's footprint, packed in 128 bits";
        build.reads = {"scene.casters", "light", "param:sm_size", "param:conservative"};
        build.creates = {
            ResourceDesc::texture("spsm", Format::RGBA32UI, SizeRule::shadowMap(),
                                  "the sub-pixel shadow map: per texel the closest triangle, 128 bits (shaders/shared/"
                                  "spsm.glsl: three 14-bit vertices, 1/z at one and the two differences); 0 = no caster"),
            ResourceDesc::texture("spsm_zbuffer", Format::DEPTH32F, SizeRule::shadowMap(),
                                  "reversed depth of the build: near / z of each texel's nearest footprint depth (scratch)")};
        build.state = PipelineState::depthGreaterReversed();
        build.create = [] { return std::make_unique<BuildPass>(); };

        PassDesc lookup;
        lookup.name = "visibility";
        lookup.doc = "per receiver: the texel's triangle; the pixels it leaves undecided listed, and only those tested "
                     "against the k x k neighbours' triangles, then the reconstructed edge";
        lookup.reads = {"gbuffer", "light", "spsm", "param:bias_const", "param:bias_slope", "param:neighbourhood",
                        "param:reconstruction"};
        ResourceDesc counts;
        counts.name = "spsm.counts";
        counts.kind = ResourceKind::StorageBuffer;
        counts.size = SizeRule::fixed(8, 1);
        counts.elementBytes = 4;
        counts.scratch = true;
        counts.doc = "[0] pixels the texel's own triangle left undecided (spsm.list1), [1-3] the neighbourhood "
                     "step's dispatch, [4] pixels the neighbourhood left undecided (spsm.list2), [5-7] the "
                     "reconstruction step's dispatch";
        ResourceDesc list1 = counts;
        list1.name = "spsm.list1";
        list1.size = SizeRule::frame();
        list1.doc = "the pixels the texel's own triangle left undecided, x | y << 16, in the order the atomic counter "
                    "gave them";
        list1.unordered = true;
        list1.scratch = true;  // each execution (each of refineFrame's bands) fills it anew
        ResourceDesc list2 = list1;
        list2.name = "spsm.list2";
        list2.doc = "the pixels the k x k neighbourhood left undecided (the reconstruction's), x | y << 16, in the "
                    "order the atomic counter gave them";
        lookup.creates = {visibilityResource(),
                          ResourceDesc::texture("spsm_branch", Format::R32F, SizeRule::frame(),
                                                "the look-up step that decided each pixel (shaders/spsm/branches.glsl)"),
                          counts, list1, list2};
        lookup.create = [] { return std::make_unique<LookupPass>(); };

        PassDesc stored;
        stored.name = "stored_triangles";
        stored.doc = "for the internals: the distinct stored triangles as a world mesh and the triangle index per texel";
        stored.reads = {"spsm", "light", "param:sm_size"};
        stored.creates = {meshResource("spsm_triangles", "the distinct triangles the SPSM stores, in world space "
                                                         "(unpacked: the stored precision)"),
                          ResourceDesc::texture("spsm_triangle_id", Format::R32F, SizeRule::shadowMap(),
                                                "per texel the index of its triangle in spsm_triangles (-1: none)")};
        stored.create = [] { return std::make_unique<StoredTrianglesPass>(); };

        d.passes = {build, lookup, stored};
        d.internals = {
            {"triangle_id", InternalDesc::Kind::Image, "spsm_triangle_id", {"id"},
             "per SPSM texel the index of its stored triangle in stored_triangles (-1: no caster)"},
            {"stored_triangles", InternalDesc::Kind::Mesh, "spsm_triangles", {},
             "the stored triangles in world space, with their id, texel count and area in texels"},
            {"branches", InternalDesc::Kind::Image, "spsm_branch", {"branch"},
             "the look-up step that decided each pixel: 1 on-triangle, 2 hit, 3 neighbour hit, 4 neighbour cover, "
             "5 reconstructed edge, 6 fallback, 7 empty texel, 8 facing away, 0 background"},
        };
        d.internals.push_back(spsmPixelRecord());

        CounterDesc counter;
        counter.name = "spsm";
        counter.doc = "how the build rasterized conservatively, the SPSM's memory, the pixels each look-up step "
                      "decided, and the pixels each step ran on (step_pixels: every pixel, then the lists)";
        counter.reads = {"spsm", "spsm_branch", "spsm.counts", "param:conservative"};
        counter.count = [](PassContext& ctx) {
            nlohmann::json j;
            j["rasterization"] = ctx.paramBool("conservative") ? spsmConservativeMethod() : "centre sampling";
            const Texture& map = ctx.texture("spsm");
            j["memory_bytes"] = size_t(map.width()) * size_t(map.height()) * 16u;
            Image b = readTexture(ctx.texture("spsm_branch"), 1);
            std::array<size_t, 9> counts{};
            for (float v : b.data) {
                int k = int(std::lround(v));
                if (k >= 0 && k < 9) ++counts[size_t(k)];
            }
            nlohmann::json pixels;
            for (size_t k = 1; k < counts.size(); ++k) pixels[spsmBranches()[k].name] = counts[k];
            j["pixels"] = pixels;
            // How many pixels each look-up step ran on (lookup.comp's lists).
            std::array<GLuint, 8> lists{};
            glGetNamedBufferSubData(ctx.buffer("spsm.counts"), 0, GLsizeiptr(sizeof lists), lists.data());
            j["step_pixels"] = {{"texel", size_t(ctx.width()) * size_t(ctx.height())},
                                {"neighbourhood", lists[0]},
                                {"reconstruction", lists[4]}};
            return j;
        };
        d.counters = {counter};
        return d;
    }();
    return desc;
}

}  // namespace shadowlab

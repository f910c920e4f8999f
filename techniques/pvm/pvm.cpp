// `pvm`: penumbra volume maps (cournia2005 chapter 4). Four passes, the dissertation's three and the
// CPU geometry it builds between them:
//  1. shadow_map: the light-centre shadow map (sec. 4, "the first pass is trivial");
//  2. volumes (CPU): the winged-edge silhouette from the light centre, the extrusion vectors and an
//     outer and an inner quadrilateral per edge (sec. 4.1.1-4.1.2; pvm.h, geometry.cpp);
//  3. volume_map: the quads rendered from the light into the PVDM and the two PVEM in one pass with
//     three render targets (sec. 4.1.3);
//  4. visibility: Listing 4.2 per pixel (sec. 4.2), with the shared math of
//     shaders/shared/penumbra_volumes.glsl.
#include "pvm/pvm.h"
#include "pvm/volume_draw.h"

#include <cfloat>
#include <cstdio>
#include <set>

#include "gl/buffer.h"
#include "gl/texture.h"
#include "gl/util.h"
#include "graph/frame.h"
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

float lightRadiusOf(const Light& light) {
    return light.isPoint() ? 0.0f : shared::pvmLightRadius(int(light.shape), light.size);
}

// ---- 2. silhouettes, extrusion vectors, volume quads ---------------------------------------------

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
        const PvmGeometry g = buildPvmGeometry(scene, casters_, ctx.sceneTime(true), light.position, r);
        const float w = pvmExtrusionLength(ctx.sceneBounds(), light.position);
        writePvmMeshes(scene, g, [w](const PvmEdge& e, float side) { return pvmQuad(e, side, w); },
                       ctx.mesh("silhouettes"), ctx.mesh("penumbra_volumes"));
        for (const std::string& warning : g.warnings)
            if (warned_.insert(warning).second) std::fprintf(stderr, "shadowlab: warning: pvm: %s\n", warning.c_str());
    }

private:
    const Scene* scene_ = nullptr;
    std::vector<SsvCaster> casters_;
    std::set<std::string> warned_;
};

// ---- 3. the penumbra volume map: PVDM and two PVEM in one pass -----------------------------------

class VolumeMapPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        // split_sides: the outer volumes into pvdm, pvem0, pvem1 and the inner ones into their own
        // maps (README.md, "Sides kept apart"); else every volume into the first three (sec. 4.1.3).
        const bool split = ctx.param("split_sides") != 0.0;
        const MeshData& volumes = ctx.mesh("penumbra_volumes");
        const MeshData& lines = ctx.mesh("silhouettes");
        const std::vector<float>& edgeOf = volumes.primitiveAttributes[0].second;
        const std::vector<float>& side = volumes.primitiveAttributes[1].second;
        std::vector<glm::vec4>& outer = draw_.begin(volumes.indices.size());
        std::vector<glm::vec4>& inner = innerDraw_.begin(split ? volumes.indices.size() : 0);
        // Per vertex: the position, then the edge's end points with its index and the side.
        for (size_t i = 0; i < volumes.indices.size(); ++i) {
            const size_t tri = i / 3;
            const size_t edge = size_t(edgeOf[tri]);
            const glm::vec3 h0 = lines.positions[lines.indices[2 * edge]], h1 = lines.positions[lines.indices[2 * edge + 1]];
            std::vector<glm::vec4>& to = split && side[tri] != 0.0f ? inner : outer;
            to.push_back(glm::vec4(volumes.positions[volumes.indices[i]], 1.0f));
            to.push_back(glm::vec4(h0, edgeOf[tri]));
            to.push_back(glm::vec4(h1, side[tri]));
        }
        Texture& zbuffer = ctx.texture("pvm_zbuffer");
        render(ctx, draw_, outerFbo_, {"pvdm", "pvem0", "pvem1"}, zbuffer);
        if (split) render(ctx, innerDraw_, innerFbo_, {"pvdm_inner", "pvem0_inner", "pvem1_inner"}, zbuffer);
    }

private:
    static void render(PassContext& ctx, VolumeDraw& draw, FramebufferCache& cache,
                       const std::array<const char*, 3>& targets, Texture& zbuffer) {
        Texture& depth = ctx.texture(targets[0]);
        const Framebuffer& fbo = cache.get({&depth, &ctx.texture(targets[1]), &ctx.texture(targets[2])}, &zbuffer);
        const int size = depth.width();
        fbo.bind(size, size);
        const float none = FLT_MAX, zero[4] = {0, 0, 0, 0}, depthClear = 0.0f;
        glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, &none);
        glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 1, zero);
        glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 2, zero);
        glClearNamedFramebufferfv(fbo.id(), GL_DEPTH, 0, &depthClear);
        draw.draw(ctx, "pvm/volume.frag");
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

    FramebufferCache outerFbo_, innerFbo_;
    VolumeDraw draw_, innerDraw_;
};

// ---- 4. visibility (Listing 4.2) ------------------------------------------------------------------

class VisibilityPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& visibility = ctx.texture("visibility");
        const Framebuffer& fbo = fbo_.get({&visibility}, nullptr);
        const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "pvm/visibility.frag");
        program.use();
        const Light& light = ctx.light();
        const Texture& map = ctx.texture(shadowTestMap(ctx));
        setShadowLookupUniforms(program, ctx.lightView(), map.width(), light);
        program.set("biasConstTexels", float(ctx.param("bias_const")));
        program.set("biasSlopeTexels", float(ctx.param("bias_slope")));
        program.set("lightRadius", lightRadiusOf(light));
        program.set("frontShape", light.isPoint() ? int(LightShape::Point) : int(light.shape));
        program.set("lightRight", light.isPoint() ? glm::vec3(0.0f) : light.right());
        program.set("lightUp", light.up);
        program.set("lightSize", light.isPoint() ? 0.0f : light.size);
        ctx.bindGBuffer(program);
        glBindTextureUnit(3, map.id());
        program.set("shadowMap", 3);
        glBindTextureUnit(4, ctx.texture("pvdm").id());
        program.set("volumeDepthMap", 4);
        glBindTextureUnit(5, ctx.texture("pvem0").id());
        program.set("edgeMap0", 5);
        glBindTextureUnit(6, ctx.texture("pvem1").id());
        program.set("edgeMap1", 6);
        // Without split_sides the inner maps do not exist and the shader does not read them; the
        // outer ones stand in for the samplers.
        const bool split = ctx.param("split_sides") != 0.0;
        glBindTextureUnit(7, ctx.texture(split ? "pvdm_inner" : "pvdm").id());
        program.set("innerDepthMap", 7);
        glBindTextureUnit(8, ctx.texture(split ? "pvem0_inner" : "pvem0").id());
        program.set("innerEdgeMap0", 8);
        glBindTextureUnit(9, ctx.texture(split ? "pvem1_inner" : "pvem1").id());
        program.set("innerEdgeMap1", 9);
        program.set("splitSides", split ? 1 : 0);
        fbo.bind(ctx.width(), ctx.height());
        drawFullscreenTriangle();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    FramebufferCache fbo_;
};

glm::vec4 texelOf(const Texture& texture, glm::ivec2 t) {
    glm::vec4 v(0.0f);
    resetPackState();
    glGetTextureSubImage(texture.id(), 0, t.x, t.y, 0, 1, 1, 1, GL_RGBA, GL_FLOAT, sizeof v, &v);
    return v;
}

}  // namespace

std::optional<RecordReceiver> beginReceiverRecord(PassContext& ctx, glm::ivec2 pixel, nlohmann::json& j) {
    const int row = ctx.height() - 1 - pixel.y;
    const glm::vec4 position = texelOf(*ctx.gbuffer().position, {pixel.x, row});
    const glm::vec4 normal = texelOf(*ctx.gbuffer().normal, {pixel.x, row});
    if (position.w == 0.0f) {
        j["background"] = true;
        return std::nullopt;
    }
    const Light& light = ctx.light();
    const LightView& view = ctx.lightView();
    RecordReceiver r;
    r.p = glm::vec3(position);
    r.n = glm::vec3(normal);
    r.coord = shared::shadowMapCoord(view.viewFromWorld, view.clipFromView, r.p);
    j["receiver"] = {r.p.x, r.p.y, r.p.z};
    j["receiver_depth"] = r.coord.z;
    r.front = shared::lightFractionInFront(light.isPoint() ? int(LightShape::Point) : int(light.shape), light.position,
                                           light.isPoint() ? glm::vec3(0.0f) : light.right(), light.up,
                                           light.isPoint() ? 0.0f : light.size, r.p, r.n);
    j["front_fraction"] = r.front;
    return r;
}

namespace {

// The picked pixel: which volume covered it, the cutting plane and the disk segment (sec. 4.2), as
// the visibility pass computed them.
InternalDesc pvmPixelRecord() {
    InternalDesc r;
    r.name = "pixel";
    r.kind = InternalDesc::Kind::Record;
    r.doc = "the picked pixel's penumbra volume look-up (--pixel x,y): the volume covering it, the cutting plane "
            "and the disk segment of eq. 4.1-4.2";
    r.schema = {{"background", "true when no geometry covers the pixel (then no other field)"},
                {"receiver", "the receiver's world position"},
                {"receiver_depth", "its light-view depth z (world units)"},
                {"map_texel", "the PVDM / PVEM / shadow-map texel it projects to (x, y from the bottom); null outside "
                              "the light's frustum"},
                {"maps", "which volume maps the receiver read: \"both sides\" (split_sides 0, the dissertation's one "
                         "map), \"outer\" (the shadow-map test lit) or \"inner\" (shadowed)"},
                {"volume_depth", "the PVDM's depth there (null: no volume)"},
                {"in_volume", "volume_depth < receiver_depth (Listing 4.2, line 15)"},
                {"volume", "when in a volume: the silhouette edge (index into the silhouettes internal, its end "
                           "points h0, h1 from the PVEM) and the side (outer or inner) of the volume"},
                {"cutting_plane", "when in a volume: n and d of the plane through h0, h1 and the receiver"},
                {"light_distance", "s = n . l + d, the light centre's signed distance from the cutting plane"},
                {"disk", "the disk of radius r about the light centre perpendicular to the plane: centre, r, the unit "
                         "normal n (the disk's axis in the plane of the figure), segment_area a = eq. 4.1 at -s (the "
                         "part on the visible side), k = 2a / (pi r^2) (eq. 4.2)"},
                {"v_volume", "3k^2 - 2k^3"},
                {"v_side", "split_sides: v_volume kept on the side of 1/2 the shadow-map test gives (pvmSideVisibility)"},
                {"shadow_test", "outside a volume: the shadow-map test (1 lit, 0 umbra)"},
                {"front_fraction", "the fraction of the light in front of the receiver's tangent plane"},
                {"visibility_from_record", "what the fields give: (v_side, v_volume or shadow_test) x front_fraction"},
                {"visibility", "this light's visibility at the pixel, read from the visibility pass"}};
    r.reads = {"gbuffer", "light", "pvdm", "pvem0", "pvem1", "pvdm_inner", "pvem0_inner", "pvem1_inner", "silhouettes",
               "shadow_map", "shadow_map_second_depth", "param:second_depth", "param:bias_const", "param:bias_slope",
               "param:split_sides", "visibility"};
    r.record = [](PassContext& ctx, glm::ivec2 pixel) {
        nlohmann::json j;
        const std::optional<RecordReceiver> receiver = beginReceiverRecord(ctx, pixel, j);
        if (!receiver) return j;
        const Light& light = ctx.light();
        const LightView& view = ctx.lightView();
        const glm::vec3 p = receiver->p, n = receiver->n;
        const glm::vec4 coord = receiver->coord;
        const float front = receiver->front;
        float v = 1.0f;
        j["map_texel"] = nullptr;
        j["in_volume"] = false;
        // Every field of the schema is present; those of the branch not taken are null.
        for (const char* f : {"maps", "volume_depth", "volume", "cutting_plane", "light_distance", "disk", "v_volume",
                              "v_side", "shadow_test"})
            j[f] = nullptr;
        if (front > 0.0f && coord.w != 0.0f) {
            // The shadow-map test first: it decides outside the volumes and, with split_sides, which
            // side's maps the receiver reads.
            const Texture& map = ctx.texture(shadowTestMap(ctx));
            const float texelWorld = shared::shadowTexelWorldSize(coord.z, view.tanHalfFov, float(map.width()));
            const float cosTheta = std::abs(glm::dot(n, glm::normalize(light.position - p)));
            const float bias = shared::shadowDepthBias(texelWorld, float(ctx.param("bias_const")),
                                                       float(ctx.param("bias_slope")), cosTheta);
            const glm::ivec2 ts = glm::clamp(glm::ivec2(glm::floor(glm::vec2(coord) * float(map.width()))),
                                             glm::ivec2(0), glm::ivec2(map.width() - 1));
            const float centre = shared::shadowDepthTest(coord.z, texelOf(map, ts).x, bias);
            const bool split = ctx.param("split_sides") != 0.0;
            const bool inner = split && centre < 0.5f;
            j["maps"] = !split ? "both sides" : inner ? "inner" : "outer";
            const Texture& pvdm = ctx.texture(inner ? "pvdm_inner" : "pvdm");
            const int size = pvdm.width();
            const glm::ivec2 t = glm::clamp(glm::ivec2(glm::floor(glm::vec2(coord) * float(size))), glm::ivec2(0),
                                            glm::ivec2(size - 1));
            j["map_texel"] = {t.x, t.y};
            const float vd = texelOf(pvdm, t).x;
            j["volume_depth"] = vd > 1e30f ? nlohmann::json(nullptr) : nlohmann::json(vd);
            if (vd < coord.z) {
                const glm::vec4 e0 = texelOf(ctx.texture(inner ? "pvem0_inner" : "pvem0"), t),
                                e1 = texelOf(ctx.texture(inner ? "pvem1_inner" : "pvem1"), t);
                const glm::vec3 h0(e0), h1(e1);
                const float r = lightRadiusOf(light);
                const glm::vec4 plane = shared::pvmCuttingPlane(h0, h1, p);
                const float s = glm::dot(glm::vec3(plane), light.position) + plane.w;
                const float k = shared::pvmDiskFraction(s, r);
                const float q = r > 0.0f ? glm::clamp(-s / r, -1.0f, 1.0f) : 0.0f;
                const float a = 0.5f * r * r * (std::acos(q) - q * std::sqrt(std::max(1.0f - q * q, 0.0f)));
                j["in_volume"] = true;
                j["volume"] = {{"edge", int(e0.w) - 1},
                               {"side", int(e1.w) - 1 == 0 ? "outer" : "inner"},
                               {"h0", {h0.x, h0.y, h0.z}},
                               {"h1", {h1.x, h1.y, h1.z}}};
                j["cutting_plane"] = {{"n", {plane.x, plane.y, plane.z}}, {"d", plane.w}};
                j["light_distance"] = s;
                j["disk"] = {{"centre", {light.position.x, light.position.y, light.position.z}},
                             {"radius", r},
                             {"normal", {plane.x, plane.y, plane.z}},
                             {"segment_area", a},
                             {"area", shared::PVM_PI * r * r},
                             {"k", k}};
                v = shared::pvmVisibility(p, h0, h1, light.position, r);
                j["v_volume"] = v;
                if (split) v = shared::pvmSideVisibility(v, centre);
                j["v_side"] = split ? nlohmann::json(v) : nlohmann::json(nullptr);
            } else {
                v = centre;
                j["shadow_test"] = v;
            }
        }
        j["visibility_from_record"] = front == 0.0f ? 0.0f : v * front;
        j["visibility"] = ctx.pixelValue("visibility", pixel);
        return j;
    };
    return r;
}

}  // namespace

const TechniqueDesc& pvmTechnique() {
    static const TechniqueDesc desc = [] {
        TechniqueDesc d;
        d.id = "pvm";
        d.name = "Penumbra volume maps";
        d.citation = "Cournia 2005, Penumbra volume maps and penumbra volume mask filtering (dissertation), chapter 4";
        d.summary = "inner and outer penumbra volumes extruded from the silhouette seen from the light centre, rendered "
                    "from the light into a depth map and two edge maps; a receiver inside a volume sees the part of the "
                    "light's disk beyond the cutting plane through its edge, any other the shadow-map test";
        d.soft = true;
        d.params = shadowMapParams();
        ParamDesc split{"split_sides", "", ParamDesc::Type::Bool, "", 1, 0, 1, 1,
                        "outer and inner volumes in maps of their own, read where the shadow-map test says lit and "
                        "shadowed, each value kept on its side of 1/2 (README.md, \"Sides kept apart\"); 0: the "
                        "dissertation's one map, nearest volume of either side (Fig. 4.7's overwrite)"};
        d.params.push_back(split);

        PassDesc volumes;
        volumes.name = "volumes";
        volumes.doc = "silhouette loops from the light centre (winged edges), each vertex's outer and inner extrusion "
                      "vectors and an outer and an inner quadrilateral per edge, on the CPU (sec. 4.1.1-4.1.2)";
        volumes.reads = {"scene.casters", "light"};
        volumes.creates = {
            meshResource("silhouettes", "silhouette edges from the light centre, clockwise seen from the light, with "
                                        "their loop neighbours (prev, next: -1 at a chain end)"),
            meshResource("penumbra_volumes", "the outer (side 0) and inner (side 1) volume quadrilaterals, two triangles "
                                             "each, with the edge they were extruded from, exactly as drawn")};
        volumes.soft = true;
        volumes.create = [] { return std::make_unique<VolumesPass>(); };

        PassDesc map;
        map.name = "volume_map";
        map.doc = "the volume quads rendered from the light into the PVDM (nearest volume depth) and the two PVEM "
                  "(the edge's end points) in one pass with three render targets (sec. 4.1.3)";
        map.reads = {"light", "penumbra_volumes", "silhouettes", "param:sm_size", "param:split_sides"};
        map.creates = {
            ResourceDesc::texture("pvdm", Format::R32F, SizeRule::shadowMap(),
                                  "penumbra volume depth map: light-view z of the nearest volume (FLT_MAX: none)"),
            ResourceDesc::texture("pvem0", Format::RGBA32F, SizeRule::shadowMap(),
                                  "penumbra volume edge map: h0 (world) of that volume's edge, w = edge index + 1"),
            ResourceDesc::texture("pvem1", Format::RGBA32F, SizeRule::shadowMap(),
                                  "penumbra volume edge map: h1 (world) of that volume's edge, w = side + 1"),
            ResourceDesc::texture("pvm_zbuffer", Format::DEPTH32F, SizeRule::shadowMap(),
                                  "reversed-depth z-buffer of the volume render (scratch)"),
            ResourceDesc::texture("pvdm_inner", Format::R32F, SizeRule::shadowMap(),
                                  "split_sides: the inner volumes' PVDM (pvdm then holds the outer volumes only)"),
            ResourceDesc::texture("pvem0_inner", Format::RGBA32F, SizeRule::shadowMap(),
                                  "split_sides: the inner volumes' PVEM h0, w = edge index + 1"),
            ResourceDesc::texture("pvem1_inner", Format::RGBA32F, SizeRule::shadowMap(),
                                  "split_sides: the inner volumes' PVEM h1, w = side + 1")};
        for (size_t i = map.creates.size() - 3; i < map.creates.size(); ++i) map.creates[i].appliesWhen = "split_sides == true";
        map.state = PipelineState::depthGreaterReversed();
        map.soft = true;
        map.create = [] { return std::make_unique<VolumeMapPass>(); };

        PassDesc visibility;
        visibility.name = "visibility";
        visibility.doc = "Listing 4.2: inside a volume, the disk fraction beyond the cutting plane through its edge "
                         "(eq. 4.1-4.2) and 3k^2 - 2k^3; elsewhere the shadow-map test; times the light's front fraction";
        visibility.reads = {"gbuffer", "light", "pvdm", "pvem0", "pvem1", "pvdm_inner", "pvem0_inner", "pvem1_inner",
                            "param:bias_const", "param:bias_slope", "param:split_sides"};
        for (const std::string& r : shadowTestReads()) visibility.reads.push_back(r);
        visibility.creates = {visibilityResource()};
        visibility.soft = true;
        visibility.create = [] { return std::make_unique<VisibilityPass>(); };

        d.passes = {shadowMapPass(), volumes, map, visibility};
        d.internals = shadowMapInternals();
        InternalDesc silhouettes{"silhouettes", InternalDesc::Kind::Lines, "silhouettes", {},
                                 "silhouette edges from the light centre, clockwise seen from the light"};
        InternalDesc volumeMesh{"penumbra_volumes", InternalDesc::Kind::Mesh, "penumbra_volumes", {},
                                "outer (side 0) and inner (side 1) penumbra volume quads, exactly as drawn"};
        InternalDesc pvdm{"pvdm", InternalDesc::Kind::Image, "pvdm", {"depth"},
                          "penumbra volume depth map: light-view z of the nearest volume (inf: none)"};
        pvdm.convert = farMarkerToInfinity;
        InternalDesc pvem0{"pvem0", InternalDesc::Kind::Image, "pvem0", {"x", "y", "z", "edge_plus_1"},
                           "penumbra volume edge map 0: the edge's first end point h0 (world), edge index + 1 (0: none)"};
        InternalDesc pvem1{"pvem1", InternalDesc::Kind::Image, "pvem1", {"x", "y", "z", "side_plus_1"},
                           "penumbra volume edge map 1: the edge's second end point h1 (world), side + 1 (1 outer, 2 "
                           "inner; 0: none)"};
        InternalDesc pvdmInner{"pvdm_inner", InternalDesc::Kind::Image, "pvdm_inner", {"depth"},
                               "split_sides: the inner volumes' depth map (pvdm then holds the outer ones)"};
        pvdmInner.convert = farMarkerToInfinity;
        pvdmInner.appliesWhen = "split_sides == true";
        d.internals.insert(d.internals.end(), {silhouettes, volumeMesh, pvdm, pvem0, pvem1, pvdmInner, pvmPixelRecord()});
        return d;
    }();
    return desc;
}

}  // namespace shadowlab

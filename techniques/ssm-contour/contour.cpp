// `ssm-contour`: guennebaud2007's visibility computation (section 4) on the HSM, kernel and
// classification of section 3 (techniques/hsm/): contour edges of the occluding samples found by the
// 2x2 rule table with parameter t (sec. 4.1, Fig. 3-4), back-projected onto the light, clipped to
// it and radially integrated with signed areas (sec. 4.2, Fig. 5a), starting from the full light or
// zero by the contour inside test at p' (Fig. 5b). Square and disk (and sphere) lights.
#include "hsm/hsm.h"

namespace shadowlab {

using namespace shared;

namespace {

// One block's edges, as contour_area.glsl computes them: the 3D extremities (map texel coordinates
// and the holders' depths) and their back-projections onto the light.
struct BlockEdge {
    glm::vec2 texelA, texelB;
    float depthA = 0.0f, depthB = 0.0f;
    glm::vec2 a, b;
};
struct Block {
    int mask = 0;
    int count = 0;
    BlockEdge edges[2];
};
Block evaluateBlock(const BackprojectionCpu& c, const BpReceiver& r, int level, glm::ivec2 corner, float t) {
    const glm::ivec2 offsets[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    float depths[4];
    Block b;
    for (int k = 0; k < 4; ++k) {
        glm::ivec2 s = corner + offsets[k];
        depths[k] = c.levelDepth(level, s);
        if (c.levelOccludes(r, level, s, depths[k])) b.mask |= 1 << k;
    }
    b.count = contourRule(b.mask).x;
    glm::vec2 centre = glm::vec2(corner) + 1.0f;
    const float scale = float(1 << level);
    for (int which = 0; which < b.count; ++which) {
        glm::vec4 e = contourEdge(b.mask, t, which);
        glm::ivec2 holders = contourEdgeHolders(b.mask, which);
        BlockEdge& out = b.edges[which];
        glm::vec2 ua = centre + glm::vec2(e.x, e.y), ub = centre + glm::vec2(e.z, e.w);
        out.texelA = ua * scale;
        out.texelB = ub * scale;
        out.depthA = depths[holders.x];
        out.depthB = depths[holders.y];
        out.a = c.backprojectLevel(r, ua, level, out.depthA);
        out.b = c.backprojectLevel(r, ub, level, out.depthB);
    }
    return b;
}

// contour_area.glsl's occludedAreaAtLevel on the CPU: the initial area (Fig. 5b) into `initial`,
// the edges' sum returned; `centreBlock` and `edges` (when given) receive the record's lists.
float contourLevelArea(const BackprojectionCpu& c, const BpReceiver& rc, glm::ivec4 range0, int level, float t0,
                       float* initial, nlohmann::json* centreBlock, nlohmann::json* edges) {
    const float t = level == 0 ? t0 : 1.0f;
    const int n = c.levelSize(level);
    glm::ivec4 range = levelTexelRange(range0, level, n);
    glm::ivec2 corner = glm::ivec2(glm::floor(rc.centre / float(1 << level) - 0.5f));
    Block centre = evaluateBlock(c, rc, level, corner, t);
    float turns[2] = {0.0f, 0.0f};
    for (int which = 0; which < centre.count; ++which) turns[which] = edgeTurn(centre.edges[which].a, centre.edges[which].b);
    bool occluded = contourCentreOccluded(centre.mask, t, turns[0], turns[1]);
    *initial = occluded ? bpLightArea(c.shape) : 0.0f;
    if (centreBlock)
        *centreBlock = {{"level", level},
                        {"corner", {corner.x, corner.y}},
                        {"mask", centre.mask},
                        {"turns", {turns[0], turns[1]}},
                        {"centre_occluded", occluded}};
    float sum = 0.0f;
    // contour_area.glsl's order: chunks of BP_ROW_CHUNK block columns, each row by row (the sum in
    // the same order as the GPU's; blocks that are not on the contour add nothing).
    const int columns = range.z - range.x + 2;
    for (int cx = 0; cx < columns; cx += BP_ROW_CHUNK)
        for (int by = range.y - 1; by <= range.w; ++by)
        for (int bx = range.x - 1 + cx; bx < range.x - 1 + cx + std::min(BP_ROW_CHUNK, columns - cx); ++bx) {
            Block b = evaluateBlock(c, rc, level, {bx, by}, t);
            for (int which = 0; which < b.count; ++which) {
                const BlockEdge& e = b.edges[which];
                float area = edgeOccludedArea(c.shape, e.a, e.b);
                sum += area;
                if (!edges) continue;
                glm::vec2 clipped = clipSegmentToLight(c.shape, e.a, e.b);
                if (clipped.x > clipped.y) continue;  // off the light: contributes nothing
                edges->push_back({{"block", {bx, by}},
                                  {"level", level},
                                  {"mask", b.mask},
                                  {"which", which},
                                  {"texel_a", {e.texelA.x, e.texelA.y, e.depthA}},
                                  {"texel_b", {e.texelB.x, e.texelB.y, e.depthB}},
                                  {"a", {e.a.x, e.a.y}},
                                  {"b", {e.b.x, e.b.y}},
                                  {"orientation", edgeTurn(e.a, e.b) > 0.0f ? "ccw" : "cw"},
                                  {"signed_area", area}});
            }
        }
    return sum;
}

InternalDesc contourPixelRecord() {
    InternalDesc r;
    r.name = "pixel";
    r.kind = InternalDesc::Kind::Record;
    r.doc = "the picked pixel's kernel, contour inside test and back-projected contour edges (--pixel x,y)";
    r.schema = backprojectionRecordSchema();
    r.schema.push_back({"centre_block", "the 2x2 block around p' (Fig. 5b) on the level walked: level, corner "
                                        "texel of that level, mask, edges' turns, centre_occluded (then initial_area is "
                                        "the full light)"});
    r.schema.push_back({"edges", "contour edges reaching the light, on the level walked: block corner texel of that "
                                 "level, level, mask, which (0/1), 3D extremities [map texel x, y, depth], a and b in "
                                 "light coordinates (occluder on the left), "
                                 "orientation (ccw: the light centre on the edge's left), signed area (occluded light "
                                 "area it adds, light coordinates)"});
    r.reads = backprojectionRecordReads();
    r.reads.push_back("param:t");
    r.reads.push_back("param:beta");
    r.record = [](PassContext& ctx, glm::ivec2 pixel) {
        const float beta = float(ctx.param("beta"));
        PixelRecordStart s = startPixelRecord(ctx, pixel, beta);
        float sum = 0.0f;
        BlendedLevelArea blended;
        if (!s.record.contains("background")) {
            s.record["centre_block"] = nullptr;  // lit and umbra pixels integrate nothing
            s.record["edges"] = nlohmann::json::array();
        }
        if (!s.done) {
            const float t = float(ctx.param("t"));
            nlohmann::json centre, edges = nlohmann::json::array();
            sum = contourLevelArea(s.cpu, s.receiver, s.range, s.level, t, &s.initialArea, &centre, &edges);
            s.record["centre_block"] = centre;
            s.record["edges"] = edges;
            if (s.blendWeight > 0.0f)
                blended.itemsArea =
                    contourLevelArea(s.cpu, s.receiver, s.range, s.blendLevel, t, &blended.initialArea, nullptr, nullptr);
        }
        finishPixelRecord(ctx, pixel, s, sum, &blended);
        return s.record;
    };
    return r;
}

}  // namespace

const TechniqueDesc& ssmContourTechnique() {
    static const TechniqueDesc desc = [] {
        TechniqueDesc d;
        d.id = "ssm-contour";
        d.name = "Soft shadow mapping with contour back-projection";
        d.citation = "Guennebaud, Barthe, Paulin 2007, High-quality adaptive soft shadow mapping, sec. 3-4 (eq. 1, "
                     "Fig. 2-5)";
        d.summary = "the contour of the occluding shadow-map samples back-projected onto the light and its covered "
                    "area integrated radially with signed areas: no gaps, no overlaps";
        d.soft = true;
        d.params = backprojectionParams();
        ParamDesc t{"t", "t", ParamDesc::Type::Float, "", 0.0, -1.0, 1.0, 0.05,
                    "contour offset t in [-1,1] (guennebaud2007 sec. 4.1): 0 joins the samples' borders, the paper's "
                    "recommended, most probable choice; 1 shrinks to occluder centres, -1 grows to background centres",
                    ""};
        d.params.push_back(t);
        ParamDesc beta{"beta", "beta", ParamDesc::Type::Float, "", 0.05, 0.0, 0.5, 0.01,
                       "width of the band of the continuous level lambda (eq. 3) where two HSM levels are blended "
                       "(guennebaud2007 sec. 5.1: \"beta = 0.05 is a typical choice\"); 0 shows the seams of Fig. 6a",
                       "light_multires == true"};
        d.params.push_back(beta);
        PassDesc visibility;
        visibility.name = "visibility";
        visibility.doc = "contour edges of the kernel's occluding samples (2x2 rules, t), back-projected, clipped and "
                         "radially integrated from the light centre, initialised by the contour inside test "
                         "(guennebaud2007 sec. 4)";
        visibility.reads = backprojectionVisibilityReads();
        visibility.reads.push_back("param:t");
        visibility.reads.push_back("param:beta");
        visibility.creates = {visibilityResource(), lightLevelsResource()};
        visibility.modifies = backprojectionVisibilityModifies();
        visibility.soft = true;
        visibility.create = [] {
            return std::make_unique<BackprojectionVisibilityPass>(
                "backprojection/contour.frag", "backprojection/contour_sparse.comp",
                [](PassContext& ctx, const ShaderProgram& p) {
                    p.set("contourT", float(ctx.param("t")));
                    p.set("contourBeta", ctx.param("light_multires") != 0.0 ? float(ctx.param("beta")) : 0.0f);
                });
        };
        d.passes = {shadowMapPass(), hsmPass(), kernelPass()};
        for (const PassDesc& p : screenSelectionPasses()) d.passes.push_back(p);
        d.passes.push_back(visibility);
        d.passes.push_back(screenPullPushPass());
        d.kernelCaps = {backprojectionKernelCap()};
        d.counters = {screenSelectionCounter()};
        d.internals = backprojectionInternals();
        d.internals.push_back(lightLevelsInternal());
        for (const InternalDesc& i : screenAdaptiveInternals()) d.internals.push_back(i);
        d.internals.push_back(contourPixelRecord());
        return d;
    }();
    return desc;
}

}  // namespace shadowlab

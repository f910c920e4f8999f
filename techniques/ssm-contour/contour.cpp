// `ssm-contour`: guennebaud2007's visibility computation (section 4) on the HSM, kernel and
// classification of section 3 (techniques/hsm/): contour edges of the occluding samples found by the
// 2x2 rule table with parameter t (sec. 4.1, Fig. 3-4), back-projected onto the light, clipped to
// it and radially integrated with signed areas (sec. 4.2, Fig. 5a), starting from the full light or
// zero by the contour inside test at p' (Fig. 5b). Square and disk (and sphere) lights.
#include "hsm/hsm.h"

namespace shadowlab {

using namespace shared;

namespace {

// One block's edges, as contour.frag computes them: the 3D extremities (texel coordinates and the
// holders' depths) and their back-projections onto the light.
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
Block evaluateBlock(const BackprojectionCpu& c, const BpReceiver& r, glm::ivec2 corner, float t) {
    const glm::ivec2 offsets[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    float depths[4];
    Block b;
    for (int k = 0; k < 4; ++k) {
        glm::ivec2 s = corner + offsets[k];
        depths[k] = c.depthAt(s);
        if (c.occludes(r, s, depths[k])) b.mask |= 1 << k;
    }
    b.count = contourRule(b.mask).x;
    glm::vec2 centre = glm::vec2(corner) + 1.0f;
    for (int which = 0; which < b.count; ++which) {
        glm::vec4 e = contourEdge(b.mask, t, which);
        glm::ivec2 holders = contourEdgeHolders(b.mask, which);
        BlockEdge& out = b.edges[which];
        out.texelA = centre + glm::vec2(e.x, e.y);
        out.texelB = centre + glm::vec2(e.z, e.w);
        out.depthA = depths[holders.x];
        out.depthB = depths[holders.y];
        out.a = backprojectToLight(r.position, out.texelA, out.depthA, float(c.size), c.view.tanHalfFov, c.lightHalfSize);
        out.b = backprojectToLight(r.position, out.texelB, out.depthB, float(c.size), c.view.tanHalfFov, c.lightHalfSize);
    }
    return b;
}

InternalDesc contourPixelRecord() {
    InternalDesc r;
    r.name = "pixel";
    r.kind = InternalDesc::Kind::Record;
    r.doc = "the picked pixel's kernel, contour inside test and back-projected contour edges (--pixel x,y)";
    r.schema = backprojectionRecordSchema();
    r.schema.push_back({"centre_block", "the 2x2 block around p' (Fig. 5b): corner texel, mask, edges' turns, "
                                        "centre_occluded (then initial_area is the full light)"});
    r.schema.push_back({"edges", "contour edges reaching the light: block corner texel, mask, which (0/1), 3D "
                                 "extremities [texel x, y, depth], a and b in light coordinates (occluder on the left), "
                                 "orientation (ccw: the light centre on the edge's left), signed area (occluded light "
                                 "area it adds, light coordinates)"});
    r.reads = backprojectionRecordReads();
    r.reads.push_back("param:t");
    r.record = [](PassContext& ctx, glm::ivec2 pixel) {
        PixelRecordStart s = startPixelRecord(ctx, pixel);
        float sum = 0.0f;
        if (!s.record.contains("background")) {
            s.record["centre_block"] = nullptr;  // lit and umbra pixels integrate nothing
            s.record["edges"] = nlohmann::json::array();
        }
        if (!s.done) {
            const BackprojectionCpu& c = s.cpu;
            const BpReceiver& rc = s.receiver;
            const float t = float(ctx.param("t"));
            // Initialisation (Fig. 5b).
            glm::ivec2 corner = glm::ivec2(glm::floor(rc.centre - 0.5f));
            Block centre = evaluateBlock(c, rc, corner, t);
            float turns[2] = {0.0f, 0.0f};
            for (int which = 0; which < centre.count; ++which)
                turns[which] = edgeTurn(centre.edges[which].a, centre.edges[which].b);
            bool occluded = contourCentreOccluded(centre.mask, t, turns[0], turns[1]);
            if (occluded) s.initialArea = bpLightArea(c.shape);
            s.record["centre_block"] = {{"corner", {corner.x, corner.y}},
                                        {"mask", centre.mask},
                                        {"turns", {turns[0], turns[1]}},
                                        {"centre_occluded", occluded}};
            // The kernel's blocks, in contour.frag's order.
            nlohmann::json edges = nlohmann::json::array();
            for (int by = s.range.y - 1; by <= s.range.w; ++by)
                for (int bx = s.range.x - 1; bx <= s.range.z; ++bx) {
                    Block b = evaluateBlock(c, rc, {bx, by}, t);
                    for (int which = 0; which < b.count; ++which) {
                        const BlockEdge& e = b.edges[which];
                        float area = edgeOccludedArea(c.shape, e.a, e.b);
                        sum += area;
                        glm::vec2 range = clipSegmentToLight(c.shape, e.a, e.b);
                        if (range.x > range.y) continue;  // off the light: contributes nothing
                        edges.push_back({{"block", {bx, by}},
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
            s.record["edges"] = edges;
        }
        finishPixelRecord(ctx, pixel, s, sum);
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
        PassDesc visibility;
        visibility.name = "visibility";
        visibility.doc = "contour edges of the kernel's occluding samples (2x2 rules, t), back-projected, clipped and "
                         "radially integrated from the light centre, initialised by the contour inside test "
                         "(guennebaud2007 sec. 4)";
        visibility.reads = backprojectionVisibilityReads();
        visibility.reads.push_back("param:t");
        visibility.creates = {visibilityResource()};
        visibility.soft = true;
        visibility.create = [] {
            return std::make_unique<BackprojectionVisibilityPass>(
                "backprojection/contour.frag",
                [](PassContext& ctx, const ShaderProgram& p) { p.set("contourT", float(ctx.param("t"))); });
        };
        d.passes = {shadowMapPass(), hsmPass(), kernelPass(), visibility};
        d.kernelCaps = {backprojectionKernelCap()};
        d.internals = backprojectionInternals();
        d.internals.push_back(contourPixelRecord());
        return d;
    }();
    return desc;
}

}  // namespace shadowlab

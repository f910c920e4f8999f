// `ssm-gbp06`: soft shadow mapping by back-projection of every occluding sample (Guennebaud, Barthe
// and Paulin 2006), as guennebaud2007 section 3 summarises it: the HSM, the kernel and the
// classification (techniques/hsm/), then each occluding sample in the kernel back-projected as a
// quad onto the light, clipped to it, gaps filled by extending quads to their neighbours, areas
// summed. The overlaps are not corrected: the shadow is overestimated (guennebaud2007 Fig. 1, 11).
#include "hsm/hsm.h"

namespace shadowlab {

using namespace shared;

namespace {

// The sample quad of texel t of HSM level `level` at min depth z back-projected from r, with GBP06's
// gap filling: the same steps as shaders/backprojection/gbp06_area.glsl. Returns (x0, y0, x1, y1) in
// light coordinates and whether the right and top sides were extended.
struct SampleQuad {
    glm::vec4 rect;
    bool extendedRight = false, extendedTop = false;
};
SampleQuad sampleQuad(const BackprojectionCpu& c, const BpReceiver& r, int level, glm::ivec2 t, float z) {
    glm::vec2 lo = c.backprojectLevel(r, glm::vec2(t), level, z);
    glm::vec2 hi = c.backprojectLevel(r, glm::vec2(t + 1), level, z);
    SampleQuad q;
    glm::ivec2 right = t + glm::ivec2(1, 0), top = t + glm::ivec2(0, 1);
    float zRight = c.levelDepth(level, right);
    if (c.levelOccludes(r, level, right, zRight)) {
        float x = c.backprojectLevel(r, glm::vec2(right), level, zRight).x;
        q.extendedRight = x > hi.x;
        hi.x = std::max(hi.x, x);
    }
    float zTop = c.levelDepth(level, top);
    if (c.levelOccludes(r, level, top, zTop)) {
        float y = c.backprojectLevel(r, glm::vec2(top), level, zTop).y;
        q.extendedTop = y > hi.y;
        hi.y = std::max(hi.y, y);
    }
    q.rect = glm::vec4(lo.x, lo.y, hi.x, hi.y);
    return q;
}

InternalDesc gbp06PixelRecord() {
    InternalDesc r;
    r.name = "pixel";
    r.kind = InternalDesc::Kind::Record;
    r.doc = "the picked pixel's kernel and back-projected sample quads (--pixel x,y)";
    r.schema = backprojectionRecordSchema();
    r.schema.push_back({"samples", "occluding samples of the level walked whose quad reaches the light: texel [x, y] of "
                                   "that level, level, depth (its min), quad "
                                   "[x0, y0, x1, y1] in light coordinates after gap filling, extended_right, "
                                   "extended_top, area (occluded light area, light coordinates)"});
    r.reads = backprojectionRecordReads();
    r.record = [](PassContext& ctx, glm::ivec2 pixel) {
        PixelRecordStart s = startPixelRecord(ctx, pixel, -1.0f);  // GBP06: eq. 2's level, no blending
        float sum = 0.0f;
        nlohmann::json samples = nlohmann::json::array();
        if (!s.done) {
            const BackprojectionCpu& c = s.cpu;
            const int level = s.level;
            glm::ivec4 range = levelTexelRange(s.range, level, c.levelSize(level));
            // gbp06_area.glsl's order: chunks of BP_ROW_CHUNK columns, each row by row.
            const int columns = range.z - range.x + 1;
            for (int cx = 0; cx < columns; cx += BP_ROW_CHUNK)
                for (int y = range.y; y <= range.w; ++y)
                for (int x = range.x + cx; x < range.x + cx + std::min(BP_ROW_CHUNK, columns - cx); ++x) {
                    float z = c.levelDepth(level, {x, y});
                    if (!c.levelOccludes(s.receiver, level, {x, y}, z)) continue;
                    SampleQuad q = sampleQuad(c, s.receiver, level, {x, y}, z);
                    float area = rectOccludedArea(c.shape, q.rect);
                    sum += area;
                    if (area == 0.0f) continue;
                    samples.push_back({{"texel", {x, y}},
                                       {"level", level},
                                       {"depth", z},
                                       {"quad", {q.rect.x, q.rect.y, q.rect.z, q.rect.w}},
                                       {"extended_right", q.extendedRight},
                                       {"extended_top", q.extendedTop},
                                       {"area", area}});
                }
        }
        if (!s.record.contains("background")) s.record["samples"] = samples;
        finishPixelRecord(ctx, pixel, s, sum);
        return s.record;
    };
    return r;
}

}  // namespace

const TechniqueDesc& ssmGbp06Technique() {
    static const TechniqueDesc desc = [] {
        TechniqueDesc d;
        d.id = "ssm-gbp06";
        d.name = "Soft shadow mapping by back-projection (GBP06)";
        d.citation = "Guennebaud, Barthe, Paulin 2006, Real-time soft shadow mapping by backprojection; as summarised "
                     "in guennebaud2007 sec. 3 (eq. 1)";
        d.summary = "every occluding shadow-map sample back-projected as a small quad onto the light and its covered "
                    "area summed: gaps filled, overlaps not, so shadows come out too dark";
        d.soft = true;
        d.params = backprojectionParams();
        PassDesc visibility;
        visibility.name = "visibility";
        visibility.doc = "occluding samples of the kernel back-projected as quads, gap-filled, clipped to the light, "
                         "areas summed (guennebaud2007 sec. 3)";
        visibility.reads = backprojectionVisibilityReads();
        visibility.creates = {visibilityResource(), lightLevelsResource()};
        visibility.modifies = backprojectionVisibilityModifies();
        visibility.soft = true;
        visibility.create = [] { return std::make_unique<BackprojectionVisibilityPass>("backprojection/gbp06.frag", "backprojection/gbp06_sparse.comp"); };
        d.passes = {shadowMapPass(), hsmPass(), kernelPass()};
        for (const PassDesc& p : screenSelectionPasses()) d.passes.push_back(p);
        d.passes.push_back(visibility);
        d.passes.push_back(screenPullPushPass());
        d.kernelCaps = {backprojectionKernelCap()};
        d.counters = {screenSelectionCounter()};
        d.internals = backprojectionInternals();
        d.internals.push_back(lightLevelsInternal());
        for (const InternalDesc& i : screenAdaptiveInternals()) d.internals.push_back(i);
        d.internals.push_back(gbp06PixelRecord());
        return d;
    }();
    return desc;
}

}  // namespace shadowlab

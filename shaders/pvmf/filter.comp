// pvmf, pass filter (cournia2005 sec. 5.2): the visibility estimate of every listed pixel (select.comp).
// d_o is the mean of the mask's edge distances d_e over the n_do x n_do mask texels about the
// receiver's projection that hold a volume; w_pcf = s_p (d_r - d_o) r / (2 d_o d_r tan(alpha / 2))
// (penumbra_mask.glsl); the filter is cut into n_pcf x n_pcf cells of w_pcf / n_pcf, one depth test
// jittered in each (the directional receiver-plane bias of pcss, shaders/pcss/pcss_common.glsl).
// A receiver with no volume about it (deep in an umbra) keeps its shadow-map test. Times the light's
// fraction in front of the tangent plane (the visibility convention).
#include "../common/gbuffer_access.glsl"
#include "../common/light_front.glsl"
#include "../pcss/pcss_common.glsl"
#include "../shared/penumbra_mask.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Counts { uint counts[]; };
layout(std430, binding = 1) buffer PixelList { uint pixels[]; };
layout(r32f, binding = 0) uniform writeonly image2D visibilityRaw;
layout(rgba32f, binding = 1) uniform writeonly image2D kernels;  // (w_pcf texels, d_o, d_r, samples)
uniform sampler2D maskMap;
uniform float sp;           // s_p
uniform float lightRadius;  // r (pvmLightRadius)
uniform int npcf;           // n_pcf
uniform int nDo;            // n_do (odd)
uniform uint seed;

void main() {
    uint index = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationID.x;
    if (index >= counts[0]) {
        return;
    }
    uint entry = pixels[index];
    ivec2 pixel = ivec2(int(entry & 0xFFFFu), int(entry >> 16u));
    vec3 p = worldPosition(pixel);
    vec3 n = worldNormal(pixel);
    float front = lightFrontFraction(p, n);
    ShadowReceiver r = prepareShadowReceiver(p, n);
    TapPlane plane = tapPlane(r, p, n);
    int size = int(shadowMapSize);
    ivec2 texel = clamp(ivec2(floor(r.coord.xy * shadowMapSize)), ivec2(0), ivec2(size - 1));
    int h = nDo / 2;
    float sum = 0.0;
    float found = 0.0;
    for (int dy = -h; dy <= h; ++dy) {
        for (int dx = -h; dx <= h; ++dx) {
            float de = texelFetch(maskMap, clamp(texel + ivec2(dx, dy), ivec2(0), ivec2(size - 1)), 0).g;
            if (de > 0.0) {
                sum += de;
                found += 1.0;
            }
        }
    }
    float dr = length(p - lightPosition);
    float v;
    if (found == 0.0) {
        v = shadowTestOffset(r, vec2(0.0));
        imageStore(kernels, pixel, vec4(0.0, -1.0, dr, 1.0));
    } else {
        float dO = sum / found;
        float width = min(pvmfFilterWidth(sp, dr, dO, lightRadius, lightTanHalfFov), 1.0) * shadowMapSize;
        uint pixelSeed = pvmfPixelSeed(seed, uint(pixel.x), uint(pixel.y));
        uint count = uint(npcf * npcf);
        float lit = 0.0;
        for (uint i = 0u; i < count; ++i) {
            lit += shadowTestTap(r, plane, pvmfSampleOffset(i, uint(npcf), pixelSeed) * width);
        }
        v = lit / float(count);
        imageStore(kernels, pixel, vec4(width, dO, dr, float(count)));
    }
    imageStore(visibilityRaw, pixel, vec4(v * front));
}

// pvmf, passes blur_h and blur_v (cournia2005 sec. 5.3): the object-id-aware box blur of the listed
// pixels' visibility, n_blur + 1 taps from -n_blur/2 to n_blur/2 along `axis` (horizontal, then
// vertical into the final v-buffer, as sec. 5.5's fourth and fifth passes). A tap counts only on the
// same object with some light in front of its tangent plane (B, pvmfBlurWeight; ids from the
// G-buffer), b_s the taps that count. What is averaged is the estimate v / front (the source holds
// v times the light's fraction in front of the tangent plane, the visibility convention), and the
// mean is multiplied by the pixel's own front fraction. Pixels not listed are not blurred: the
// target already holds their value (a copy of the source).
#include "../common/gbuffer_access.glsl"
#include "../common/light_front.glsl"
#include "../shared/penumbra_mask.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Counts { uint counts[]; };
layout(std430, binding = 1) buffer PixelList { uint pixels[]; };
layout(r32f, binding = 0) uniform readonly image2D source;
layout(r32f, binding = 1) uniform writeonly image2D target;
uniform ivec2 axis;
uniform int nblur;
uniform ivec2 frameSize;

float objectId(ivec2 pixel) {
    return isBackground(pixel) ? -1.0 : texelFetch(gMaterial, pixel, 0).a;
}

void main() {
    uint index = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationID.x;
    if (index >= counts[0]) {
        return;
    }
    uint entry = pixels[index];
    ivec2 pixel = ivec2(int(entry & 0xFFFFu), int(entry >> 16u));
    float id = objectId(pixel);
    float front = lightFrontFraction(worldPosition(pixel), worldNormal(pixel));
    float sum = 0.0;
    float bs = 0.0;
    int h = nblur / 2;
    for (int i = -h; i <= h; ++i) {
        ivec2 q = pixel + i * axis;
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, frameSize))) {
            continue;
        }
        float frontTap = isBackground(q) ? 0.0 : lightFrontFraction(worldPosition(q), worldNormal(q));
        float b = pvmfBlurWeight(id, objectId(q), frontTap);
        sum += b > 0.0 ? imageLoad(source, q).r / frontTap : 0.0;
        bs += b;
    }
    imageStore(target, pixel, vec4(bs > 0.0 && front > 0.0 ? front * sum / bs : imageLoad(source, pixel).r));
}

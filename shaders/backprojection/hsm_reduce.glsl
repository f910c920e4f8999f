// HSM level texel p's (min, max) over the texels of the level below it (hsm.comp, hsm_first.frag):
// the 2x2 texels below, widened on a level's last row or column when the level below has an odd
// size, so no texel is left out. The includer defines vec2 sourceTexel(ivec2).
#ifndef SHADOWLAB_BACKPROJECTION_HSM_REDUCE_GLSL
#define SHADOWLAB_BACKPROJECTION_HSM_REDUCE_GLSL
vec2 hsmReduce(ivec2 p, ivec2 destinationSize, ivec2 sourceSize) {
    ivec2 lo = 2 * p;
    ivec2 hi = min(2 * p + 1, sourceSize - 1);
    if (p.x == destinationSize.x - 1) hi.x = sourceSize.x - 1;
    if (p.y == destinationSize.y - 1) hi.y = sourceSize.y - 1;
    vec2 range = vec2(3.4e38, -3.4e38);
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            vec2 texel = sourceTexel(ivec2(x, y));
            range = vec2(min(range.x, texel.x), max(range.y, texel.y));
        }
    return range;
}
#endif

// ssv, pass hard_volumes: the stencil's z-fail count as a float. The count wraps in 8 bits, so
// values of 128 and more are negative counts (a point behind more front faces than back faces,
// which a closed volume does not produce).
uniform usampler2D stencilCount;
layout(location = 0) out vec4 count;  // the colour mask keeps the sub-light's channel

void main() {
    uint s = texelFetch(stencilCount, ivec2(gl_FragCoord.xy), 0).r;
    count = vec4(s < 128u ? float(s) : float(int(s) - 256));
}

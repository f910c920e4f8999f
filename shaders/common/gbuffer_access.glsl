// Reads of the G-buffer (techniques/core/graph/renderer.h: position.w = 1 on geometry, 0 on background;
// normal: the geometric normal, the receiver's tangent plane every visibility test uses
// (gbuffer.frag), w = 1 when the object receives shadows; material.a = object id).
#ifndef SHADOWLAB_GBUFFER_ACCESS_GLSL
#define SHADOWLAB_GBUFFER_ACCESS_GLSL
uniform sampler2D gPosition;
uniform sampler2D gNormal;
uniform sampler2D gMaterial;

bool isBackground(ivec2 pixel) { return texelFetch(gPosition, pixel, 0).w == 0.0; }
vec3 worldPosition(ivec2 pixel) { return texelFetch(gPosition, pixel, 0).xyz; }
vec3 worldNormal(ivec2 pixel) { return texelFetch(gNormal, pixel, 0).xyz; }
#endif

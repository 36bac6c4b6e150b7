#version 450
// Irradiance stage, directional light (thesis 3.3.2, "Directional Lighting"; modules/irradiance):
// per point the transmitted irradiance
//   E_t = E0 · T(uv) · Ft(eta, n·L) · max(0, n·L) · V
// with E0 the light's irradiance on a surface facing it, T the projected texture (filtered
// mode; 1 otherwise) and V the shadow-map visibility (common/irradiance_shadow.glsl, layer 0).
// result[i] = (E_t, V).
layout(local_size_x = 64) in;

#include "common/irradiance_lighting.glsl"
#include "common/irradiance_shadow.glsl"

layout(std430, binding = 0) readonly buffer Points { IrradiancePoint points[]; };
layout(std430, binding = 1) writeonly buffer Result { vec4 result[]; };
layout(binding = 2) uniform sampler2D Projected;

uniform uint PointCount;
uniform uint PointOffset; // first point of this dispatch
uniform vec3 LightCentre;
uniform float LightExtent;
uniform vec3 LightU;
uniform vec3 LightV;
uniform vec3 LightW; // towards the light
uniform vec3 Irradiance;
uniform float Eta;
uniform int UseProjected;

void main() {
    uint i = gl_GlobalInvocationID.x + PointOffset;
    if (i >= PointCount) return;
    vec3 p = points[i].position.xyz;
    vec3 n = points[i].normal.xyz;
    float c = dot(n, LightW);
    vec3 E = vec3(0.0);
    float V = 0.0;
    if (c > 0.0) {
        vec3 d = p - LightCentre;
        vec3 lc = vec3(dot(d, LightU), dot(d, LightV), dot(d, LightW));
        V = shadowVisibility(lc, LightExtent, c, 0.0, i);
        vec3 colour = Irradiance;
        if (UseProjected != 0) colour *= texture(Projected, 0.5 + 0.5 * lc.xy / LightExtent).rgb;
        E = colour * (irradianceFt(c, Eta) * c * V);
    }
    result[i] = vec4(E, V);
}

#version 450
// Shadow pass of the irradiance stage (thesis 3.3.2, "Directional Lighting"): the mesh's depth
// seen from the light, orthographic (modules/irradiance/light_frame.h: clip = (x, y, −z)/e).
// VertexSnap: another rasteriser emulated (common/vertex_snap.glsl; 0 but in tests).
#include "common/vertex_snap.glsl"

layout(location = 0) in vec3 Position;
uniform mat4 ClipFromWorld;
uniform vec3 VertexSnap;
uniform uint VertexSnapSeed;

void main() {
    gl_Position = ClipFromWorld * vec4(Position, 1.0);
    gl_Position.xyz += vertexSnap(uint(gl_VertexID), VertexSnapSeed, VertexSnap); // w = 1
}

#version 450
// G-buffer pass of the point-cloud renderer (modules/render/gbuffer.cpp): rasterises the mesh
// (positions and per-vertex normals in mesh units) with the orbit camera's matrices.
// RenderViewProjection already flips y, so texture row 0 is the top of the image. The hybrid's
// light-view map (modules/texspace/hybrid.cpp) draws with it too. VertexSnap: another
// rasteriser emulated (common/vertex_snap.glsl; 0 but in tests).
#include "common/vertex_snap.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;

uniform mat4 RenderViewProjection;
uniform vec3 VertexSnap;
uniform uint VertexSnapSeed;

out vec3 vPosition;
out vec3 vNormal;

void main() {
    vPosition = inPosition;
    vNormal = inNormal;
    gl_Position = RenderViewProjection * vec4(inPosition, 1.0);
    gl_Position.xyz += vertexSnap(uint(gl_VertexID), VertexSnapSeed, VertexSnap) * gl_Position.w;
}

#version 450
// G-buffer pass of the point-cloud renderer (modules/render/gbuffer.cpp): rasterises the mesh
// (positions and per-vertex normals in mesh units) with the orbit camera's matrices.
// RenderViewProjection already flips y, so texture row 0 is the top of the image.
layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;

uniform mat4 RenderViewProjection;

out vec3 vPosition;
out vec3 vNormal;

void main() {
    vPosition = inPosition;
    vNormal = inNormal;
    gl_Position = RenderViewProjection * vec4(inPosition, 1.0);
}

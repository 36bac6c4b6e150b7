#version 450
// G-buffer pass (see render_gbuffer.vert): attachment 0 = (xo, 1) (mesh units; cleared to 0 so
// w = 0 marks a miss), attachment 1 = (interpolated vertex normal, normalised, 0). The normal
// is not flipped towards the camera.
in vec3 vPosition;
in vec3 vNormal;

layout(location = 0) out vec4 outPosition;
layout(location = 1) out vec4 outNormal;

void main() {
    outPosition = vec4(vPosition, 1.0);
    float len = length(vNormal);
    outNormal = vec4(len > 0.0 ? vNormal / len : vec3(0.0, 0.0, 1.0), 0.0);
}

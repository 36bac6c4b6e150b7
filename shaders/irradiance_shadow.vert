#version 450
// Shadow pass of the irradiance stage (thesis 3.3.2, "Directional Lighting"): the mesh's depth
// seen from the light, orthographic (modules/irradiance/light_frame.h: clip = (x, y, −z)/e).
layout(location = 0) in vec3 Position;
uniform mat4 ClipFromWorld;
void main() {
    gl_Position = ClipFromWorld * vec4(Position, 1.0);
}

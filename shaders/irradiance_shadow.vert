#version 450
// Shadow pass of the irradiance stage (thesis 3.3.2, "Directional Lighting"): the mesh's depth
// seen from the light, orthographic (modules/irradiance/light_frame.h: clip = (x, y, −z)/e).
// VertexSnap: each vertex moved on its own by up to that much (clip units, per axis), from a
// hash of its index and VertexSnapSeed, as another rasteriser snaps vertices to its sub-pixel
// grid and rounds their depths (irradiance::ShadowMaps::setVertexSnap, tests); 0 otherwise.
layout(location = 0) in vec3 Position;
uniform mat4 ClipFromWorld;
uniform vec3 VertexSnap;
uniform uint VertexSnapSeed;

uint snapHash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

void main() {
    gl_Position = ClipFromWorld * vec4(Position, 1.0);
    if (VertexSnap != vec3(0.0)) { // an indexed draw's gl_VertexID is the index: a shared
                                   // vertex moves alike in every triangle
        uint h = snapHash(uint(gl_VertexID) ^ (VertexSnapSeed * 0x9e3779b9u));
        vec3 r = vec3(uvec3(h, snapHash(h + 1u), snapHash(h + 2u)) >> 8u) / 8388608.0 - 1.0;
        gl_Position.xyz += r * VertexSnap; // w = 1: orthographic
    }
}

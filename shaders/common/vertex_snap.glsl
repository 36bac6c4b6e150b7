// Another rasteriser's per-vertex snapping, emulated (tests of the raster allowances:
// gl::VertexSnap): the move of vertex `id` under `seed`, each component uniform in
// [-1, 1) times `amplitude` (clip units per w). An indexed draw's gl_VertexID is the index, so a
// vertex shared by several triangles moves alike in all of them; each vertex moves on its own,
// as a driver snaps each to its sub-pixel grid and rounds its depth. 0 when the amplitude is 0.
// No #version here.
uint vertexSnapHash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

vec3 vertexSnap(uint id, uint seed, vec3 amplitude) {
    if (amplitude == vec3(0.0)) return vec3(0.0);
    uint h = vertexSnapHash(id ^ (seed * 0x9e3779b9u));
    uvec3 bits = uvec3(h, vertexSnapHash(h + 1u), vertexSnapHash(h + 2u)) >> 8u;
    return (vec3(bits) / 8388608.0 - 1.0) * amplitude;
}

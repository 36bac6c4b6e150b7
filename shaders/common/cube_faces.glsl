// Cube-map faces as OpenGL 4.5 Table 8.19 orients them (modules/irradiance: the irradiance
// cubemap, irradiance_cubemap.comp, and its lookups, irradiance_ibl.comp): faces 0…5 are
// +X −X +Y −Y +Z −Z; on a face of N × N texels, texel (i, j) covers s ∈ [i, i + 1)/N and
// t ∈ [j, j + 1)/N, where (s, t) = ½ (sc/|ma| + 1, tc/|ma| + 1) for the major axis ma.

// The direction (not normalised) through the centre of texel (i, j) of `face`; i and j may lie
// one beyond the face, giving the direction just past its edge.
vec3 cubeTexelDirection(int face, int i, int j, int n) {
    float sc = 2.0 * (float(i) + 0.5) / float(n) - 1.0;
    float tc = 2.0 * (float(j) + 0.5) / float(n) - 1.0;
    if (face == 0) return vec3(1.0, -tc, -sc);
    if (face == 1) return vec3(-1.0, -tc, sc);
    if (face == 2) return vec3(sc, 1.0, tc);
    if (face == 3) return vec3(sc, -1.0, -tc);
    if (face == 4) return vec3(sc, -tc, 1.0);
    return vec3(-sc, -tc, -1.0);
}

// The face of direction d and its (s, t) in [0, 1]² (ties go to x, then y).
int cubeFace(vec3 d, out vec2 st) {
    vec3 a = abs(d);
    int face;
    float sc, tc, ma;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x >= 0.0 ? 0 : 1;
        sc = d.x >= 0.0 ? -d.z : d.z;
        tc = -d.y;
        ma = a.x;
    } else if (a.y >= a.z) {
        face = d.y >= 0.0 ? 2 : 3;
        sc = d.x;
        tc = d.y >= 0.0 ? d.z : -d.z;
        ma = a.y;
    } else {
        face = d.z >= 0.0 ? 4 : 5;
        sc = d.z >= 0.0 ? d.x : -d.x;
        tc = -d.y;
        ma = a.z;
    }
    st = 0.5 * (vec2(sc, tc) / ma + 1.0);
    return face;
}

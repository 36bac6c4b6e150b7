// bssrdf_prelude.glsl: the built-in uniforms every .bssrdf model sees (materials/README.md).
// Included by each consumer template before `#pragma bssrdf_model`; no #version here.
//
// Units and conventions:
//   SigmaA, SigmaS  absorption and scattering coefficients per RGB channel, in 1/mm
//   G               Henyey-Greenstein mean cosine g (dimensionless, -1 < g < 1)
//   IOR             relative index of refraction eta of the medium (outside = 1)
//   Scale           mm per model unit (the mesh is normalised to 1 unit on its longest axis)
//   Bssrdf(Xi, Wi, Xo, Wo): Xi, Xo are surface positions in mm, Wi, Wo unit directions.
//   PI              the constant pi

uniform vec3 SigmaA;
uniform vec3 SigmaS;
uniform float G;
uniform float IOR;
uniform float Scale;

const float PI = 3.14159265358979323846;

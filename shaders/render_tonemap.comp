#version 450
// Tone mapping of the point-cloud renderer's HDR image (thesis 3.6.4: "renders in high dynamic
// range and supports post-process gamma correction and exposure adjustment"):
//   c = clamp((L·2^exposure)^(1/gamma), 0, 1) per channel, alpha 1;
// pixels whose HDR alpha is 0 (G-buffer miss) show TonemapBackground (display values); a pixel
// whose radiance is NaN or infinite (a model that returned such values) shows magenta, never
// black or a clamped colour that could pass for a result. RenderInvalid counts the surface
// pixels and those whose radiance is NaN, infinite or negative (the Errors entry of the scene).
layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = 0) readonly uniform image2D TonemapHdr;
layout(rgba8, binding = 1) writeonly uniform image2D TonemapLdr;

uniform ivec2 TonemapSize;
uniform float TonemapExposure; // stops
uniform float TonemapGamma;    // > 0
uniform vec3 TonemapBackground;
layout(std430, binding = 2) buffer RenderInvalid {
    uint surfacePixels, nanPixels, infPixels, negativePixels;
};

void main() {
    ivec2 pix = ivec2(gl_GlobalInvocationID.xy);
    if (pix.x >= TonemapSize.x || pix.y >= TonemapSize.y) return;
    vec4 hdr = imageLoad(TonemapHdr, pix);
    vec3 c = TonemapBackground;
    if (hdr.w != 0.0) {
        vec3 v = max(hdr.rgb * exp2(TonemapExposure), vec3(0.0));
        c = pow(v, vec3(1.0 / TonemapGamma));
        if (any(isnan(hdr.rgb)) || any(isinf(hdr.rgb))) c = vec3(1.0, 0.0, 1.0);
        atomicAdd(surfacePixels, 1u);
        if (any(isnan(hdr.rgb)))
            atomicAdd(nanPixels, 1u);
        else if (any(isinf(hdr.rgb)))
            atomicAdd(infPixels, 1u);
        else if (any(lessThan(hdr.rgb, vec3(0.0))))
            atomicAdd(negativePixels, 1u);
    }
    imageStore(TonemapLdr, pix, vec4(clamp(c, 0.0, 1.0), 1.0));
}

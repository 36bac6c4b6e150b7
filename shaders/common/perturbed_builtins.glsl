// perturbed_builtins.glsl: GLSL's transcendental functions, each result moved by the largest error
// the GLSL 4.50 specification allows it (section 4.7.1, "Range and Precision"), with a sign drawn
// per call from the argument's bits and PerturbSeed. Evaluating a model under several seeds shows
// how far its values may lie apart on two drivers that both keep to the specification: the
// conditioning that replaying a capture on another driver allows for (bssrdf/conditioning.h).
// Included after the prelude and before the model; PerturbSeed 0 leaves every function as the
// driver computes it. Arithmetic (+, -, *, /) is not moved: the replay's relative floor covers it.
//
//   exp(x), exp2(x)     (3 + 2|x|) ulp
//   log(x), log2(x)     3 ulp outside [0.5, 2]; 2^-21 absolute inside
//   pow(x, y)           inherited from exp2(y log2 x): (3 + 2|u|) ulp of the result, u = y log2 x,
//                       plus ln 2 |y| times the error of log2 x
//   inversesqrt(x)      2 ulp;  sqrt(x): inherited from 1.0 / inversesqrt(x), 4.5 ulp
// One ulp is taken as 2^-23 of the value, the largest it is relative to a float.
// Where a bound is not below 1 (a relative one) or the value is not finite (an argument at a pole,
// pow(0, y), exp(-inf), log(0)), the value is left as the driver computes it: multiplying by an
// infinite bound would turn the exact 0 of pow(0, y > 0) into NaN, even under seed 0.

uniform uint PerturbSeed;

const float BW_ULP = 1.0 / 8388608.0;

// +1 or -1 from the argument and the seed (a 32-bit integer hash); 0 when PerturbSeed is 0.
float bw_sign(float x, uint salt) {
    if (PerturbSeed == 0u) return 0.0;
    uint h = floatBitsToUint(x) ^ (PerturbSeed * 0x9E3779B9u) ^ (salt * 0x85EBCA6Bu);
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    h *= 0x846CA68Bu;
    h ^= h >> 16;
    return (h & 1u) != 0u ? 1.0 : -1.0;
}

// value moved by sign * rel of itself (a relative bound) or by sign * err (an absolute one); the
// comparisons are false for NaN, so a bound that is not finite leaves the value. The relative
// move is value + value * (sign * rel), not value * (1 + sign * rel), where 1 + a bound of a few
// ulp would round to a whole ulp of 1.
float bw_moveRel(float value, float sign, float rel) {
    return sign != 0.0 && rel < 1.0 ? value + value * (sign * rel) : value;
}
float bw_moveAbs(float value, float sign, float err) {
    return sign != 0.0 && abs(value) < 3.0e38 && err < 3.0e38 ? value + sign * err : value;
}

// Each driver function's value is `precise`: one program evaluates it under every seed, and a
// compiler that lowers exp(x) to exp2(x · log2 e) may otherwise round that product differently
// in two places (zink did, by e^x |x| ulp: the difference of two exps then moved past the sum of
// their bounds, Conditioning.ADifferenceOfTwoExps…).
float bw_exp(float x) {
    precise float v = exp(x);
    return bw_moveRel(v, bw_sign(x, 1u), (3.0 + 2.0 * abs(x)) * BW_ULP);
}
float bw_exp2(float x) {
    precise float v = exp2(x);
    return bw_moveRel(v, bw_sign(x, 2u), (3.0 + 2.0 * abs(x)) * BW_ULP);
}
// the error of log2(x) (the same bound holds for log)
float bw_logError(float x, float value) {
    return x >= 0.5 && x <= 2.0 ? 1.0 / 2097152.0 : 3.0 * BW_ULP * abs(value);
}
float bw_log(float x) {
    precise float v = log(x);
    return bw_moveAbs(v, bw_sign(x, 3u), bw_logError(x, v));
}
float bw_log2(float x) {
    precise float v = log2(x);
    return bw_moveAbs(v, bw_sign(x, 4u), bw_logError(x, v));
}
float bw_pow(float x, float y) {
    float l = log2(x);
    float u = y * l;
    float rel = (3.0 + 2.0 * abs(u)) * BW_ULP + 0.69314718 * abs(y) * bw_logError(x, l);
    precise float v = pow(x, y);
    return bw_moveRel(v, bw_sign(x + 0.61803399 * y, 5u), rel);
}
float bw_inversesqrt(float x) {
    precise float v = inversesqrt(x);
    return bw_moveRel(v, bw_sign(x, 6u), 2.0 * BW_ULP);
}
float bw_sqrt(float x) {
    precise float v = sqrt(x);
    return bw_moveRel(v, bw_sign(x, 7u), 4.5 * BW_ULP);
}

// the vector forms, component by component (GLSL has no generic functions)
vec2 bw_exp(vec2 x) { return vec2(bw_exp(x.x), bw_exp(x.y)); }
vec3 bw_exp(vec3 x) { return vec3(bw_exp(x.x), bw_exp(x.y), bw_exp(x.z)); }
vec4 bw_exp(vec4 x) { return vec4(bw_exp(x.xyz), bw_exp(x.w)); }
vec2 bw_exp2(vec2 x) { return vec2(bw_exp2(x.x), bw_exp2(x.y)); }
vec3 bw_exp2(vec3 x) { return vec3(bw_exp2(x.x), bw_exp2(x.y), bw_exp2(x.z)); }
vec4 bw_exp2(vec4 x) { return vec4(bw_exp2(x.xyz), bw_exp2(x.w)); }
vec2 bw_log(vec2 x) { return vec2(bw_log(x.x), bw_log(x.y)); }
vec3 bw_log(vec3 x) { return vec3(bw_log(x.x), bw_log(x.y), bw_log(x.z)); }
vec4 bw_log(vec4 x) { return vec4(bw_log(x.xyz), bw_log(x.w)); }
vec2 bw_log2(vec2 x) { return vec2(bw_log2(x.x), bw_log2(x.y)); }
vec3 bw_log2(vec3 x) { return vec3(bw_log2(x.x), bw_log2(x.y), bw_log2(x.z)); }
vec4 bw_log2(vec4 x) { return vec4(bw_log2(x.xyz), bw_log2(x.w)); }
vec2 bw_pow(vec2 x, vec2 y) { return vec2(bw_pow(x.x, y.x), bw_pow(x.y, y.y)); }
vec3 bw_pow(vec3 x, vec3 y) { return vec3(bw_pow(x.x, y.x), bw_pow(x.y, y.y), bw_pow(x.z, y.z)); }
vec4 bw_pow(vec4 x, vec4 y) { return vec4(bw_pow(x.xyz, y.xyz), bw_pow(x.w, y.w)); }
vec2 bw_inversesqrt(vec2 x) { return vec2(bw_inversesqrt(x.x), bw_inversesqrt(x.y)); }
vec3 bw_inversesqrt(vec3 x) {
    return vec3(bw_inversesqrt(x.x), bw_inversesqrt(x.y), bw_inversesqrt(x.z));
}
vec4 bw_inversesqrt(vec4 x) { return vec4(bw_inversesqrt(x.xyz), bw_inversesqrt(x.w)); }
vec2 bw_sqrt(vec2 x) { return vec2(bw_sqrt(x.x), bw_sqrt(x.y)); }
vec3 bw_sqrt(vec3 x) { return vec3(bw_sqrt(x.x), bw_sqrt(x.y), bw_sqrt(x.z)); }
vec4 bw_sqrt(vec4 x) { return vec4(bw_sqrt(x.xyz), bw_sqrt(x.w)); }

#define exp bw_exp
#define exp2 bw_exp2
#define log bw_log
#define log2 bw_log2
#define pow bw_pow
#define inversesqrt bw_inversesqrt
#define sqrt bw_sqrt

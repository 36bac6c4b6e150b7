// octree_layout.glsl: the GPU layout of the point-cloud octree (modules/octree/octree.h, thesis
// 3.3.3, Figs. 3.4/3.5) and the solid-angle criterion of eq. 2.40. No #version here.
//
// Buffers (std430, uploaded as-is from octree::Octree by render::Renderer):
//   binding 0  OctreeDescriptors  one uint per node: bits 0–3 child count (0 = leaf),
//                                 bits 4–7 point count (leaves), bits 8–31 index (first child
//                                 or first point)
//   binding 1  OctreeNodes        NodeRecord per node: irradianceArea = (Σ E·A rgb, Σ A),
//                                 meanPosition (irradiance weighted), boxMin, boxMax,
//                                 covariance about the mean (diagonal xx yy zz, off-diagonal
//                                 xy xz yz; same weights)
//   binding 2  OctreePoints       PointRecord per slot: positionArea = (p, A), normal, irradiance
// Positions are in mesh units.

struct OctreeNode {
    vec4 irradianceArea;
    vec4 meanPosition;
    vec4 boxMin;
    vec4 boxMax;
    vec4 covarianceDiagonal;
    vec4 covarianceOffDiagonal;
};
struct OctreePoint {
    vec4 positionArea;
    vec4 normal;
    vec4 irradiance;
};

layout(std430, binding = 0) readonly buffer OctreeDescriptors { uint octreeDescriptors[]; };
layout(std430, binding = 1) readonly buffer OctreeNodes { OctreeNode octreeNodes[]; };
layout(std430, binding = 2) readonly buffer OctreePoints { OctreePoint octreePoints[]; };

const uint OCTREE_STACK_SIZE = 16u;        // octree::kStackSize
const uint OCTREE_FLAG_STACK_OVERFLOW = 1u; // octree::kFlagStackOverflow
const uint OCTREE_FLAG_ITERATION_CAP = 2u;  // octree::kFlagIterationCap

uint octreeChildCount(uint d) { return d & 0xfu; }
uint octreePointCount(uint d) { return (d >> 4u) & 0xfu; }
uint octreeIndex(uint d) { return d >> 8u; }
uint octreePackEntry(uint node, uint childnum) { return (node << 8u) | (childnum & 0xffu); }

// Solid-angle criterion (eq. 2.40) with exactly the float operations of octree::traverse:
//   default:      d = xo − meanPosition
//   bounding box: d = max(boxMin − xo, 0) + max(xo − boxMax, 0) per axis (conservative)
//   d2 = (d.x*d.x + d.y*d.y) + d.z*d.z, accept = A_v < eps·d2 (d2 = 0 never accepts).
// `precise` keeps the compiler from fusing or reordering, so CPU and GPU decide alike.
bool octreeAccept(uint node, vec3 xo, float eps, bool boundingBox) {
    precise vec3 d;
    if (boundingBox) {
        d = max(octreeNodes[node].boxMin.xyz - xo, vec3(0.0)) +
            max(xo - octreeNodes[node].boxMax.xyz, vec3(0.0));
    } else {
        d = xo - octreeNodes[node].meanPosition.xyz;
    }
    precise float d2 = d.x * d.x + d.y * d.y + d.z * d.z;
    precise float threshold = eps * d2;
    return octreeNodes[node].irradianceArea.w < threshold;
}

// Second-order cluster rule (octree.h; octree::clusterPoints is the same arithmetic): the j-th
// (0, 1, 2) of the three evaluation points of `node` for receiver xo, at distances
// ρ0 = √(r² + t²), ρ∓ = √((r ∓ s)² + t²) from xo on the ray through the mean, s = √(2q), q the
// covariance's variance along d = xo − mean, t² = tr Σ − q; weights OCTREE_CLUSTER_WEIGHTS.
const float OCTREE_CLUSTER_WEIGHTS[3] = float[3](0.5, 0.25, 0.25);

// The node's shared quantities: d = xo − mean, r = |d| and the three distances ρ0, ρ−, ρ+
// (mesh units); r = 0 (xo at the mean) gives ρ = 0.
struct OctreeCluster {
    vec3 mean;
    vec3 d;
    float r;
    vec3 rho;
};

OctreeCluster octreeCluster(uint node, vec3 xo) {
    OctreeCluster c;
    c.mean = octreeNodes[node].meanPosition.xyz;
    precise vec3 d = xo - c.mean;
    c.d = d;
    precise float xx = d.x * d.x;
    precise float yy = d.y * d.y;
    precise float zz = d.z * d.z;
    precise float r2 = (xx + yy) + zz;
    c.r = 0.0;
    c.rho = vec3(0.0);
    if (!(r2 > 0.0)) return c;
    vec3 cd = octreeNodes[node].covarianceDiagonal.xyz;
    vec3 co = octreeNodes[node].covarianceOffDiagonal.xyz;
    precise float a = xx * cd.x + yy * cd.y + zz * cd.z;
    precise float xy = d.x * d.y;
    precise float xz = d.x * d.z;
    precise float yz = d.y * d.z;
    precise float b = xy * co.x + xz * co.y + yz * co.z;
    precise float q = max((a + 2.0 * b) / r2, 0.0);
    precise float tr = (cd.x + cd.y) + cd.z;
    precise float t2 = max(tr - q, 0.0);
    precise float r = sqrt(r2);
    precise float s = sqrt(2.0 * q);
    precise float m = r - s;
    precise float p = r + s;
    precise float rho0 = sqrt(r2 + t2);
    precise float rhoMinus = sqrt(m * m + t2);
    precise float rhoPlus = sqrt(p * p + t2);
    c.r = r;
    c.rho = vec3(rho0, rhoMinus, rhoPlus);
    return c;
}

// The j-th evaluation point: xo − d·(ρ_j / r), or the mean when r = 0.
vec3 octreeClusterPoint(OctreeCluster c, vec3 xo, uint j) {
    if (!(c.r > 0.0)) return c.mean;
    precise vec3 xi = xo - c.d * (c.rho[j] / c.r);
    return xi;
}

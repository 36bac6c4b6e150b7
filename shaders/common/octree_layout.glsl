// octree_layout.glsl: the GPU layout of the point-cloud octree (modules/octree/octree.h, thesis
// 3.3.3, Figs. 3.4/3.5) and the solid-angle criterion of eq. 2.40. No #version here.
//
// Buffers (std430, uploaded as-is from octree::Octree by render::Renderer):
//   binding 0  OctreeDescriptors  one uint per node: bits 0–3 child count (0 = leaf),
//                                 bits 4–7 point count (leaves), bits 8–31 index (first child
//                                 or first point)
//   binding 1  OctreeNodes        NodeRecord per node: irradianceArea = (Σ E·A rgb, Σ A),
//                                 meanPosition (irradiance weighted), boxMin, boxMax
//   binding 2  OctreePoints       PointRecord per slot: positionArea = (p, A), normal, irradiance
// Positions are in mesh units.

struct OctreeNode {
    vec4 irradianceArea;
    vec4 meanPosition;
    vec4 boxMin;
    vec4 boxMax;
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

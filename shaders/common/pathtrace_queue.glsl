// pathtrace_queue.glsl: the work queue of the GL compute path tracers (pathtrace_slab.comp,
// pathtrace_sphere.comp, bssrdf_walk.comp) and the hand-over from one dispatch to the next on
// the GPU (host side: modules/pathtrace/detail/gpu_work_queue.h); no #version here.
//
// A round traces `itemCount` new work items to their end in dispatches of bounded length. An
// invocation takes first a path suspended by the previous dispatch (PtIn, ptInCount of them),
// then new items (ptNext); a path still running when the invocation's event budget is spent is
// saved to PtOut. The last invocation of a dispatch to finish plans the next one: every
// invocation counts itself in ptFinished after a memoryBarrierBuffer(), so the one that
// counts last sees every other's queue updates; it makes the suspended paths the next input,
// checks that every suspended path was resumed, and writes the next dispatch's group count
// into ptGroups, the arguments the host's next glDispatchComputeIndirect reads (0 groups once
// the round is done). The host so issues dispatches in batches and reads the queue once per
// batch, not after every dispatch.
layout(std430, binding = 2) coherent buffer PtQueue {
    uint ptNext;       // new items taken in this round (past itemCount by the idle lanes)
    uint ptInTaken;    // suspended paths taken from PtIn (past ptInCount by the idle lanes)
    uint ptOutCount;   // paths suspended into PtOut
    uint ptEventsLo;   // events of the round, 64-bit (diagnostics)
    uint ptEventsHi;
    uint ptInCount;    // paths the previous dispatch suspended: this dispatch's input
    uint ptFinished;   // invocations of this dispatch that have finished
    uint ptFault;      // 1: suspended paths were left behind
    uint ptFaultValue; // ... that many of ptFaultCount were resumed
    uint ptFaultCount;
    uint ptDispatches; // dispatches planned in this round
    uint ptPad;
    uvec4 ptGroups;    // the next dispatch: (groups, 1, 1) for glDispatchComputeIndirect, pad
};

const uint PT_LOCAL_SIZE = 64u;             // local_size_x of every tracer
const uint PT_ITEMS_PER_INVOCATION = 4u;    // invocations launched per new item of work
const uint PT_MAX_GROUPS = 1024u;           // at most 65536 invocations per dispatch

// The next piece of work: 1 and `index` = k for suspended path k, 2 and `index` = i for new
// item i of the round, 0 when there is none (the invocation is done).
uint ptTake(uint itemCount, out uint index) {
    uint k = atomicAdd(ptInTaken, 1u);
    if (k < ptInCount) {
        index = k;
        return 1u;
    }
    index = atomicAdd(ptNext, 1u);
    return index < itemCount ? 2u : 0u;
}

// Ends the invocation (after it saved any suspended path): adds its events (at most the event
// budget) and, as the dispatch's last invocation, plans the next dispatch.
void ptFinish(uint eventsLo, uint itemCount) {
    uint old = atomicAdd(ptEventsLo, eventsLo);
    if (old + eventsLo < old) atomicAdd(ptEventsHi, 1u);
    memoryBarrierBuffer(); // this invocation's queue updates and saved path before its count
    uint total = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (atomicAdd(ptFinished, 1u) != total - 1u) return;
    memoryBarrierBuffer();
    // the last one: every other invocation has finished; atomics read their final values
    uint inCount = ptInCount;
    uint inTaken = atomicAdd(ptInTaken, 0u);
    uint suspended = atomicAdd(ptOutCount, 0u);
    uint taken = min(atomicAdd(ptNext, 0u), itemCount);
    if (inTaken < inCount && ptFault == 0u) {
        ptFault = 1u;
        ptFaultValue = inTaken;
        ptFaultCount = inCount;
    }
    atomicExchange(ptNext, taken); // idle lanes' overshoot dropped: no wrap in long rounds
    atomicExchange(ptInTaken, 0u);
    atomicExchange(ptOutCount, 0u);
    atomicExchange(ptFinished, 0u);
    ptInCount = suspended;
    // one invocation per suspended path at least (it takes them all on its first iteration),
    // and about PT_ITEMS_PER_INVOCATION new items per invocation
    uint perGroup = PT_LOCAL_SIZE * PT_ITEMS_PER_INVOCATION;
    uint groups = 0u;
    if (taken < itemCount || suspended > 0u)
        groups = clamp(max((suspended + PT_LOCAL_SIZE - 1u) / PT_LOCAL_SIZE,
                           (suspended + (itemCount - taken) + perGroup - 1u) / perGroup),
                       1u, PT_MAX_GROUPS);
    ptGroups = uvec4(groups, 1u, 1u, 0u);
    ptDispatches += 1u;
}

// pathtrace_queue.glsl: the work queue of the GL compute path tracers (pathtrace_slab.comp,
// pathtrace_sphere.comp, bssrdf_walk.comp) and the hand-over from one dispatch to the next on
// the GPU (host side: modules/pathtrace/detail/gpu_work_queue.h); no #version here.
//
// A step traces a number of work items (paths; 3 per path in the sphere tracer, one per
// colour channel) in rounds of at most ptMaxRound new items, each round to its end in
// dispatches of bounded length. An invocation takes first a path suspended by the previous
// dispatch (PtIn, ptInCount of them), then new items of the round (ptNext); a path still
// running when the invocation's event budget is spent is saved to PtOut. The last invocation
// of a dispatch to finish plans the next one: every invocation counts itself in ptFinished
// after a memoryBarrierBuffer(), so the one that counts last sees every other's queue updates.
// It makes the suspended paths the next input, checks that every suspended path was resumed,
// starts the next round when this one is done (its first path index and item count from the
// step's items left), and writes the next dispatch's group count into ptGroups, the arguments
// the host's next glDispatchComputeIndirect reads (0 once the step is done). The host so
// issues dispatches in batches and reads the queue once per batch, never per dispatch or round.
layout(std430, binding = 2) coherent buffer PtQueue {
    uint ptNext;       // new items taken in this round (past ptRoundCount by the idle lanes)
    uint ptInTaken;    // suspended paths taken from PtIn (past ptInCount by the idle lanes)
    uint ptOutCount;   // paths suspended into PtOut
    uint ptEventsLo;   // events of the step, 64-bit (diagnostics)
    uint ptEventsHi;
    uint ptInCount;    // paths the previous dispatch suspended: this dispatch's input
    uint ptFinished;   // invocations of this dispatch that have finished
    uint ptFault;      // 1: suspended paths were left behind
    uint ptFaultValue; // ... that many of ptFaultCount were resumed
    uint ptFaultCount;
    uint ptDispatches; // dispatches planned in this step
    uint ptRounds;     // rounds started in this step
    uvec4 ptGroups;    // the next dispatch: (groups, 1, 1) for glDispatchComputeIndirect, pad
    uint ptFirstLo;    // the round's first path index, 64-bit
    uint ptFirstHi;
    uint ptRoundCount; // new items of the round
    uint ptItemsLeft;  // items of the step in no round yet
    uint ptItemsPerPath;
    uint ptMaxRound;   // items per round at most (a multiple of ptItemsPerPath)
};

const uint PT_LOCAL_SIZE = 64u;          // local_size_x of every tracer
const uint PT_ITEMS_PER_INVOCATION = 4u; // invocations launched per new item of work
const uint PT_MAX_GROUPS = 1024u;        // at most 65536 invocations per dispatch

// The next piece of work: 1 and `index` = k for suspended path k, 2 and `index` = i for new
// item i of the round, 0 when there is none (the invocation is done).
uint ptTake(out uint index) {
    uint k = atomicAdd(ptInTaken, 1u);
    if (k < ptInCount) {
        index = k;
        return 1u;
    }
    index = atomicAdd(ptNext, 1u);
    return index < ptRoundCount ? 2u : 0u;
}

// The path index (64-bit, lo/hi) of new item `item` of the round.
uvec2 ptPathOf(uint item) {
    uint i = item / ptItemsPerPath;
    uint lo = ptFirstLo + i;
    return uvec2(lo, ptFirstHi + (lo < i ? 1u : 0u));
}

// The group count of a dispatch with `suspended` paths to resume and `fresh` new items: one
// invocation per suspended path at least (it takes one on its first iteration), and about
// PT_ITEMS_PER_INVOCATION new items per invocation.
uint ptGroupsFor(uint suspended, uint fresh) {
    uint perGroup = PT_LOCAL_SIZE * PT_ITEMS_PER_INVOCATION;
    return clamp(max((suspended + PT_LOCAL_SIZE - 1u) / PT_LOCAL_SIZE,
                     (suspended + fresh + perGroup - 1u) / perGroup),
                 1u, PT_MAX_GROUPS);
}

// Ends the invocation (after it saved any suspended path): adds its events (at most the event
// budget) and, as the dispatch's last invocation, plans the next dispatch.
void ptFinish(uint eventsLo) {
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
    uint taken = min(atomicAdd(ptNext, 0u), ptRoundCount);
    if (inTaken < inCount && ptFault == 0u) {
        ptFault = 1u;
        ptFaultValue = inTaken;
        ptFaultCount = inCount;
    }
    atomicExchange(ptInTaken, 0u);
    atomicExchange(ptOutCount, 0u);
    atomicExchange(ptFinished, 0u);
    ptInCount = suspended;
    ptDispatches += 1u;
    if (taken < ptRoundCount || suspended > 0u) {
        atomicExchange(ptNext, taken); // idle lanes' overshoot dropped: no wrap in long rounds
        ptGroups = uvec4(ptGroupsFor(suspended, ptRoundCount - taken), 1u, 1u, 0u);
        return;
    }
    // the round is done: the next one, if items are left
    uint paths = ptRoundCount / ptItemsPerPath;
    uint lo = ptFirstLo + paths;
    ptFirstHi += lo < paths ? 1u : 0u;
    ptFirstLo = lo;
    ptRoundCount = min(ptItemsLeft, ptMaxRound);
    ptItemsLeft -= ptRoundCount;
    atomicExchange(ptNext, 0u);
    if (ptRoundCount > 0u) ptRounds += 1u;
    ptGroups = uvec4(ptRoundCount > 0u ? ptGroupsFor(0u, ptRoundCount) : 0u, 1u, 1u, 0u);
}

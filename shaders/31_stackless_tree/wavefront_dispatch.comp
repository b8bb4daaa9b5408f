#version 430 core
// --8<-- [start:dispatch]
// After a kernel has filled queues: each queue's dispatch command, enough work groups
// of QUEUE_GROUP_SIZE for its items, which glDispatchComputeIndirect reads from the
// buffer without the host ever seeing the sizes.
#include "path_tracer.glsl"
#include "wavefront.glsl"

layout(local_size_x = QUEUE_COUNT) in;

void main() {
    uint queue = gl_LocalInvocationID.x;
    uint size = queues[queue].size;
    queues[queue].groupsX = (size + QUEUE_GROUP_SIZE - 1u) / QUEUE_GROUP_SIZE;
    queues[queue].groupsY = 1u;
    queues[queue].groupsZ = 1u;
}
// --8<-- [end:dispatch]

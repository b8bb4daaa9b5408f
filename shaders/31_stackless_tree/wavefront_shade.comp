#version 430 core
// --8<-- [start:shade]
// Shade the hits on one kind of material (SHADE_KIND, from the generated
// shade_kind.glsl: one program per kind the scene has). Next-event estimation's shadow
// ray goes to the shadow queue, a path that goes on to the other ray queue.
#include "shade_kind.glsl"
#include "path_tracer.glsl"
#include "wavefront.glsl"

layout(local_size_x = QUEUE_GROUP_SIZE) in;
layout(std430, binding = RANDOM_BINDING) buffer Random { RandomState randomStates[]; };

void main() {
    uint slot;
    if (!itemOf(QUEUE_SHADE + SHADE_KIND, slot)) return;
    PathState path = loadPath(slot);
    RandomState random = randomStates[pixelOf(slot)];
    ShadowRay shadow;
    bool goesOn = shadeHit(path, loadHit(slot), random, shadow);
    randomStates[pixelOf(slot)] = random;
    storePath(slot, path);
    if (shadow.tMax != 0.0) {
        storeShadowRay(slot, shadow);
        push(QUEUE_SHADOW, slot);
    }
    if (goesOn) push(1u - rayQueue, slot);
}
// --8<-- [end:shade]

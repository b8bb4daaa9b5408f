// How the shaders read the spheres, quads, materials and emitters: from storage
// buffers, as chapters 02-18 read everything, or from constant arrays that the host
// writes into the shader itself for a small scene (scene_code.glsl, SCENE_MEMORY).
// Everything else reads them through sphereAt(i), quadAt(i), materialAt(i) and
// emitterAt(i).

// --8<-- [start:small]
#if SCENE_MEMORY == MEMORY_STORAGE
layout(std430, binding = SPHERES_BINDING) readonly buffer Spheres { Sphere spheres[]; };
layout(std430, binding = QUADS_BINDING) readonly buffer Quads { Quad quads[]; };
layout(std430, binding = MATERIALS_BINDING) readonly buffer Materials {
    Material materials[];
};
layout(std430, binding = EMITTERS_BINDING) readonly buffer Emitters { Emitter emitters[]; };
Sphere sphereAt(int i) { return spheres[i]; }
Quad quadAt(int i) { return quads[i]; }
Material materialAt(uint i) { return materials[i]; }
Emitter emitterAt(uint i) { return emitters[i]; }

#else  // MEMORY_CONSTANTS: SCENE_SPHERES, ... are constant arrays in scene_code.glsl
Sphere sphereAt(int i) { return SCENE_SPHERES[i]; }
Quad quadAt(int i) { return SCENE_QUADS[i]; }
Material materialAt(uint i) { return SCENE_MATERIALS[i]; }
Emitter emitterAt(uint i) { return SCENE_EMITTERS[i]; }
#endif
// --8<-- [end:small]

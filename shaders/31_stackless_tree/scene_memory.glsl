// How the shaders read the scene: the same numbers along four paths, which llvmpipe
// (and a GPU) run at very different speeds. scene_code.glsl, which the host writes for
// each scene (scene_code.cpp), says which path the small arrays take (SCENE_MEMORY:
// spheres, quads, materials, emitters) and which the tree takes (BVH_MEMORY: its
// nodes, the triangles and their corners). Everything else reads what it needs through
// the functions below: sphereAt(i), quadAt(i), materialAt(i), emitterAt(i),
// triangleAt(i), positionAt(i), leafCornerAt(i), bvhBoxAt(i) and bvhGrid().
//
//   MEMORY_STORAGE    storage buffers, as chapters 02-18 read everything
//   MEMORY_UNIFORM    uniform blocks: fixed-size arrays, small (GL_MAX_UNIFORM_BLOCK_SIZE)
//   MEMORY_TEXTURE    buffer textures: the same bytes, read with texelFetch
//   MEMORY_CONSTANTS  constant arrays written into the shader itself (scene_code.glsl)

// A buffer texture of RGBA32UI texels hands back 4 uints a texel: the bytes as the
// host wrote them. A float in the struct comes back through uintBitsToFloat. (Read as
// RGBA32F, a uint that looks like a denormal float could be flushed to zero, or a NaN's
// bits changed, on the way.)
vec4 floatsAt(usamplerBuffer texels, int index) {
    return uintBitsToFloat(texelFetch(texels, index));
}

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

#elif SCENE_MEMORY == MEMORY_UNIFORM
// The arrays' sizes must be known here: scene_code.glsl gives them (at least 1 each).
// These structs have the same layout under std140 as under std430.
layout(std140, binding = SPHERES_BLOCK_BINDING) uniform SphereBlock {
    Sphere uniformSpheres[SPHERE_ARRAY_SIZE];
};
layout(std140, binding = QUADS_BLOCK_BINDING) uniform QuadBlock {
    Quad uniformQuads[QUAD_ARRAY_SIZE];
};
layout(std140, binding = MATERIALS_BLOCK_BINDING) uniform MaterialBlock {
    Material uniformMaterials[MATERIAL_ARRAY_SIZE];
};
layout(std140, binding = EMITTERS_BLOCK_BINDING) uniform EmitterBlock {
    Emitter uniformEmitters[EMITTER_ARRAY_SIZE];
};
Sphere sphereAt(int i) { return uniformSpheres[i]; }
Quad quadAt(int i) { return uniformQuads[i]; }
Material materialAt(uint i) { return uniformMaterials[i]; }
Emitter emitterAt(uint i) { return uniformEmitters[i]; }

#elif SCENE_MEMORY == MEMORY_TEXTURE
layout(binding = SPHERES_UNIT) uniform usamplerBuffer sphereTexels;      // 2 texels each
layout(binding = QUADS_UNIT) uniform usamplerBuffer quadTexels;          // 3 texels each
layout(binding = MATERIALS_UNIT) uniform usamplerBuffer materialTexels;  // 4 texels each
layout(binding = EMITTERS_UNIT) uniform usamplerBuffer emitterTexels;    // 1 texel each
Sphere sphereAt(int i) {
    vec4 a = floatsAt(sphereTexels, 2 * i);
    uvec4 b = texelFetch(sphereTexels, 2 * i + 1);
    return Sphere(a.xyz, a.w, b.x, b.y, 0u, 0u);
}
Quad quadAt(int i) {
    uvec4 a = texelFetch(quadTexels, 3 * i), b = texelFetch(quadTexels, 3 * i + 1);
    vec3 c = floatsAt(quadTexels, 3 * i + 2).xyz;
    return Quad(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w, c, 0u);
}
Material materialAt(uint i) {
    int at = 4 * int(i);
    uvec4 a = texelFetch(materialTexels, at), d = texelFetch(materialTexels, at + 3);
    vec4 b = floatsAt(materialTexels, at + 1), c = floatsAt(materialTexels, at + 2);
    return Material(uintBitsToFloat(a.xyz), a.w, b.xyz, b.w, c.xyz, c.w,
                    uintBitsToFloat(d.xyz), int(d.w));
}
Emitter emitterAt(uint i) {
    uvec4 a = texelFetch(emitterTexels, int(i));
    return Emitter(a.x, a.y, uintBitsToFloat(a.z), uintBitsToFloat(a.w));
}

#else  // MEMORY_CONSTANTS: SCENE_SPHERES, ... are constant arrays in scene_code.glsl
Sphere sphereAt(int i) { return SCENE_SPHERES[i]; }
Quad quadAt(int i) { return SCENE_QUADS[i]; }
Material materialAt(uint i) { return SCENE_MATERIALS[i]; }
Emitter emitterAt(uint i) { return SCENE_EMITTERS[i]; }
#endif
// --8<-- [end:small]

// --8<-- [start:tree]
// The tree and its triangles: storage buffers or buffer textures over the same bytes.
#if BVH_MEMORY == MEMORY_STORAGE
layout(std430, binding = TRIANGLES_BINDING) readonly buffer Triangles {
    Triangle triangles[];
};
layout(std430, binding = POSITIONS_BINDING) readonly buffer Positions { vec4 positions[]; };
// The tree's boxes (bvh_layout.h): the grid, then the 8 orders.
layout(std430, binding = BVH_NODES_BINDING) readonly buffer BvhBoxes { BvhBox bvhBoxes[]; };
Triangle triangleAt(uint i) { return triangles[i]; }
// Corner i % 3 of triangle i / 3, through its index, as chapter 18 reads it. (A copy
// in leaf order would be one more storage block than llvmpipe's 16 for a shader.)
vec3 leafCornerAt(uint i) { return positions[triangles[i / 3u].corners[i % 3u]].xyz; }
vec3 positionAt(uint i) { return positions[i].xyz; }
BvhBox bvhBoxAt(uint i) { return bvhBoxes[BVH_GRID_BOXES + i]; }
BvhGrid bvhGrid() {
    BvhBox a = bvhBoxes[0], b = bvhBoxes[1];
    return BvhGrid(uintBitsToFloat(uvec3(a.nearXY, a.nearZFarX, a.farYZ)), a.next,
                   uintBitsToFloat(uvec3(b.nearXY, b.nearZFarX, b.farYZ)), 0u);
}
#else
layout(binding = TRIANGLES_UNIT) uniform usamplerBuffer triangleTexels;  // 3 texels each
layout(binding = POSITIONS_UNIT) uniform usamplerBuffer positionTexels;  // 1 texel each
layout(binding = BVH_NODES_UNIT) uniform usamplerBuffer bvhBoxTexels;    // 1 texel each
layout(binding = LEAF_CORNERS_UNIT) uniform usamplerBuffer leafCornerTexels;  // 3 each
Triangle triangleAt(uint i) {
    int at = 3 * int(i);
    uvec4 a = texelFetch(triangleTexels, at), b = texelFetch(triangleTexels, at + 1);
    uvec4 c = texelFetch(triangleTexels, at + 2);
    return Triangle(a.xyz, a.w, b.xyz, b.w, c.xyz, c.w);
}
vec3 positionAt(uint i) { return floatsAt(positionTexels, int(i)).xyz; }
vec3 leafCornerAt(uint i) { return floatsAt(leafCornerTexels, int(i)).xyz; }
BvhBox bvhBoxAt(uint i) {
    uvec4 box = texelFetch(bvhBoxTexels, BVH_GRID_BOXES + int(i));
    return BvhBox(box.x, box.y, box.z, box.w);
}
BvhGrid bvhGrid() {
    uvec4 a = texelFetch(bvhBoxTexels, 0), b = texelFetch(bvhBoxTexels, 1);
    return BvhGrid(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), 0u);
}
#endif
// --8<-- [end:tree]

// Instances: where each one is, as the walk reads it (bvh_traversal.glsl), and how rays
// and normals go between the world and an object's own space. An instance keeps only
// the map from the world to its object, M and an offset; everything else follows.

// The instances' table (gpu::Instance, five texels each), through a buffer texture:
// course::BufferTexture, whose texels are uints with the floats' bits as they are.
layout(binding = INSTANCES_UNIT) uniform usamplerBuffer instanceTable;

Instance instanceAt(uint index) {
    int texel = 5 * int(index);
    uvec4 where = texelFetch(instanceTable, texel + 3);
    return Instance(uintBitsToFloat(texelFetch(instanceTable, texel)),
                    uintBitsToFloat(texelFetch(instanceTable, texel + 1)),
                    uintBitsToFloat(texelFetch(instanceTable, texel + 2)),
                    where.x, where.y, where.z, where.w,
                    uintBitsToFloat(texelFetch(instanceTable, texel + 4)));
}

// --8<-- [start:time]
// When this path looks, as a fraction of the shutter's interval from its opening:
// path.comp draws it once for each camera sample, so that every ray of the path sees
// the scene at the same instant, and the mean over samples is the mean over the
// interval: motion blur.
float pathTime = 0.0;
// --8<-- [end:time]

// --8<-- [start:to_object]
// M's rows as a GLSL matrix's columns: that matrix is M transposed, so v * it is M v
// (GLSL multiplies a row vector on the left by the transpose).
mat3 transposeOfM(Instance placed) {
    return mat3(placed.objectFromWorld0.xyz, placed.objectFromWorld1.xyz,
                placed.objectFromWorld2.xyz);
}

// The ray in the object's space: its origin is a point (M, then the offset), its
// direction a vector (M alone). The direction keeps the length M gives it: then the
// point at t is the same point in both spaces, and a hit's t needs no converting.
// An instance that has moved by pathTime times its motion is where it was with the ray
// moved back as far: in the object's space, by pathTime times M's motion.
Ray rayToObject(Ray ray, Instance placed) {
    mat3 transposed = transposeOfM(placed);
    vec3 offset = vec3(placed.objectFromWorld0.w, placed.objectFromWorld1.w,
                       placed.objectFromWorld2.w);
    // BEGIN SOLUTION the object's space moved back by this path's share of the motion
    offset -= pathTime * placed.objectMotion.xyz;
    // STUB: // the instance where it is when the shutter opens, whatever the time
    // END SOLUTION
    return Ray(ray.origin * transposed + offset, ray.direction * transposed);
}

// A normal goes to the world by the inverse transpose of world-from-object: M is that
// inverse, so it is M transposed. (The map itself would tilt the normals of an unevenly
// scaled object; this keeps them at right angles to its surface.)
vec3 normalToWorld(vec3 normal, Instance placed) {
    return normalize(transposeOfM(placed) * normal);
}
// --8<-- [end:to_object]

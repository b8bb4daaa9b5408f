// Direct light from one point light: Lambert's cosine law and a shadow ray.

// --8<-- [start:light]
uniform vec3 lightPosition;
// Light that arrives from everywhere (the sky, other surfaces), crudely: a constant
// share of the albedo, so that shadows are dark but not black.
const float AMBIENT = 0.1;
// How far shadow rays start off the surface: SHADOW_OFFSET * (1 + the mesh's radius),
// or 0 (--no-shadow-offset).
uniform float shadowOffset;
// --8<-- [end:light]

// --8<-- [start:shade]
vec3 shade(Hit hit) {
    // 1. Is the light visible from the hit point? A shadow ray from just above the
    //    surface towards the light: anything hit before the light is in the way.
    //    "Above" means off the flat triangle the point is on, so along its own
    //    normal: the smooth normal can lean so far that its offset ends up below.
    vec3 shadowOrigin = hit.position + hit.geometricNormal * shadowOffset;
    vec3 toLight = lightPosition - shadowOrigin;
    float lightDistance = length(toLight);
    Ray shadowRay = Ray(shadowOrigin, toLight / lightDistance);
    float visible = anyHit(shadowRay, 0.0, lightDistance) ? 0.0 : 1.0;
    // 2. Lambert: a surface tilted away from the light by an angle receives cos(angle)
    //    as much light per area; facing away, none.
    float cosine = max(0.0, dot(hit.normal, shadowRay.direction));
    return hit.albedo * (AMBIENT + (1.0 - AMBIENT) * visible * cosine);
}
// --8<-- [end:shade]

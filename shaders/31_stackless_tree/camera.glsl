// The camera: chapter 03's pinhole, now with a thin lens. Every ray of a pixel passes
// through the same point of the focus plane, from a random point of the aperture:
// what lies on that plane is sharp, the rest blurs by its distance from it
// (python_prototypes/thin_lens.py). The host computes the camera's basis once
// (chapters/NN/camera.cpp).

// --8<-- [start:camera]
struct Ray {
    vec3 origin;
    vec3 direction;  // unit length
};

// The camera is `camera`, a member of the PathParameters uniform block (shared.h).
// --8<-- [end:camera]

// --8<-- [start:concentric]
const float QUARTER_TURN = 1.57079632679;  // pi / 2 (sampling.glsl's PI comes later)

// Shirley and Chiu's map from the unit square onto the unit disk: the square's rings
// round its centre become the disk's rings, so equal areas stay equal (uniform points
// stay uniform) and neighbours stay neighbours.
vec2 concentricDisk(vec2 u) {
    vec2 ab = 2.0 * u - 1.0;
    if (ab == vec2(0.0)) return vec2(0.0);
    float radius, angle;
    if (abs(ab.x) > abs(ab.y)) {
        radius = ab.x;
        angle = 0.5 * QUARTER_TURN * (ab.y / ab.x);
    } else {
        radius = ab.y;
        angle = QUARTER_TURN - 0.5 * QUARTER_TURN * (ab.x / ab.y);
    }
    return radius * vec2(cos(angle), sin(angle));
}
// --8<-- [end:concentric]

// --8<-- [start:primary_ray]
// pointInPixel: where the ray crosses the pixel, (0, 0) its top left corner and (1, 1)
// its bottom right; (0.5, 0.5) is the centre, a random point anti-aliases (chapter 09).
// pointOnLens: where on the aperture it starts, (0.5, 0.5) its centre (the pinhole).
Ray primaryRay(uvec2 pixel, uvec2 imageSize, vec2 pointInPixel, vec2 pointOnLens) {
    // Square pixels: the sensor has the image's aspect ratio.
    float sensorHeight = camera.sensorWidth * float(imageSize.y) / float(imageSize.x);
    // The point on the sensor, from -0.5 to 0.5 across and up. Row 0 is the top of the
    // image, so y runs the other way.
    vec2 onSensor = (vec2(pixel) + pointInPixel) / vec2(imageSize);
    float across = onSensor.x - 0.5;
    float upwards = 0.5 - onSensor.y;
    // From the eye to the point. Adding the eye (metres away from the origin)
    // and subtracting it again would round away digits of these millimetre offsets.
    vec3 eyeToPixel = camera.forward * camera.focalLength
                    + camera.right * (across * camera.sensorWidth)
                    + camera.up * (upwards * sensorHeight);
    // The pinhole ray meets the focus plane `focusDistance` in front of the eye here;
    // every ray of this pixel, from anywhere on the lens, passes through that point.
    vec3 eyeToFocus = eyeToPixel * (camera.focusDistance / dot(eyeToPixel, camera.forward));
#if HAS_LENS
    vec2 lens = camera.lensRadius * concentricDisk(pointOnLens);
#else  // a pinhole (scene_code.glsl): the lens's code compiled out, the same ray
    vec2 lens = vec2(0.0);
#endif
    vec3 eyeToLens = camera.right * lens.x + camera.up * lens.y;
    return Ray(camera.eye + eyeToLens, normalize(eyeToFocus - eyeToLens));
}
// --8<-- [end:primary_ray]

// The pinhole camera: one ray from the eye through a point of each pixel.
// The host computes the camera's basis once (chapters/NN/camera.cpp); every invocation
// only scales and adds three vectors.

// --8<-- [start:camera]
struct Ray {
    vec3 origin;
    vec3 direction;  // unit length
};

// The camera is `camera`, a member of the PathParameters uniform block (shared.h).
// --8<-- [end:camera]

// --8<-- [start:primary_ray]
// pointInPixel: where the ray crosses the pixel, (0, 0) its top left corner and (1, 1)
// its bottom right; (0.5, 0.5) is the centre, a random point anti-aliases (chapter 09).
Ray primaryRay(uvec2 pixel, uvec2 imageSize, vec2 pointInPixel) {
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
    return Ray(camera.eye, normalize(eyeToPixel));
}
// --8<-- [end:primary_ray]

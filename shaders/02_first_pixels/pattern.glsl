// The test pattern both dispatch shapes paint. Linear colours: red grows to the
// right, green grows downwards, blue alternates in 32-pixel squares.
// --8<-- [start:pattern]
vec3 patternColor(uvec2 pixel, uvec2 imageSize) {
    // BEGIN SOLUTION compute the gradient and the checkerboard from the pixel position
    vec2 centre = (vec2(pixel) + 0.5) / vec2(imageSize);
    bool oddSquare = (((pixel.x / 32u) + (pixel.y / 32u)) & 1u) == 1u;
    return vec3(centre.x, centre.y, oddSquare ? 1.0 : 0.25);
    // STUB: return vec3(0.0);
    // END SOLUTION
}
// --8<-- [end:pattern]

// From radiance to what a screen shows. A screen's white is a fixed brightness; the
// sky is thousands of times brighter than a room. Exposure scales the picture, as a
// camera's shutter does; a tone-mapping curve then squeezes [0, infinity) into [0, 1)
// gently instead of clipping. The result is still linear: the PNG writer and the
// window sRGB-encode it. The PFM keeps the radiance itself.

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }  // Rec. 709

// --8<-- [start:reinhard]
// Reinhard, Stark, Shirley and Ferwerda (2002), extended: on luminance, so that hues
// keep their ratios; L / (1 + L) rolls off the highlights, and the factor 1 + L / W^2
// lets luminance W reach exactly 1.
vec3 reinhard(vec3 c) {
    float l = luminance(c);
    if (l <= 0.0) return vec3(0.0);
    float w2 = REINHARD_WHITE * REINHARD_WHITE;
    float mapped = l * (1.0 + l / w2) / (1.0 + l);
    return c * (mapped / l);
}
// --8<-- [end:reinhard]

// --8<-- [start:aces]
// Narkowicz's (2015) rational fit of the ACES reference rendering transform's curve,
// per channel: a toe that deepens the shadows, a shoulder that rolls off the
// highlights (and desaturates them, as film does). The 0.6 is his: the fit expects
// the exposure ACES's own would give.
vec3 aces(vec3 c) {
    vec3 x = 0.6 * c;
    return clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}
// --8<-- [end:aces]

// --8<-- [start:false_colour]
// Luminance in stops (doublings) above or below mid-grey (0.18), as colours: blue at
// -6 and darker, through cyan, green at mid-grey, yellow, to red at +6 and brighter.
// What a cinematographer's monitor shows to judge an exposure.
vec3 falseColour(vec3 c) {
    float stops = log2(max(luminance(c), 1e-10) / 0.18);
    float x = clamp((stops + 6.0) / 12.0, 0.0, 1.0) * 4.0;
    const vec3 ramp[5] = vec3[5](vec3(0.0, 0.0, 1.0), vec3(0.0, 1.0, 1.0), vec3(0.0, 1.0, 0.0),
                                 vec3(1.0, 1.0, 0.0), vec3(1.0, 0.0, 0.0));
    int i = min(int(x), 3);
    return mix(ramp[i], ramp[i + 1], x - float(i));
}
// --8<-- [end:false_colour]

vec3 toneMapped(vec3 radiance, float exposure, int toneMap) {
    vec3 exposed = radiance * exp2(exposure);
    if (toneMap == TONE_MAP_REINHARD) return min(reinhard(exposed), vec3(1.0));
    if (toneMap == TONE_MAP_ACES) return aces(exposed);
    if (toneMap == TONE_MAP_FALSE_COLOUR) return falseColour(exposed);
    return clamp(exposed, 0.0, 1.0);
}

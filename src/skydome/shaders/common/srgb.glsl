// sRGB transfer function (IEC 61966-2-1:1999); float64 twins: skydome.display.srgb.
// Inputs are clamped to [0, 1].

// twin: skydome.display.srgb.srgb_encode(linear_rgb) linear_rgb=-0.1..1.1
vec3 srgb_encode(vec3 linear_rgb) {
    vec3 v = clamp(linear_rgb, 0.0, 1.0);
    vec3 lo = 12.92 * v;
    vec3 hi = 1.055 * pow(max(v, vec3(0.0031308)), vec3(1.0 / 2.4)) - 0.055;
    return mix(hi, lo, vec3(lessThanEqual(v, vec3(0.0031308))));
}

// twin: skydome.display.srgb.srgb_decode(encoded) encoded=-0.1..1.1
float srgb_decode(float encoded) {
    float v = clamp(encoded, 0.0, 1.0);
    return v <= 0.04045 ? v / 12.92 : pow((max(v, 0.04045) + 0.055) / 1.055, 2.4);
}

vec3 srgb_decode(vec3 encoded) {
    return vec3(srgb_decode(encoded.r), srgb_decode(encoded.g), srgb_decode(encoded.b));
}

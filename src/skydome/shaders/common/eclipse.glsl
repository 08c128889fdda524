// Eclipses: how much of one disk another hides (float64 twins: skydome.astro.eclipses).
// Used by the sky's light in a solar eclipse (atmosphere/eclipse_sky.glsl) and by the Moon
// in the Earth's penumbra (celestial/moon.glsl). Angles in radians.

// Area of a circular segment of half-angle t (at the centre) of the unit circle,
// t - sin(t) cos(t), by its series where that would cancel in float32.
float segment_area(float t) {
    if (t < 0.25) {
        float t2 = t * t;
        return t * t2 * (2.0 / 3.0 - t2 * (2.0 / 15.0 - t2 * (4.0 / 315.0)));
    }
    return t - 0.5 * sin(2.0 * t);
}

// Fraction of the uniform disk of radius a hidden by the disk of radius b whose centre is d
// away: the lens of the two circles (two segments) over pi a^2.
// twin: skydome.astro.eclipses.disk_overlap_fraction(d, a, b) d=0..0.02 a=0.004..0.006 b=0.003..0.007
float disk_overlap_fraction(float d, float a, float b) {
    d = abs(d);
    if (d >= a + b) return 0.0;
    if (d <= abs(a - b)) return min(a, b) * min(a, b) / (a * a);
    // half-angles from the half-angle formula of the triangle (d, a, b): stable near 0
    float s = 0.5 * (d + a + b);
    float ta = 2.0 * atan(sqrt(max((s - d) * (s - a), 0.0) / max(s * (s - b), 1e-30)));
    float tb = 2.0 * atan(sqrt(max((s - d) * (s - b), 0.0) / max(s * (s - a), 1e-30)));
    float lens = a * a * segment_area(ta) + b * b * segment_area(tb);
    return clamp(lens / (3.14159265358979 * a * a), 0.0, 1.0);
}

// The angle between two unit vectors, accurate for small angles (from the cross product).
float small_angle(vec3 u, vec3 v) { return atan(length(cross(u, v)), dot(u, v)); }

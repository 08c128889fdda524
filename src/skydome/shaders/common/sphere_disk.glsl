// A sphere seen from outside (the Sun, the Moon, the planets): which view rays meet it and
// where (float64 twins: skydome.physics.geometry). Directions are unit vectors; `centre` points at the sphere's centre and
// `sin_radius` is the sine of its angular radius. Small angles are computed from cross
// products: in float32, 1 - cos(theta) for theta ~ 5 mrad keeps 2 digits, the sine 7.

// sin(theta) of the angle between the ray and the centre, and whether it lies in front.
// twin: skydome.physics.geometry.sin_offset(dir, centre) dir=unit centre=unit
float sin_offset(vec3 dir, vec3 centre) { return length(cross(dir, centre)); }

// twin: skydome.physics.geometry.ray_meets_sphere(dir, centre, sin_radius) dir=unit centre=unit sin_radius=0.3
bool ray_meets_sphere(vec3 dir, vec3 centre, float sin_radius) {
    return dot(dir, centre) > 0.0 && sin_offset(dir, centre) < sin_radius;
}

// The outward normal where the ray first meets the sphere (it must meet it), in the frame
// of the directions: distances in units of the centre's distance, the sphere's radius is
// sin_radius; the hit is at t = cos(theta) - sqrt(sin_radius^2 - sin^2(theta)).
// twin: skydome.physics.geometry.sphere_normal(dir, centre, sin_radius) dir=unit centre=unit sin_radius=0.0047
vec3 sphere_normal(vec3 dir, vec3 centre, float sin_radius) {
    vec3 c = cross(dir, centre);
    float s2 = dot(c, c);
    float t = dot(dir, centre) - sqrt(max(sin_radius * sin_radius - s2, 0.0));
    return (t * dir - centre) / sin_radius;
}

// Fall speeds of rain drops and snowflakes (skydome.weather.rain and .snow).

// Terminal speed (m/s) of a raindrop of diameter d_mm (Atlas et al. 1973's fit to Gunn &
// Kinzer 1949).
// twin: skydome.weather.rain.fall_speed_m_s(d_mm) d_mm=0.05..6
float rain_fall_speed(float d_mm) {
    return max(9.65 - 10.3 * exp(-0.6 * d_mm), 0.0);
}

// Fall speed (m/s) of an unrimed aggregate snowflake of size d_mm (Locatelli & Hobbs 1974).
// twin: skydome.weather.snow.flake_fall_speed_m_s(d_mm) d_mm=0.1..20
float flake_fall_speed(float d_mm) {
    return 0.8 * pow(d_mm, 0.16);
}

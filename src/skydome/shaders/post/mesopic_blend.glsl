// The eye's mesopic colours (CIE 191:2010 MES2 weights; skydome.display.night_vision): the
// photopic share w_p of a pixel keeps its colour, the scotopic share is drawn in the blue
// grey C_b of unit luminance: w_p RGB + (1 - w_p) L_s C_b. Twin: skydome/reference/
// night_vision.py (mesopic_blend).
uniform vec3 u_blue_grey;           // C_b, linear sRGB with luminance 1
uniform float u_wp;                 // photopic share w_p

vec3 mesopic_blend(vec4 c) { return u_wp * c.rgb + (1.0 - u_wp) * c.a * u_blue_grey; }

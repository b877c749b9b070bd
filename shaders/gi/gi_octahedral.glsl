// Unit vectors as points of the octahedron unfolded onto [-1, 1]^2 (gi_bake.h's
// giOctahedralEncode / giOctahedralDecode are the CPU's copies): surfels' face normals, and the
// probes' visibility maps.
#ifndef JANUS_GI_OCTAHEDRAL_GLSL
#define JANUS_GI_OCTAHEDRAL_GLSL

vec2 giOctahedralEncode(vec3 n) {
    vec2 o = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if (n.z < 0.0) o = (1.0 - abs(o.yx)) * vec2(o.x >= 0.0 ? 1.0 : -1.0, o.y >= 0.0 ? 1.0 : -1.0);
    return o;
}

vec3 giOctahedralDecode(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return normalize(n);
}
#endif

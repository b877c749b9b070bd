// Cube-map geometry shared by the IBL shaders; the GLSL twin of renderer/src/ibl/cube_geometry.h.
// Faces +X, -X, +Y, -Y, +Z, -Z with the Vulkan/GL cube map table (t = 0 is row 0).
#ifndef JANUS_IBL_CUBE_GEOMETRY_GLSL
#define JANUS_IBL_CUBE_GEOMETRY_GLSL

// The direction through (s, t) in [0, 1]^2 of cube face `face`. Not normalised.
vec3 cubeDirection(int face, vec2 st) {
    float a = 2.0 * st.x - 1.0;
    float b = 2.0 * st.y - 1.0;
    if (face == 0) return vec3(1.0, -b, -a);
    if (face == 1) return vec3(-1.0, -b, a);
    if (face == 2) return vec3(a, 1.0, b);
    if (face == 3) return vec3(a, -1.0, -b);
    if (face == 4) return vec3(a, -b, 1.0);
    return vec3(-a, -b, -1.0);
}

// The unit direction through the centre of texel `texel` of a face `size` texels wide.
vec3 cubeTexelDirection(int face, ivec2 texel, int size) {
    return normalize(cubeDirection(face, (vec2(texel) + 0.5) / float(size)));
}

#endif

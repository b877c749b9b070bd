// --debug gi's probe spheres (renderer/src/debug_views/gi_probe_view.*, docs/GI.md): what the
// vertex and fragment shader share. Probe i of the grid (x + X (y + Y z)) sits at
// giVolume.origin + (x, y, z) * giVolume.spacing, as shading (gi_access.glsl) reads it.
#ifndef JANUS_GI_PROBE_VIEW_COMMON_GLSL
#define JANUS_GI_PROBE_VIEW_COMMON_GLSL
#include "janus/shaders/bindings.h"
#include "gi/gi_access.glsl"

layout(set = 0, binding = JANUS_BINDING_GI_PROBE_VIEW, std140) uniform GiProbeViewUniforms {
    mat4 viewProjection;
    // Homogeneous, as the frame uniforms' cameraPosition: w 1 the eye, w 0 the unit direction
    // towards an orthographic camera (whose rays are parallel).
    vec4 camera;
    vec4 spheres;   // x the spheres' radius
} probeView;

vec3 giProbeCentre(ivec3 probe) { return giVolume.origin.xyz + vec3(probe) * giVolume.spacing.xyz; }
#endif

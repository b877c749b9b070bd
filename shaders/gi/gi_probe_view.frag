#version 450
#extension GL_GOOGLE_include_directive : require
// --debug gi's probes: the sphere of the fragment's probe (the camera's ray through the
// fragment; a miss is discarded), shaded with the probe's own SH at the sphere's normal:
// irradiance / pi, what the view shows on surfaces too. Invalid probes are flat magenta.
#include "gi/gi_probe_view_common.glsl"

layout(location = 0) in vec3 vWorldPosition;
layout(location = 1) flat in ivec3 vProbe;
layout(location = 2) flat in int vValid;
layout(location = 0) out vec4 outRadiance;

const vec3 kInvalidProbeColor = vec3(1.0, 0.0, 1.0);   // gi_probe_view.h kInvalidProbeColor
const float kMaxRadiance = 65000.0;                     // as forward.frag: fp16 stays finite

void main() {
    vec3 centre = giProbeCentre(vProbe);
    float radius = probeView.spheres.x;
    // The ray through the fragment: from the eye, or (orthographic) along the view axis through
    // the fragment's point on the quad; either way -b - sqrt(h) below is the side facing the camera.
    bool orthographic = probeView.camera.w == 0.0;
    vec3 origin = orthographic ? vWorldPosition : probeView.camera.xyz;
    vec3 direction = orthographic ? -probeView.camera.xyz : normalize(vWorldPosition - origin);
    vec3 oc = origin - centre;
    float b = dot(oc, direction);
    float h = b * b - (dot(oc, oc) - radius * radius);
    if (h < 0.0) discard;
    vec3 normal = normalize(origin + direction * (-b - sqrt(h)) - centre);
    if (vValid == 0) {
        outRadiance = vec4(kInvalidProbeColor, 1.0);
        return;
    }
    int z0 = vProbe.y * 9;
    ShBasis y = shEvalBasis(normal);
    vec3 sum = texelFetch(giVolumeTexture, ivec3(vProbe.x, vProbe.z, z0), 0).rgb * y.a.x +
               texelFetch(giVolumeTexture, ivec3(vProbe.x, vProbe.z, z0 + 1), 0).rgb * y.a.y +
               texelFetch(giVolumeTexture, ivec3(vProbe.x, vProbe.z, z0 + 2), 0).rgb * y.a.z +
               texelFetch(giVolumeTexture, ivec3(vProbe.x, vProbe.z, z0 + 3), 0).rgb * y.a.w +
               texelFetch(giVolumeTexture, ivec3(vProbe.x, vProbe.z, z0 + 4), 0).rgb * y.b.x +
               texelFetch(giVolumeTexture, ivec3(vProbe.x, vProbe.z, z0 + 5), 0).rgb * y.b.y +
               texelFetch(giVolumeTexture, ivec3(vProbe.x, vProbe.z, z0 + 6), 0).rgb * y.b.z +
               texelFetch(giVolumeTexture, ivec3(vProbe.x, vProbe.z, z0 + 7), 0).rgb * y.b.w +
               texelFetch(giVolumeTexture, ivec3(vProbe.x, vProbe.z, z0 + 8), 0).rgb * y.c;
    outRadiance = vec4(min(max(sum, vec3(0.0)), vec3(kMaxRadiance)), 1.0);
}

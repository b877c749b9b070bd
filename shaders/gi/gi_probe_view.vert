#version 450
#extension GL_GOOGLE_include_directive : require
// --debug gi's probes: one camera-facing quad (6 vertices, no vertex buffer) per probe, through
// the probe's centre; the fragment shader cuts the sphere out of it. Invalid probes are inside
// geometry, where the depth test would hide them: they are drawn in front of everything.
#include "gi/gi_probe_view_common.glsl"

layout(location = 0) out vec3 vWorldPosition;
layout(location = 1) flat out ivec3 vProbe;
layout(location = 2) flat out int vValid;

void main() {
    const vec2 corners[6] = vec2[6](vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(-1.0, 1.0), vec2(-1.0, 1.0), vec2(1.0, -1.0), vec2(1.0, 1.0));
    int index = gl_VertexIndex / 6;
    ivec3 counts = giVolume.counts.xyz;
    ivec3 probe = ivec3(index % counts.x, (index / counts.x) % counts.y, index / (counts.x * counts.y));
    vec3 centre = giProbeCentre(probe);
    float radius = probeView.spheres.x;
    vec3 toCamera = probeView.camera.xyz - centre * probeView.camera.w;
    // An orthographic camera is infinitely far from every sphere (its outline radius is r).
    float distanceToCamera = probeView.camera.w == 0.0 ? 1e30 : length(toCamera);
    vec3 forward = toCamera / max(length(toCamera), 1e-20);
    vec3 helper = abs(forward.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 right = normalize(cross(helper, forward));
    vec3 up = cross(forward, right);
    // The sphere's outline, seen from the camera in the plane through its centre, has radius
    // r d / sqrt(d^2 - r^2): at most 2 r while the camera is 1.155 r away or more.
    vec2 corner = corners[gl_VertexIndex - index * 6];
    vWorldPosition = centre + (right * corner.x + up * corner.y) * (2.0 * radius);
    vProbe = probe;
    vValid = texelFetch(giVolumeTexture, ivec3(probe.x, probe.z, probe.y * 9), 0).a > 0.5 ? 1 : 0;
    gl_Position = probeView.viewProjection * vec4(vWorldPosition, 1.0);
    // Just behind the near plane's depth 0: in front of every surface (a probe behind the camera,
    // w < 0, stays clipped).
    if (vValid == 0) gl_Position.z = 1e-6 * gl_Position.w;
    // A camera inside (or nearly inside) the sphere: no quad covers it; the probe is not drawn.
    if (distanceToCamera < 1.2 * radius) gl_Position = vec4(0.0, 0.0, -1.0, 1.0);
}

// The plane of the triangle a fragment lies on, for lookups that must not count light from below
// it where the shading normal leans away from it (forward shading's and the GI relight's irradiance
// volume lookups, gi_access.glsl). Take the derivatives where the whole 2x2 quad is present: before
// any discard, outside branches on per-fragment values.
#ifndef JANUS_FACE_NORMAL_GLSL
#define JANUS_FACE_NORMAL_GLSL

// The unit normal of the triangle's plane on the viewer's side, from the world position's screen
// derivatives (exact within a triangle); `fallback` where they give no plane (a triangle seen
// edge-on). Each derivative is scaled by its largest component first, so tiny scenes keep a plane.
vec3 faceNormal(vec3 positionDx, vec3 positionDy, vec3 toViewer, vec3 fallback) {
    float scaleX = max(max(abs(positionDx.x), abs(positionDx.y)), abs(positionDx.z));
    float scaleY = max(max(abs(positionDy.x), abs(positionDy.y)), abs(positionDy.z));
    if (!(scaleX > 0.0 && scaleY > 0.0)) return fallback;
    vec3 n = cross(positionDx / scaleX, positionDy / scaleY);
    float lengthSq = dot(n, n);
    if (!(lengthSq > 1e-24)) return fallback;   // also NaN
    n = normalize(n);
    return dot(n, toViewer) < 0.0 ? -n : n;
}

#endif

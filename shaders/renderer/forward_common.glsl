// Uniform blocks shared by forward.vert and forward.frag. Mirrors FrameUniforms/DrawUniforms in
// renderer/src/renderer.cpp (std140); binding numbers are unique across sets (see Conventions).

const int kMaxDirectionalLights = 4;
const int kMaxLocalLights = 16;   // point and spot lights, shaded in a plain loop for now

struct LightData {
    vec4 positionRange;    // xyz position, w range (0 = infinite)
    vec4 directionType;    // xyz direction the light travels, w 0 directional / 1 point / 2 spot
    vec4 colorIntensity;   // rgb colour * intensity (lux or candela), w unused
    vec4 spotScaleOffset;  // x, y: cone attenuation scale and offset (KHR_lights_punctual)
};

layout(set = 0, binding = 0, std140) uniform FrameUniforms {
    mat4 viewProjection;
    vec4 cameraPosition;
    vec4 ambientColor;
    ivec4 lightCounts;     // x directional, y local
    LightData directionalLights[kMaxDirectionalLights];
    LightData localLights[kMaxLocalLights];
} frame;

layout(set = 1, binding = 1, std140) uniform DrawUniforms {
    mat4 world;
    mat4 normalMatrix;     // inverse transpose of world (upper 3x3 used)
    vec4 baseColorFactor;
    vec4 emissiveFactor;   // rgb emissive, w alpha cutoff
    vec4 materialParams;   // x metallic, y roughness, z normal scale, w occlusion strength
    ivec4 flags;           // x double-sided, y has tangents, z alpha mask
} draw;

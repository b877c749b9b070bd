// Binding slots of the renderer's shaders: the one place that numbers them. Included by C++
// (`#include "janus/shaders/bindings.h"`) and by GLSL (glslang runs with shaders/include on its
// include path), so it holds preprocessor definitions only.
//
// Binding numbers are unique across all sets of one pipeline (docs/ARCHITECTURE.md, "Binding
// model"): the GL backend uses them as UBO binding points, texture units, SSBO bindings and
// image units directly. So: storage images and storage buffers below 8 (GL 4.3's minimum image
// units and SSBO bindings per stage), uniform blocks below 24 (GLES 3.0's binding points),
// textures below 30 (units 30 and 31 are the GL backend's own).
#ifndef JANUS_SHADERS_BINDINGS_H
#define JANUS_SHADERS_BINDINGS_H

// ---- Scene passes (forward.vert/.frag, depth_prepass.frag) ------------------------------------
// Set 0: per view.
#define JANUS_SET_VIEW 0
#define JANUS_BINDING_FRAME_UNIFORMS 0      // FrameUniforms (forward_common.glsl)
#define JANUS_BINDING_LOCAL_LIGHTS 7        // light array: SSBO (compute path) | RGBA32UI texture (fallback)
#define JANUS_BINDING_TILE_LISTS 8          // tile lists: SSBO (compute path) | R32UI texture (fallback)
#define JANUS_BINDING_SHADOW_MAP 9          // sampler2DShadow of the main directional light
#define JANUS_BINDING_SKY_SPECULAR 10       // samplerCube: the sky, GGX-prefiltered (mip = roughness * (mips - 1))
#define JANUS_BINDING_DFG 11                // sampler2D: split-sum (A, B) at (NoV, roughness)
#define JANUS_BINDING_SKY_SH 12             // the sky's SH9 irradiance / pi: 9 vec4 SSBO (compute path) | 9x1 RGBA32F (fallback)
#define JANUS_BINDING_PROBE_CUBES 13        // reflection probes: samplerCubeArray (cube = probe slot) | without cube arrays (GLES 3.0): samplerCube of slot 0
#define JANUS_BINDING_PROBE_CUBE_1 14       // without cube arrays only: samplerCube of slot 1
#define JANUS_BINDING_REFLECTION_PROBES 15  // ReflectionProbeUniforms (probe_access.glsl): the shown probes in blend order
#define JANUS_BINDING_GI_VOLUME 16          // irradiance volume (gi_access.glsl): RGBA16F 3D texture of the probes' SH
#define JANUS_BINDING_GI_UNIFORMS 17        // GiVolumeUniforms (gi_access.glsl): grid, normal bias, on/off
#define JANUS_BINDING_GI_VISIBILITY 18      // RGBA32F 2D texture (gi_access.glsl): per probe its position and distance moments
// Set 1: per draw: one set for every draw, a dynamic uniform buffer whose offset picks the draw's
// slot (renderer/src/core/gpu_scene.cpp; mesh pipelines declare it with addDynamicUniformBuffer).
#define JANUS_SET_DRAW 1
#define JANUS_BINDING_DRAW_UNIFORMS 1       // DrawUniforms (forward_common.glsl)
// Set 2: per material: its five textures, bound when the material changes.
#define JANUS_SET_MATERIAL 2
#define JANUS_BINDING_BASE_COLOR 2
#define JANUS_BINDING_METALLIC_ROUGHNESS 3
#define JANUS_BINDING_NORMAL 4
#define JANUS_BINDING_OCCLUSION 5
#define JANUS_BINDING_EMISSIVE 6

// ---- Light culling (light_cull.comp), set 0 ---------------------------------------------------
#define JANUS_BINDING_CULL_UNIFORMS 0
#define JANUS_BINDING_CULL_DEPTH 1
#define JANUS_BINDING_CULL_LIGHTS 2
#define JANUS_BINDING_CULL_TILE_LISTS 3
#define JANUS_BINDING_CULL_STATS 4

// ---- Shadow map pass (shadow.vert) ------------------------------------------------------------
#define JANUS_BINDING_SHADOW_PASS 0         // set 0: light view-projection
#define JANUS_BINDING_SHADOW_CASTER 1       // set 1: caster world matrix (a dynamic uniform buffer: one set, an offset per caster)

// ---- Mesh deformation: skins and morph targets (renderer/src/deform/, shaders/renderer/deform*), set 0
#define JANUS_BINDING_DEFORM_UNIFORMS 0     // DeformUniforms (deform_common.glsl)
#define JANUS_BINDING_DEFORM_JOINTS 1       // joint matrices: mat4 SSBO (compute) | RGBA32F texture, 4 texels per matrix (fallback)
#define JANUS_BINDING_DEFORM_MORPHS 2       // morph displacements: vec4 SSBO (compute) | RGBA32F texture (fallback)
#define JANUS_BINDING_DEFORM_BASE 3         // compute path: the mesh's vertices (SSBO of floats)
#define JANUS_BINDING_DEFORM_SKIN 4         // compute path: per vertex joints and weights (SSBO of vec4 pairs)
#define JANUS_BINDING_DEFORM_OUTPUT 5       // compute path: the posed vertices (SSBO of floats, renderer Vertex layout)

// ---- Tonemap (tonemap.comp / tonemap.frag), set 0 ---------------------------------------------
#define JANUS_BINDING_TONEMAP_UNIFORMS 0
#define JANUS_BINDING_TONEMAP_HDR 1
#define JANUS_BINDING_TONEMAP_DISPLAY 2     // compute path: rgba8 storage image

// ---- Sky background (shaders/ibl/sky.vert/.frag), set 0 --------------------------------------
#define JANUS_BINDING_SKY_UNIFORMS 0        // SkyUniforms: inverse view-projection without translation, intensity
#define JANUS_BINDING_SKY_RADIANCE 1        // samplerCube: the sky (mip 0 of the prefiltered cube)

// ---- Tile heat map (tile_heatmap.frag), set 0; reads JANUS_BINDING_TILE_LISTS -----------------
#define JANUS_BINDING_HEATMAP_UNIFORMS 0

// ---- IBL: SH irradiance (shaders/ibl/sh_*.comp|frag, renderer/src/ibl/sh_irradiance.*), set 0 ------
#define JANUS_BINDING_SH_UNIFORMS 0         // ShUniforms (sh_common.glsl)
#define JANUS_BINDING_SH_CUBE 1             // samplerCube: the environment (nearest, one mip)
#define JANUS_BINDING_SH_SOLID_ANGLES 2     // sampler2D R32F: exact texel solid angles of one face
#define JANUS_BINDING_SH_PARTIALS 3         // per-group partial sums: SSBO (compute) | RGBA32F row sums (fallback)
#define JANUS_BINDING_SH_COEFFICIENTS 4     // compute path: 9 vec4 std430 (irradiance / pi SH), written by sh_reduce
// Shading reads the result through JANUS_BINDING_SKY_SH (scene passes, set 0).
// ---- IBL: environment and GGX prefilter (renderer/src/ibl/, shaders/ibl/), set 0 ------------
// equirect_to_cube.comp / .frag
#define JANUS_BINDING_EQUIRECT_PARAMS 0     // EquirectParams (face for the fallback path)
#define JANUS_BINDING_EQUIRECT_SOURCE 1     // sampler2D: equirectangular radiance (wraps in u)
#define JANUS_BINDING_EQUIRECT_CUBE 2       // compute path: rgba16f imageCube, mip 0, all faces
// ggx_prefilter.comp / .frag
#define JANUS_BINDING_PREFILTER_PARAMS 0    // PrefilterParams (face, mip, size, sample count)
#define JANUS_BINDING_PREFILTER_SAMPLES 1   // PrefilterSamples: GGX directions + source lod of one mip
#define JANUS_BINDING_PREFILTER_SOURCE 2    // samplerCube: the source cube with its mip chain
#define JANUS_BINDING_PREFILTER_TARGET 3    // compute path: rgba16f imageCube, one mip, all faces
#define JANUS_BINDING_PREFILTER_REST 4      // bright-texel variant: samplerCube, the source without its bright texels
#define JANUS_BINDING_PREFILTER_BRIGHT_LIST 5   // bright-texel variant: PrefilterBrightList, the list as a uniform block
// ggx_bright_split.comp / .frag, ggx_bright_list.comp / .frag (the bright-texel passes of the prefilter)
#define JANUS_BINDING_BRIGHT_PARAMS 0       // BrightParams (face, size, top level, capacity; threshold)
#define JANUS_BINDING_BRIGHT_SOURCE 1       // samplerCube (nearest): the source with its box-filtered chain
#define JANUS_BINDING_BRIGHT_REST 2         // list pass: samplerCube (nearest), the rest's chain (alpha: bright counts)
#define JANUS_BINDING_BRIGHT_TARGET 3       // compute path: rgba16f imageCube of the rest's mip 0 (split) | image2D 2(K + 1) x 1 list (list)


// ---- GI relight (shaders/gi/, renderer/src/gi/), set 0; also the scene-pass bindings 0 (frame
// uniforms: lights, shadow), 7-8 (local lights), 9 (shadow map), 10-12 (sky), 16-17 (the volume).
#define JANUS_BINDING_GI_TARGET 1           // compute path: rgba32f image2D brick radiance | rgba16f image3D volume
#define JANUS_BINDING_GI_SURFELS 2          // RGBA32F data texture: 4 texels per surfel (gi_relight_common.glsl)
#define JANUS_BINDING_GI_BRICKS 3           // RGBA32F: 2 texels per brick
#define JANUS_BINDING_GI_TRANSFERS 4        // RGBA32F: 3 texels per (probe, brick) SH transfer
#define JANUS_BINDING_GI_PROBES 5           // RGBA32F: per probe (grid order) its transfers, validity, relight rank; then rank -> probe
#define JANUS_BINDING_GI_BRICK_RADIANCE 6   // RGBA32F: the bricks' radiance (the SH pass reads it)
#define JANUS_BINDING_GI_RELIGHT_PARAMS 13  // GiRelightParams (gi_relight_common.glsl)
// ---- GI bake (shaders/gi/gi_gbuffer.frag): the forward pass's sets 0, 1 and 2 (frame and draw uniforms, material textures).

// ---- GI probe view (--debug gi: shaders/gi/gi_probe_view.*), set 0; also 16-17 (the volume) --
#define JANUS_BINDING_GI_PROBE_VIEW 0       // GiProbeViewUniforms: view-projection, camera, sphere radius

#endif

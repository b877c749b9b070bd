# Light culling shaders (see docs/LIGHTING.md).

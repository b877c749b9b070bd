# Directional shadow map shaders.

#version 450
// Embedded twice by CMakeLists.txt: as it is and with RED defined (janus_embed_shaders variants).
layout(location = 0) out vec4 color;

void main() {
#ifdef RED
    color = vec4(1.0, 0.0, 0.0, 1.0);
#else
    color = vec4(1.0);
#endif
}

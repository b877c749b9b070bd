#version 450
// Shadow pass: depth only. GLES and GL programs need a fragment stage, so it exists and writes nothing.
void main() {}

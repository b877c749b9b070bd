#version 450
// A fragment shader with no colour output (depth-only passes), for the validation tests.
void main() {}

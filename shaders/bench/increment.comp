#version 450
// One invocation adds 1 to the counter it is bound to. Every dispatch binds a different counter,
// so after F frames each counter holds F: the benchmark checks that, proving every dispatch ran.
layout(local_size_x = 1) in;
layout(std430, set = 0, binding = 0) buffer Counter { uint value; } counter;

void main() { counter.value += 1u; }

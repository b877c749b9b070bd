#version 450
// Every invocation writes (workgroup id, 1 + its linear index) into its own slot, so the test
// sees exactly which invocations ran and with which ids.
layout(local_size_x = 2, local_size_y = 1, local_size_z = 1) in;
layout(std430, set = 0, binding = 0) buffer Slots { uvec4 slots[]; } outSlots;

void main() {
    uvec3 size = gl_NumWorkGroups * gl_WorkGroupSize;
    uvec3 id = gl_GlobalInvocationID;
    uint index = id.x + size.x * (id.y + size.y * id.z);
    outSlots.slots[index] = uvec4(gl_WorkGroupID, 1u + index);
}

// Preloaded by scripts/sanitize.sh: keeps the Vulkan validation layer loaded until exit. The loader
// dlopens the layer for each instance and dlcloses it at vkDestroyInstance; what the layer still
// held then (see lsan.supp) becomes unreachable from a module LSan can no longer name. Opened here
// RTLD_LOCAL (no symbol of the layer interposes the loader's) and RTLD_NODELETE (never unmapped), the
// loader's own dlopen/dlclose only count references to this copy.
#include <dlfcn.h>

__attribute__((constructor)) static void keepVulkanLayersLoaded(void) {
    dlopen("libVkLayer_khronos_validation.so", RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
}

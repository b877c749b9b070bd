/* LD_PRELOAD library for tests/cli/gl_platforms.sh: makes dlopen fail for libOSMesa, as on a
 * machine where OSMesa is not installed, and lets every other library load. dlerror then reports
 * it as the dynamic loader would, so the CLI shows the message a user would see. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

static __thread const char* hiddenName;
static __thread char hiddenMessage[512];

void* dlopen(const char* file, int mode) {
    static void* (*realDlopen)(const char*, int);
    if (!realDlopen) realDlopen = (void* (*)(const char*, int))dlsym(RTLD_NEXT, "dlopen");
    if (file && strstr(file, "libOSMesa")) {
        hiddenName = file;
        return NULL;
    }
    return realDlopen(file, mode);
}

char* dlerror(void) {
    static char* (*realDlerror)(void);
    if (!realDlerror) realDlerror = (char* (*)(void))dlsym(RTLD_NEXT, "dlerror");
    if (hiddenName) {
        snprintf(hiddenMessage, sizeof hiddenMessage, "%s: cannot open shared object file: No such file or directory",
                 hiddenName);
        hiddenName = NULL;
        return hiddenMessage;
    }
    return realDlerror();
}
